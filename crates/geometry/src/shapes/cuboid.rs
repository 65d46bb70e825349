//! The box: an axis-aligned box in object space, placed by any affine transform. Hit by
//! the slab test; the face is the one whose slab the hit lies on.

use super::{ShapeHit, ShapeSurface};
use crate::Placement;
use glam::{Vec2, Vec3};
use penumbra_core::{Aabb, Ray, Transform};

#[derive(Clone, Debug, PartialEq)]
pub struct Cuboid {
    local: Aabb,
    placement: Placement,
}

impl Cuboid {
    /// `None` if the box has no volume.
    pub fn new(min: Vec3, max: Vec3, to_world: &Transform) -> Option<Self> {
        let local = Aabb::new(min, max);
        (local.extent().cmpgt(Vec3::ZERO).all()).then(|| Cuboid {
            local,
            placement: Placement::new(to_world),
        })
    }

    pub fn bounds(&self) -> Aabb {
        self.placement.bounds(self.local)
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let r = self.placement.ray_to_object(ray);
        let inv = r.dir.recip();
        let t0 = (self.local.min - r.origin) * inv;
        let t1 = (self.local.max - r.origin) * inv;
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element();
        if near > far {
            return None;
        }
        let t = if near > 0.0 { near } else { far };
        (t > 0.0 && t < t_max).then_some((t, Vec2::ZERO))
    }

    pub fn surface(&self, ray: &Ray, (t, _): ShapeHit) -> ShapeSurface {
        let local = self.placement.ray_to_object(ray).at(t);
        // The face is the axis along which the point is furthest out, relative to the half size.
        let half = 0.5 * self.local.extent();
        let d = (local - self.local.centroid()) / half;
        let axis = d.abs().max_position();
        let mut n = Vec3::ZERO;
        n[axis] = d[axis].signum();
        let rel = self.local.offset(local);
        let uv = match axis {
            0 => Vec2::new(rel.z, rel.y),
            1 => Vec2::new(rel.x, rel.z),
            _ => Vec2::new(rel.x, rel.y),
        };
        let mut p = local;
        p[axis] = if n[axis] > 0.0 {
            self.local.max[axis]
        } else {
            self.local.min[axis]
        };
        // u runs along z on the x faces, along x on the others.
        let du = if axis == 0 { Vec3::Z } else { Vec3::X };
        ShapeSurface {
            p: self.placement.point_to_world(p),
            n: self.placement.normal_to_world(n),
            uv,
            dpdu: self.placement.vector_to_world(du),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_and_inside() {
        let b = Cuboid::new(Vec3::splat(-1.0), Vec3::ONE, &Transform::IDENTITY).unwrap();
        let ray = Ray::new(Vec3::new(0.2, 5.0, 0.3), Vec3::NEG_Y);
        let hit = b.intersect(&ray, f32::INFINITY).unwrap();
        assert_eq!(hit.0, 4.0);
        assert_eq!(b.surface(&ray, hit).n, Vec3::Y);
        let inside = Ray::new(Vec3::ZERO, Vec3::X);
        let hit = b.intersect(&inside, f32::INFINITY).unwrap();
        assert_eq!(hit.0, 1.0);
        assert_eq!(b.surface(&inside, hit).n, Vec3::X);
        assert!(b
            .intersect(&Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::X), f32::INFINITY)
            .is_none());
        assert!(Cuboid::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0), &Transform::IDENTITY).is_none());
    }

    #[test]
    fn rotated_box() {
        let rot = Transform::rotate(Vec3::Y, 45.0).unwrap();
        let b = Cuboid::new(Vec3::splat(-1.0), Vec3::ONE, &rot).unwrap();
        let ray = Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::NEG_X);
        let hit = b.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.0 - (5.0 - 2f32.sqrt())).abs() < 1e-5);
    }
}
