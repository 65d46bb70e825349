//! The disk: `center + x * axis1 + y * axis2` with x^2 + y^2 <= 1. Under an affine
//! placement a disk becomes an ellipse of the same form, so placement is baked in.
//! Texture coordinates map the unit disk to [0, 1]^2.

use super::{one_lane, plane_coordinates, plane_frame, plane_hit, FlatLanes, ShapeHit, ShapeSurface};
use glam::{Vec2, Vec3};
use penumbra_core::{Aabb, Frame, Ray, Transform};

#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    center: Vec3,
    axis1: Vec3,
    axis2: Vec3,
    n: Vec3,
    w: Vec3,
}

impl Disk {
    /// A disk of `radius` at `center` facing `normal`, placed by `to_world`. `None` for a
    /// zero normal or radius.
    pub fn new(center: Vec3, normal: Vec3, radius: f32, to_world: &Transform) -> Option<Self> {
        let frame = Frame::from_normal(normal.try_normalize()?);
        let center = to_world.point(center);
        let axis1 = to_world.vector(frame.s * radius);
        let axis2 = to_world.vector(frame.t * radius);
        let (n, w) = plane_frame(axis1, axis2, to_world.normal(frame.n))?;
        Some(Disk {
            center,
            axis1,
            axis2,
            n,
            w,
        })
    }

    pub fn bounds(&self) -> Aabb {
        // The ellipse's extent along each world axis is the norm of that row of [axis1 axis2].
        let half = Vec3::new(
            Vec2::new(self.axis1.x, self.axis2.x).length(),
            Vec2::new(self.axis1.y, self.axis2.y).length(),
            Vec2::new(self.axis1.z, self.axis2.z).length(),
        );
        Aabb::new(self.center - half, self.center + half)
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = plane_hit(ray, self.center, self.n, t_max)?;
        let xy = plane_coordinates(ray.at(t), self.center, self.axis1, self.axis2, self.w);
        (xy.length_squared() <= 1.0).then_some((t, xy))
    }

    /// The one-lane instance of the surface kernel.
    #[inline(always)]
    pub fn lanes(&self) -> FlatLanes<f32> {
        FlatLanes {
            origin: self.center.into(),
            e1: self.axis1.into(),
            e2: self.axis2.into(),
            n: self.n.into(),
            disk: true,
        }
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ShapeSurface {
        one_lane(&self.lanes(), ray, hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_respected() {
        let d = Disk::new(Vec3::ZERO, Vec3::Y, 2.0, &Transform::IDENTITY).unwrap();
        assert!(d
            .intersect(&Ray::new(Vec3::new(1.9, 1.0, 0.0), Vec3::NEG_Y), f32::INFINITY)
            .is_some());
        assert!(d
            .intersect(&Ray::new(Vec3::new(1.5, 1.0, 1.5), Vec3::NEG_Y), f32::INFINITY)
            .is_none());
        let b = d.bounds();
        assert!((b.max - Vec3::new(2.0, 0.0, 2.0)).length() < 1e-5);
        assert_eq!(d.n, Vec3::Y);
    }
}
