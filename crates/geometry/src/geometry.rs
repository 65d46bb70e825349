//! The scene's geometry: analytic shapes, world-space triangle meshes and mesh instances,
//! as one primitive set for the top-level accelerator.

use crate::accel::{build_accel, Accel, AccelKind, PrimitiveSet};
use crate::instance::triangle_surface;
use crate::shapes::triangle::{intersect_triangle_prepared, TriangleRay};
use crate::shapes::triangle_box::{triangle_clipped_bounds, triangle_overlaps_box};
use crate::{Hit, Instance, Shape, SurfaceHit, TriangleMesh};
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

/// One primitive of the top level.
#[derive(Clone, Copy, Debug)]
enum Prim {
    Shape(u32),
    Triangle { mesh: u32, tri: u32 },
    Instance(u32),
}

/// All primitives of a scene, each tagged with the scene object it belongs to.
#[derive(Default)]
pub struct Geometry {
    shapes: Vec<(Shape, u32)>,
    meshes: Vec<(TriangleMesh, u32)>,
    instances: Vec<(Instance, u32)>,
    prims: Vec<Prim>,
}

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
        let g = &mut self.geometry;
        let m = g.meshes.len() as u32;
        g.prims
            .extend((0..mesh.indices.len() as u32).map(|tri| Prim::Triangle { mesh: m, tri }));
        g.meshes.push((mesh, object));
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
        self.geometry
    }
}

impl Geometry {
    /// The accelerator `kind` over this geometry.
    pub fn accel(self: &Arc<Self>, kind: AccelKind) -> Box<dyn Accel> {
        build_accel(kind, self.clone())
    }

    /// Number of triangles, counting each instance's.
    pub fn triangle_count(&self) -> usize {
        let flat: usize = self.meshes.iter().map(|(m, _)| m.indices.len()).sum();
        let instanced: usize = self.instances.iter().map(|(i, _)| i.triangle_count()).sum();
        flat + instanced
    }

    /// The full surface description at `hit`, which `ray` produced.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfaceHit {
        match self.prims[hit.prim as usize] {
            Prim::Shape(s) => {
                let (shape, object) = &self.shapes[s as usize];
                let surf = shape.surface(ray, (hit.t, hit.uv));
                SurfaceHit {
                    p: surf.p,
                    ng: surf.n,
                    ns: surf.n,
                    uv: surf.uv,
                    object: *object,
                    triangle: 0,
                }
            }
            Prim::Triangle { mesh, tri } => {
                let (mesh, object) = &self.meshes[mesh as usize];
                let (p, ng, ns, uv) = triangle_surface(mesh, tri, hit.uv);
                SurfaceHit {
                    p,
                    ng,
                    ns,
                    uv,
                    object: *object,
                    triangle: tri,
                }
            }
            Prim::Instance(i) => {
                let (instance, object) = &self.instances[i as usize];
                let (p, ng, ns, uv) = instance.surface(hit.sub, hit.uv);
                SurfaceHit {
                    p,
                    ng,
                    ns,
                    uv,
                    object: *object,
                    triangle: hit.sub,
                }
            }
        }
    }
}

impl PrimitiveSet for Geometry {
    type RayData = TriangleRay;
    #[inline]
    fn prepare(&self, ray: &Ray) -> TriangleRay {
        TriangleRay::new(ray)
    }

    fn len(&self) -> usize {
        self.prims.len()
    }

    fn bounds(&self, i: u32) -> Aabb {
        match self.prims[i as usize] {
            Prim::Shape(s) => self.shapes[s as usize].0.bounds(),
            Prim::Triangle { mesh, tri } => self.meshes[mesh as usize].0.triangle_bounds(tri as usize),
            Prim::Instance(k) => self.instances[k as usize].0.bounds(),
        }
    }

    #[inline]
    fn intersect(&self, i: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        match self.prims[i as usize] {
            Prim::Shape(s) => {
                self.shapes[s as usize]
                    .0
                    .intersect(ray, t_max)
                    .map(|(t, uv)| Hit { t, prim: i, sub: 0, uv })
            }
            Prim::Triangle { mesh, tri } => {
                let p = self.meshes[mesh as usize].0.vertices(tri as usize);
                intersect_triangle_prepared(data, p, t_max).map(|(t, uv)| Hit { t, prim: i, sub: 0, uv })
            }
            Prim::Instance(k) => self.instances[k as usize].0.intersect(ray, t_max).map(|h| Hit {
                t: h.t,
                prim: i,
                sub: h.prim,
                uv: h.uv,
            }),
        }
    }

    fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        match self.prims[i as usize] {
            Prim::Triangle { mesh, tri } => {
                triangle_overlaps_box(self.meshes[mesh as usize].0.vertices(tri as usize), b)
            }
            _ => self.bounds(i).overlaps(b),
        }
    }

    /// The primitive table, the analytic shapes, and the meshes' positions and indices
    /// (what intersection reads; shading data and instanced meshes are not counted).
    fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let meshes: usize = self
            .meshes
            .iter()
            .map(|(m, _)| {
                m.positions.capacity() * size_of::<glam::Vec3>() + m.indices.capacity() * size_of::<[u32; 3]>()
            })
            .sum();
        self.prims.capacity() * size_of::<Prim>()
            + self.shapes.capacity() * size_of::<(Shape, u32)>()
            + self.instances.capacity() * size_of::<(Instance, u32)>()
            + meshes
    }

    fn clip_bounds(&self, i: u32, b: &Aabb) -> Aabb {
        match self.prims[i as usize] {
            Prim::Triangle { mesh, tri } => {
                triangle_clipped_bounds(self.meshes[mesh as usize].0.vertices(tri as usize), b)
            }
            _ => self.bounds(i).intersection(*b),
        }
    }

    fn occluded(&self, i: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> bool {
        match self.prims[i as usize] {
            Prim::Instance(k) => self.instances[k as usize].0.occluded(ray, t_max),
            _ => self.intersect(i, ray, data, t_max).is_some(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AccelKind, MeshAccel};
    use glam::Vec3;
    use penumbra_core::Transform;

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
