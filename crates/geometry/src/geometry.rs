//! The scene's geometry: analytic shapes, world-space triangle meshes and mesh instances.
//!
//! The triangles of all world-space meshes are pooled into one [`MeshTriangles`] set, so
//! that an accelerator over them stores them in SIMD packets of four in leaf order; the
//! shapes and instances form a second set (the [`PrimitiveSet`] of `Geometry` itself). A
//! scene's accelerator ([`Geometry::accel`]) answers for both: one structure of the chosen
//! kind over each, the closer hit winning; or, when the triangles are a handful beside
//! shapes (a ground quad under spheres), one structure over the shapes' set with the
//! triangles in it, so that a ray walks one structure, not two.

use crate::accel::{build_accel, closest_of_two, occluded_by_either, Accel, AccelKind, TraversalStats, PAD};
use crate::instance::{triangle_surface, MeshTriangles};
use crate::object_set::ObjectSet;
use crate::shapes::triangle::{intersect_triangle_prepared, TriangleRay};
use crate::shapes::triangle_box::{triangle_clipped_bounds, triangle_overlaps_box};
use crate::{Hit, Instance, Shape, SurfaceHit, TriangleMesh};
use glam::Vec3;
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

/// One shape or instance.
#[derive(Clone, Copy, Debug)]
enum Prim {
    Shape(u32),
    Instance(u32),
}

/// What a slot of [`ObjectSet`]'s packets holds.
pub(crate) enum PacketPrim {
    Pad,
    Sphere(Vec3, f32),
    Triangle([Vec3; 3]),
    Other,
}

/// All primitives of a scene, each tagged with the scene object it belongs to.
#[derive(Default)]
pub struct Geometry {
    shapes: Vec<(Shape, u32)>,
    meshes: Vec<(TriangleMesh, u32)>,
    instances: Vec<(Instance, u32)>,
    prims: Vec<Prim>,
    /// The positions and triangles of every mesh in `meshes`, one after the other.
    pooled: Arc<TriangleMesh>,
    /// The first pooled triangle of each mesh.
    pooled_starts: Vec<u32>,
    /// The mesh of each pooled triangle, when there is more than one mesh: a lookup per
    /// hit instead of a binary search over `pooled_starts`, whose unpredictable branches
    /// cost more than the 4 bytes per triangle.
    pooled_mesh: Vec<u32>,
    /// The pooled triangles are few ([`INLINE_TRIANGLES`] or fewer) beside shapes or
    /// instances: they join the shapes' set, so that a ray walks one structure, not two.
    inline_triangles: bool,
}

/// Most pooled triangles that join the shapes' set (a ground quad, a few light quads)
/// rather than getting a structure of their own, which every ray would walk as well.
const INLINE_TRIANGLES: usize = 16;

/// Collects shapes, meshes and instances, numbering them as scene objects in order.
#[derive(Default)]
pub struct GeometryBuilder {
    geometry: Geometry,
    objects: u32,
}

impl GeometryBuilder {
    pub fn new() -> Self {
        Self::default()
    }

    fn next_object(&mut self) -> u32 {
        self.objects += 1;
        self.objects - 1
    }

    /// Adds a shape; returns its object number.
    pub fn add_shape(&mut self, shape: Shape) -> u32 {
        let object = self.next_object();
        let g = &mut self.geometry;
        g.prims.push(Prim::Shape(g.shapes.len() as u32));
        g.shapes.push((shape, object));
        object
    }

    /// Adds a world-space mesh whose triangles become top-level primitives.
    pub fn add_mesh(&mut self, mesh: TriangleMesh) -> u32 {
        let object = self.next_object();
        self.geometry.meshes.push((mesh, object));
        object
    }

    /// Adds an instance of a shared mesh.
    pub fn add_instance(&mut self, instance: Instance) -> u32 {
        let object = self.next_object();
        let g = &mut self.geometry;
        g.prims.push(Prim::Instance(g.instances.len() as u32));
        g.instances.push((instance, object));
        object
    }

    pub fn build(self) -> Geometry {
        let mut g = self.geometry;
        let mut pooled = TriangleMesh::default();
        for (mesh, _) in &g.meshes {
            g.pooled_starts.push(pooled.indices.len() as u32);
            let base = pooled.positions.len() as u32;
            pooled.positions.extend_from_slice(&mesh.positions);
            pooled.indices.extend(mesh.indices.iter().map(|t| t.map(|i| i + base)));
        }
        if g.meshes.len() > 1 {
            g.pooled_mesh = g
                .meshes
                .iter()
                .enumerate()
                .flat_map(|(k, (mesh, _))| std::iter::repeat_n(k as u32, mesh.indices.len()))
                .collect();
        }
        g.inline_triangles = !g.prims.is_empty() && (1..=INLINE_TRIANGLES).contains(&pooled.indices.len());
        g.pooled = Arc::new(pooled);
        g
    }
}

impl Geometry {
    /// The accelerator `kind` over this geometry. Hits on pooled triangles carry
    /// `prim = shapes and instances + pooled triangle`.
    pub fn accel(self: &Arc<Self>, kind: AccelKind) -> Box<dyn Accel> {
        if self.inline_triangles {
            return build_accel(kind, Arc::new(ObjectSet::new(self.clone())));
        }
        let triangles = (!self.pooled.indices.is_empty())
            .then(|| build_accel(kind, Arc::new(MeshTriangles::new(self.pooled.clone()))));
        let objects = (!self.prims.is_empty() || triangles.is_none())
            .then(|| build_accel(kind, Arc::new(ObjectSet::new(self.clone()))));
        match (triangles, objects) {
            // Only triangles, numbered from 0: their structure answers alone.
            (Some(triangles), None) => triangles,
            (Some(triangles), Some(objects)) => Box::new(Split {
                triangles,
                objects,
                first_triangle: self.prims.len() as u32,
            }),
            (None, Some(objects)) => objects,
            (None, None) => unreachable!("an accelerator is built for the objects when there are no triangles"),
        }
    }

    /// Shapes, instances and world-space triangles.
    pub fn primitive_count(&self) -> usize {
        self.prims.len() + self.pooled.indices.len()
    }

    /// Bounds of the finite part of the scene (infinite planes left out).
    pub fn finite_bounds(&self) -> Aabb {
        let objects = (0..self.prims.len() as u32).map(|i| self.bounds(i));
        objects
            .chain(std::iter::once(Aabb::from_points(
                self.pooled.positions.iter().copied(),
            )))
            .filter(|b| b.is_finite())
            .fold(Aabb::EMPTY, |a, b| a.union(b))
    }

    /// Number of triangles, counting each instance's.
    pub fn triangle_count(&self) -> usize {
        let flat: usize = self.meshes.iter().map(|(m, _)| m.indices.len()).sum();
        let instanced: usize = self.instances.iter().map(|(i, _)| i.triangle_count()).sum();
        flat + instanced
    }

    /// For a hit on a world-space mesh's triangle: the mesh, the triangle within it and
    /// the mesh's object number.
    pub fn pooled_hit(&self, hit: &Hit) -> Option<(&TriangleMesh, u32, u32)> {
        let (mesh, triangle) = self.pooled_index(hit)?;
        let (m, object) = &self.meshes[mesh];
        Some((m, triangle, *object))
    }

    /// For a hit on a world-space mesh's triangle: the mesh's number among
    /// [`Geometry::meshes`] and the triangle within it.
    #[inline]
    pub fn pooled_index(&self, hit: &Hit) -> Option<(usize, u32)> {
        let pooled = hit.prim.checked_sub(self.prims.len() as u32)?;
        let mesh = self.pooled_mesh.get(pooled as usize).map_or(0, |&m| m as usize);
        Some((mesh, pooled - self.pooled_starts[mesh]))
    }

    /// The world-space meshes, each with its object number, in the numbering of
    /// [`Geometry::pooled_index`].
    pub fn meshes(&self) -> &[(TriangleMesh, u32)] {
        &self.meshes
    }

    /// What primitive `i` of the set is to the packets of [`ObjectSet`]: a round sphere
    /// (world centre and radius), a triangle, or a kind tested one by one.
    pub(crate) fn packet_prim(&self, i: u32) -> PacketPrim {
        if i == PAD {
            return PacketPrim::Pad;
        }
        if let Some(tri) = self.inline_triangle(i) {
            return PacketPrim::Triangle(tri);
        }
        match self.prims[i as usize] {
            Prim::Shape(s) => match &self.shapes[s as usize].0 {
                Shape::Sphere(sphere) => sphere
                    .world_round()
                    .map_or(PacketPrim::Other, |(centre, radius)| PacketPrim::Sphere(centre, radius)),
                _ => PacketPrim::Other,
            },
            Prim::Instance(_) => PacketPrim::Other,
        }
    }

    /// Pooled triangle `i - prims.len()` of the set's primitive `i`, for a set with its
    /// triangles inline.
    #[inline]
    fn inline_triangle(&self, i: u32) -> Option<[Vec3; 3]> {
        let t = (i as usize).checked_sub(self.prims.len())?;
        Some(self.pooled.vertices(t))
    }

    /// The full surface description at `hit`, which `ray` produced.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfaceHit {
        let Some(&prim) = self.prims.get(hit.prim as usize) else {
            let (mesh, tri, object) = self.pooled_hit(hit).expect("a hit on a pooled triangle");
            let (p, ng, ns, uv, dpdu) = triangle_surface(mesh, tri, hit.uv);
            return SurfaceHit {
                p,
                ng,
                ns,
                uv,
                dpdu,
                object,
                triangle: tri,
            };
        };
        match prim {
            Prim::Shape(s) => {
                let (shape, object) = &self.shapes[s as usize];
                let surf = shape.surface(ray, (hit.t, hit.uv));
                SurfaceHit {
                    p: surf.p,
                    ng: surf.n,
                    ns: surf.n,
                    uv: surf.uv,
                    dpdu: surf.dpdu,
                    object: *object,
                    triangle: 0,
                }
            }
            Prim::Instance(i) => {
                let (instance, object) = &self.instances[i as usize];
                let (p, ng, ns, uv, dpdu) = instance.surface(hit.sub, hit.uv);
                SurfaceHit {
                    p,
                    ng,
                    ns,
                    uv,
                    dpdu,
                    object: *object,
                    triangle: hit.sub,
                }
            }
        }
    }
}

/// Primitive `i` of the shapes' set: the shapes and instances, numbered as in hits; the
/// pooled triangles after them when they are inline (else they have their own set). What
/// [`ObjectSet`], the set's [`PrimitiveSet`](crate::accel::PrimitiveSet), asks of each
/// primitive.
impl Geometry {
    pub(crate) fn len(&self) -> usize {
        self.prims.len()
            + if self.inline_triangles {
                self.pooled.indices.len()
            } else {
                0
            }
    }

    pub(crate) fn bounds(&self, i: u32) -> Aabb {
        if let Some(tri) = self.inline_triangle(i) {
            return Aabb::from_points(tri);
        }
        match self.prims[i as usize] {
            Prim::Shape(s) => self.shapes[s as usize].0.bounds(),
            Prim::Instance(k) => self.instances[k as usize].0.bounds(),
        }
    }

    pub(crate) fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        match self.inline_triangle(i) {
            Some(tri) => triangle_overlaps_box(tri, b),
            None => self.bounds(i).overlaps(b),
        }
    }

    pub(crate) fn clip_bounds(&self, i: u32, b: &Aabb) -> Aabb {
        match self.inline_triangle(i) {
            Some(tri) => triangle_clipped_bounds(tri, b),
            None => self.bounds(i).intersection(*b),
        }
    }

    #[inline]
    pub(crate) fn intersect(&self, i: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        if let Some(tri) = self.inline_triangle(i) {
            // The test the triangles' own set makes (`Triangle4` gives these bits).
            return intersect_triangle_prepared(data, tri, t_max).map(|(t, uv)| Hit { t, prim: i, sub: 0, uv });
        }
        match self.prims[i as usize] {
            Prim::Shape(s) => {
                self.shapes[s as usize]
                    .0
                    .intersect(ray, t_max)
                    .map(|(t, uv)| Hit { t, prim: i, sub: 0, uv })
            }
            Prim::Instance(k) => self.instances[k as usize].0.intersect(ray, t_max).map(|h| Hit {
                t: h.t,
                prim: i,
                sub: h.prim,
                uv: h.uv,
            }),
        }
    }

    /// The primitive table, the analytic shapes, the instances (instanced meshes are
    /// not counted) and the pooled triangles' mesh numbers.
    pub(crate) fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.pooled_mesh.capacity() * size_of::<u32>()
            + self.prims.capacity() * size_of::<Prim>()
            + self.shapes.capacity() * size_of::<(Shape, u32)>()
            + self.instances.capacity() * size_of::<(Instance, u32)>()
    }

    pub(crate) fn occluded(&self, i: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> bool {
        if i as usize >= self.prims.len() {
            return self.intersect(i, ray, data, t_max).is_some();
        }
        match self.prims[i as usize] {
            Prim::Instance(k) => self.instances[k as usize].0.occluded(ray, t_max),
            _ => self.intersect(i, ray, data, t_max).is_some(),
        }
    }
}

/// The scene's accelerator when it has both: one structure over the pooled triangles, one
/// over the shapes and instances.
struct Split {
    triangles: Box<dyn Accel>,
    objects: Box<dyn Accel>,
    /// What pooled triangle numbers are offset by in hits.
    first_triangle: u32,
}

impl Split {
    #[inline]
    fn renumber(&self, hit: Hit) -> Hit {
        Hit {
            prim: hit.prim + self.first_triangle,
            ..hit
        }
    }
}

impl Accel for Split {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let near = self.triangles.intersect(ray, t_max).map(|h| self.renumber(h));
        self.objects.intersect(ray, near.map_or(t_max, |h| h.t)).or(near)
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.triangles.occluded(ray, t_max) || self.objects.occluded(ray, t_max)
    }
    fn bounds(&self) -> Aabb {
        self.triangles.bounds().union(self.objects.bounds())
    }
    fn intersect_counted(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        let near = self
            .triangles
            .intersect_counted(ray, t_max, stats)
            .map(|h| self.renumber(h));
        self.objects
            .intersect_counted(ray, near.map_or(t_max, |h| h.t), stats)
            .or(near)
    }
    fn memory_bytes(&self) -> usize {
        self.triangles.memory_bytes() + self.objects.memory_bytes()
    }
    fn primitive_bytes(&self) -> usize {
        self.triangles.primitive_bytes() + self.objects.primitive_bytes()
    }
    fn intersect_batch(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        closest_of_two(
            &*self.triangles,
            &*self.objects,
            |h| self.renumber(h),
            (rays, false),
            hits,
        );
    }
    fn intersect_coherent(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        closest_of_two(
            &*self.triangles,
            &*self.objects,
            |h| self.renumber(h),
            (rays, true),
            hits,
        );
    }
    fn occluded_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
        occluded_by_either(&*self.triangles, &*self.objects, rays, blocked);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AccelKind, MeshAccel};
    use glam::Vec3;
    use penumbra_core::Transform;

    /// Hits on pooled triangles name the mesh (object) and the triangle within it, for
    /// meshes of different sizes side by side, and for a single mesh.
    #[test]
    fn pooled_hits_name_their_mesh_and_triangle() {
        let strip = |n: usize, x: f32| TriangleMesh {
            positions: (0..n)
                .flat_map(|k| {
                    let z = -(k as f32);
                    [Vec3::new(x, 0.0, z), Vec3::new(x + 0.9, 0.0, z), Vec3::new(x, 0.9, z)]
                })
                .collect(),
            indices: (0..n as u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect(),
            ..Default::default()
        };
        for sizes in [&[3usize, 1, 5][..], &[4]] {
            let mut b = GeometryBuilder::new();
            for (m, &n) in sizes.iter().enumerate() {
                b.add_mesh(strip(n, 2.0 * m as f32));
            }
            let g = Arc::new(b.build());
            let accel = g.accel(AccelKind::Bvh);
            for (m, &n) in sizes.iter().enumerate() {
                for k in 0..n {
                    let ray = Ray::new(Vec3::new(2.0 * m as f32 + 0.2, 0.2, 0.5 - k as f32), Vec3::NEG_Z);
                    let hit = accel.intersect(&ray, 0.9).unwrap();
                    let s = g.surface(&ray, &hit);
                    assert_eq!((s.object, s.triangle), (m as u32, k as u32), "mesh {m}, triangle {k}");
                }
            }
        }
    }

    /// A handful of triangles beside shapes join the shapes' structure: every kind of
    /// accelerator gives the hits (primitive, distance and barycentrics, bit for bit) and
    /// shadow answers of the two structures, for a ground quad of two triangles under
    /// spheres and a few more triangles, rays from everywhere.
    #[test]
    fn inline_triangles_answer_as_their_own_structure_would() {
        use crate::shapes::Sphere;
        use penumbra_core::Pcg32;
        let build = |inline: bool| {
            let mut b = GeometryBuilder::new();
            for k in 0..3 {
                let c = Vec3::new(k as f32 * 2.0 - 2.0, 1.0, 0.0);
                b.add_shape(Shape::Sphere(Sphere::new(c, 0.9, &Transform::IDENTITY).unwrap()));
            }
            b.add_mesh(TriangleMesh {
                positions: vec![
                    Vec3::new(-5.0, 0.0, -5.0),
                    Vec3::new(5.0, 0.0, -5.0),
                    Vec3::new(5.0, 0.0, 5.0),
                    Vec3::new(-5.0, 0.0, 5.0),
                ],
                indices: vec![[0, 1, 2], [0, 2, 3]],
                ..Default::default()
            });
            b.add_mesh(TriangleMesh {
                positions: vec![
                    Vec3::new(0.0, 2.5, 0.0),
                    Vec3::new(1.0, 2.5, 0.5),
                    Vec3::new(0.0, 3.0, 1.0),
                ],
                indices: vec![[0, 1, 2]],
                ..Default::default()
            });
            let mut g = b.build();
            assert!(g.inline_triangles, "three triangles beside shapes go inline");
            g.inline_triangles = inline;
            Arc::new(g)
        };
        let (inline, split) = (build(true), build(false));
        let mut rng = Pcg32::new(5, 9);
        let mut point = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 12.0 - Vec3::splat(6.0);
        for kind in AccelKind::ALL {
            let (a, b) = (inline.accel(kind), split.accel(kind));
            let mut hits = 0;
            for round in 0..2_000 {
                let (o, target) = (point(), point());
                let ray = Ray::new(o, target - o);
                let t_max = if round % 3 == 0 { 5.0 } else { f32::INFINITY };
                assert_eq!(a.intersect(&ray, t_max), b.intersect(&ray, t_max), "{kind:?} {ray:?}");
                assert_eq!(a.occluded(&ray, t_max), b.occluded(&ray, t_max), "{kind:?} {ray:?}");
                hits += a.intersect(&ray, t_max).is_some() as usize;
            }
            assert!(hits > 500, "{kind:?}: only {hits} hits");
        }
    }

    #[test]
    fn mirrored_instances_and_meshes_keep_their_outside() {
        // One triangle facing +z, mirrored in x: as a flattened mesh and as an instance, the
        // geometric normal must still face +z.
        let tri = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 2]],
            ..Default::default()
        };
        let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
        let mut b = GeometryBuilder::new();
        b.add_mesh(tri.transformed(&mirror));
        let shared = Arc::new(MeshAccel::new(Arc::new(tri), AccelKind::Bvh));
        b.add_instance(Instance::new(
            shared,
            &mirror.then(Transform::translate(Vec3::new(0.0, 0.0, -1.0))),
        ));
        let g = Arc::new(b.build());
        let accel = g.accel(AccelKind::List);
        for z in [0.0, -1.0] {
            let ray = Ray::new(Vec3::new(-0.25, 0.25, z + 1.0), Vec3::NEG_Z);
            let hit = accel.intersect(&ray, 1.5).unwrap();
            let s = g.surface(&ray, &hit);
            assert!((s.ng - Vec3::Z).length() < 1e-6, "object {}: ng {}", s.object, s.ng);
            assert!((s.p - Vec3::new(-0.25, 0.25, z)).length() < 1e-6);
        }
    }
}
