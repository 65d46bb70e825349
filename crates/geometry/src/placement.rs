//! The placement of a canonical shape in the world: an affine map and its inverse.

use glam::{Affine3A, Mat3A, Vec3};
use penumbra_core::{Aabb, Ray, Transform};

/// Object-to-world and world-to-object maps of one shape, with the normal matrix.
/// Rays are mapped to object space without renormalising the direction, so the ray
/// parameter `t` is the same in both spaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    to_world: Affine3A,
    to_object: Affine3A,
    normal: Mat3A,
}

impl Placement {
    pub fn new(t: &Transform) -> Self {
        let to_world = Affine3A::from_mat4(t.m);
        let to_object = Affine3A::from_mat4(t.inv);
        Placement {
            to_world,
            to_object,
            normal: to_object.matrix3.transpose(),
        }
    }

    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.to_object.transform_point3(ray.origin),
            self.to_object.transform_vector3(ray.dir),
        )
    }

    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.to_world.transform_point3(p)
    }

    /// A world-space vector from an object-space vector.
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.to_world.transform_vector3(v)
    }

    /// A world-space unit normal from an object-space normal.
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        Vec3::from(self.normal * glam::Vec3A::from(n)).normalize()
    }

    pub fn bounds(&self, object: Aabb) -> Aabb {
        Transform {
            m: glam::Mat4::from(self.to_world),
            inv: glam::Mat4::from(self.to_object),
        }
        .bounds(object)
    }
}
