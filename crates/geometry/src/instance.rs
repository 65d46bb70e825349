//! Instancing: one mesh with its own accelerator, placed any number of times under
//! different transforms without copying its triangles.

use crate::accel::{build_accel, Accel, AccelKind, PrimitiveSet};
use crate::shapes::triangle::{intersect_triangle_prepared, TriangleRay};
use crate::shapes::triangle_box::triangle_overlaps_box;
use crate::{Hit, Placement, TriangleMesh};
use glam::{Vec2, Vec3};
use penumbra_core::{Aabb, Ray, Transform};
use std::sync::Arc;

/// The triangles of one mesh as a primitive set, their vertices stored contiguously so
/// that a test touches one cache line instead of chasing indices.
pub struct MeshTriangles {
    pub mesh: Arc<TriangleMesh>,
    triangles: Vec<[Vec3; 3]>,
}

impl MeshTriangles {
    pub fn new(mesh: Arc<TriangleMesh>) -> Self {
        let triangles = (0..mesh.indices.len()).map(|i| mesh.vertices(i)).collect();
        MeshTriangles { mesh, triangles }
    }

    /// Bytes held beside the mesh itself.
    pub fn memory_bytes(&self) -> usize {
        self.triangles.capacity() * std::mem::size_of::<[Vec3; 3]>()
    }
}

impl PrimitiveSet for MeshTriangles {
    type RayData = TriangleRay;
    #[inline]
    fn prepare(&self, ray: &Ray) -> TriangleRay {
        TriangleRay::new(ray)
    }
    fn len(&self) -> usize {
        self.triangles.len()
    }
    fn bounds(&self, i: u32) -> Aabb {
        Aabb::from_points(self.triangles[i as usize])
    }
    fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        triangle_overlaps_box(self.triangles[i as usize], b)
    }
    #[inline]
    fn intersect(&self, i: u32, _ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        intersect_triangle_prepared(data, self.triangles[i as usize], t_max).map(|(t, uv)| Hit {
            t,
            prim: i,
            sub: 0,
            uv,
        })
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

    /// World-space position, geometric and shading normals and texture coordinates.
    pub fn surface(&self, tri: u32, b: Vec2) -> (Vec3, Vec3, Vec3, Vec2) {
        let (p, ng, ns, uv) = triangle_surface(&self.mesh.mesh, tri, b);
        // The inverse transpose keeps normals on the same side, mirrors included.
        let ng = self.placement.normal_to_world(ng);
        let ns = self.placement.normal_to_world(ns);
        let ns = if ns.dot(ng) < 0.0 { -ns } else { ns };
        (self.placement.point_to_world(p), ng, ns, uv)
    }
}

/// The surface of triangle `tri` at barycentrics `b = (b1, b2)`: position, geometric
/// normal (flipped to the side of the shading normal when the mesh has normals), shading
/// normal and texture coordinates (the barycentrics when the mesh has none).
pub(crate) fn triangle_surface(mesh: &TriangleMesh, tri: u32, b: Vec2) -> (Vec3, Vec3, Vec3, Vec2) {
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
    let uv = match &mesh.uvs {
        Some(uvs) => b0 * uvs[idx[0] as usize] + b.x * uvs[idx[1] as usize] + b.y * uvs[idx[2] as usize],
        None => b,
    };
    (p, ng, ns, uv)
}
