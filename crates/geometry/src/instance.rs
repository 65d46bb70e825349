//! Instancing: one mesh with its own accelerator, placed any number of times under
//! different transforms without copying its triangles.

use crate::accel::{build_accel, packets_of, Accel, AccelKind, PrimitiveSet, RayPacket, PACKET, PAD};
use crate::shapes::triangle::{dominant_axis, intersect_triangle_prepared, TriangleRay};
use crate::shapes::triangle4::{Triangle4, TriangleRays};
use crate::shapes::triangle_box::{triangle_clipped_bounds, triangle_overlaps_box};
use crate::{Hit, Placement, TriangleMesh};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::Lane8;
use penumbra_core::{Aabb, Ray, Transform};
use rayon::prelude::*;
use std::sync::Arc;

/// The triangles of one mesh as a primitive set, their vertices stored in packets of four
/// (one SIMD lane each) so that a test touches adjacent memory instead of chasing indices,
/// and an accelerator's leaf of up to four triangles is tested at once.
pub struct MeshTriangles {
    pub mesh: Arc<TriangleMesh>,
    /// Triangle `i` is lane `i % 4` of packet `i / 4`.
    packets: Vec<Triangle4>,
    /// Number of triangle slots (empty ones included in a reordered set).
    len: usize,
    /// The mesh's number for each slot once reordered ([`PAD`] for an empty one); empty while
    /// the triangles are in the mesh's order.
    ids: Vec<u32>,
}

impl MeshTriangles {
    pub fn new(mesh: Arc<TriangleMesh>) -> Self {
        let triangles: Vec<[Vec3; 3]> = (0..mesh.indices.len()).map(|i| mesh.vertices(i)).collect();
        MeshTriangles {
            packets: triangles.chunks(4).map(Triangle4::pack).collect(),
            len: triangles.len(),
            mesh,
            ids: Vec::new(),
        }
    }

    /// The mesh's number for slot `i`.
    #[inline]
    fn id(&self, i: u32) -> u32 {
        if self.ids.is_empty() {
            i
        } else {
            self.ids[i as usize]
        }
    }

    #[inline]
    fn triangle(&self, i: u32) -> [Vec3; 3] {
        self.packets[i as usize / 4].get(i as usize % 4)
    }
}

impl PrimitiveSet for MeshTriangles {
    type RayData = TriangleRay;
    type PacketData = TriangleRays;
    #[inline]
    fn prepare(&self, ray: &Ray) -> TriangleRay {
        TriangleRay::new(ray)
    }
    fn len(&self) -> usize {
        self.len
    }
    fn bounds(&self, i: u32) -> Aabb {
        if self.id(i) == PAD {
            return Aabb::EMPTY;
        }
        Aabb::from_points(self.triangle(i))
    }
    fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        self.id(i) != PAD && triangle_overlaps_box(self.triangle(i), b)
    }
    fn clip_bounds(&self, i: u32, b: &Aabb) -> Aabb {
        if self.id(i) == PAD {
            return Aabb::EMPTY;
        }
        triangle_clipped_bounds(self.triangle(i), b)
    }
    #[inline]
    fn intersect(&self, i: u32, _ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        intersect_triangle_prepared(data, self.triangle(i), t_max).map(|(t, uv)| Hit {
            t,
            prim: self.id(i),
            sub: 0,
            uv,
        })
    }
    #[inline(always)]
    fn intersect_run(&self, first: usize, count: usize, _ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        let mut t_max = t_max;
        let mut closest = None;
        for (packet, lanes) in packets_of(first, count) {
            if let Some((lane, t, uv)) = self.packets[packet].closest(data, t_max, lanes) {
                t_max = t;
                closest = Some(Hit {
                    t,
                    prim: self.id((packet * 4 + lane) as u32),
                    sub: 0,
                    uv,
                });
            }
        }
        closest
    }
    #[inline(always)]
    fn occluded_run(&self, first: usize, count: usize, _ray: &Ray, data: &TriangleRay, t_max: f32) -> bool {
        // A loop, not `Iterator::any`: its `try_fold` was not inlined into the traversal.
        for (packet, lanes) in packets_of(first, count) {
            if self.packets[packet].any(data, t_max, lanes) {
                return true;
            }
        }
        false
    }
    fn group(&self) -> usize {
        4
    }
    fn packet_class(&self, ray: &Ray) -> usize {
        dominant_axis(ray.dir)
    }
    fn prepare_packet(&self, p: &RayPacket<TriangleRay>) -> Option<TriangleRays> {
        TriangleRays::new(&p.data)
    }
    #[inline(always)]
    fn intersect_run_packet<L: Lane8>(
        &self,
        first: usize,
        count: usize,
        p: &RayPacket<TriangleRay>,
        rays: &TriangleRays,
        lanes: u32,
        (t_max, hits): (&mut [f32; PACKET], &mut [Option<Hit>; PACKET]),
    ) {
        for (packet, tris) in packets_of(first, count) {
            if let Some(h) = self.packets[packet].closest_rays::<L>(rays, &p.data, (tris, lanes), t_max) {
                h.write(t_max, hits, |k| self.id((packet * 4 + k) as u32));
            }
        }
    }
    fn reordered(&self, order: &[u32]) -> Option<Self> {
        let packets = order
            .par_chunks(4)
            .map(|slots| {
                let mut packet = Triangle4::EMPTY;
                for (lane, &i) in slots.iter().enumerate() {
                    if i != PAD {
                        packet.set(lane, self.triangle(i));
                    }
                }
                packet
            })
            .collect();
        Some(MeshTriangles {
            mesh: self.mesh.clone(),
            packets,
            len: order.len(),
            ids: order.iter().map(|&i| if i == PAD { PAD } else { self.id(i) }).collect(),
        })
    }
    /// The packed vertices and the slots' numbers (the mesh itself is counted apart).
    fn memory_bytes(&self) -> usize {
        self.packets.capacity() * std::mem::size_of::<Triangle4>() + self.ids.capacity() * 4
    }
}

/// A mesh in its own space together with its accelerator: what instances share.
pub struct MeshAccel {
    pub mesh: Arc<TriangleMesh>,
    accel: Box<dyn Accel>,
}

impl MeshAccel {
    pub fn new(mesh: Arc<TriangleMesh>, kind: AccelKind) -> Self {
        let accel = build_accel(kind, Arc::new(MeshTriangles::new(mesh.clone())));
        MeshAccel { mesh, accel }
    }
}

/// A placed copy of a shared mesh.
pub struct Instance {
    mesh: Arc<MeshAccel>,
    placement: Placement,
    bounds: Aabb,
}

impl Instance {
    pub fn new(mesh: Arc<MeshAccel>, to_world: &Transform) -> Self {
        let placement = Placement::new(to_world);
        let bounds = placement.bounds(mesh.accel.bounds());
        Instance {
            mesh,
            placement,
            bounds,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    pub fn triangle_count(&self) -> usize {
        self.mesh.mesh.indices.len()
    }

    /// The closest hit, with the triangle in `Hit::prim`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.mesh.accel.intersect(&self.placement.ray_to_object(ray), t_max)
    }

    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.mesh.accel.occluded(&self.placement.ray_to_object(ray), t_max)
    }

    /// World-space position, geometric and shading normals, texture coordinates and ∂p/∂u.
    pub fn surface(&self, tri: u32, b: Vec2) -> (Vec3, Vec3, Vec3, Vec2, Vec3) {
        let (p, ng, ns, uv, dpdu) = triangle_surface(&self.mesh.mesh, tri, b);
        // The inverse transpose keeps normals on the same side, mirrors included.
        let ng = self.placement.normal_to_world(ng);
        let ns = self.placement.normal_to_world(ns);
        let ns = if ns.dot(ng) < 0.0 { -ns } else { ns };
        (
            self.placement.point_to_world(p),
            ng,
            ns,
            uv,
            self.placement.vector_to_world(dpdu),
        )
    }
}

/// The surface of triangle `tri` at barycentrics `b = (b1, b2)`: position, geometric
/// normal (flipped to the side of the shading normal when the mesh has normals), shading
/// normal, texture coordinates (the barycentrics when the mesh has none) and ∂p/∂u (from
/// the texture coordinates, pbrt-v4 eq. 6.7; the first edge when they are degenerate).
pub(crate) fn triangle_surface(mesh: &TriangleMesh, tri: u32, b: Vec2) -> (Vec3, Vec3, Vec3, Vec2, Vec3) {
    let idx = mesh.indices[tri as usize];
    let [p0, p1, p2] = mesh.vertices(tri as usize);
    let b0 = 1.0 - b.x - b.y;
    let p = b0 * p0 + b.x * p1 + b.y * p2;
    let mut ng = (p1 - p0).cross(p2 - p0).normalize();
    let ns = match &mesh.normals {
        Some(normals) => {
            let n = b0 * normals[idx[0] as usize] + b.x * normals[idx[1] as usize] + b.y * normals[idx[2] as usize];
            match n.try_normalize() {
                Some(n) => {
                    if n.dot(ng) < 0.0 {
                        ng = -ng;
                    }
                    n
                }
                None => ng,
            }
        }
        None => ng,
    };
    let (uv, dpdu) = match &mesh.uvs {
        Some(uvs) => {
            let [t0, t1, t2] = idx.map(|i| uvs[i as usize]);
            let (d1, d2) = (t1 - t0, t2 - t0);
            let det = d1.x * d2.y - d1.y * d2.x;
            let dpdu = if det.abs() > 1e-12 {
                ((p1 - p0) * d2.y - (p2 - p0) * d1.y) / det
            } else {
                p1 - p0
            };
            (b0 * t0 + b.x * t1 + b.y * t2, dpdu)
        }
        None => (b, p1 - p0),
    };
    (p, ng, ns, uv, dpdu)
}
