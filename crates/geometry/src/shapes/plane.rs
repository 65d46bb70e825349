//! The infinite plane: a point and a normal. Texture coordinates are world distances
//! along two tangent directions, so a checkerboard's scale is in scene units.

use super::{plane_hit, ShapeHit, ShapeSurface};
use glam::{Vec2, Vec3};
use penumbra_core::{Frame, Ray, Transform};

#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    origin: Vec3,
    frame: Frame,
}

impl Plane {
    /// The plane through `point` with normal `normal`, placed by `to_world`. `None` if the
    /// normal is zero.
    pub fn new(point: Vec3, normal: Vec3, to_world: &Transform) -> Option<Self> {
        let n = to_world.normal(normal).try_normalize()?;
        Some(Plane {
            origin: to_world.point(point),
            frame: Frame::from_normal(n),
        })
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        plane_hit(ray, self.origin, self.frame.n, t_max).map(|t| (t, Vec2::ZERO))
    }

    pub fn surface(&self, ray: &Ray, (t, _): ShapeHit) -> ShapeSurface {
        let p = ray.at(t);
        let d = p - self.origin;
        // Project back onto the plane to remove rounding error along the normal.
        let p = p - self.frame.n * d.dot(self.frame.n);
        ShapeSurface {
            p,
            n: self.frame.n,
            uv: Vec2::new(d.dot(self.frame.s), d.dot(self.frame.t)),
            dpdu: self.frame.s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_from_both_sides_and_misses_parallel() {
        let p = Plane::new(Vec3::ZERO, Vec3::Y, &Transform::translate(Vec3::new(0.0, -1.0, 0.0))).unwrap();
        let (t, _) = p.intersect(&Ray::new(Vec3::ZERO, Vec3::NEG_Y), f32::INFINITY).unwrap();
        assert_eq!(t, 1.0);
        assert!(p
            .intersect(&Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::Y), f32::INFINITY)
            .is_some());
        assert!(p.intersect(&Ray::new(Vec3::ZERO, Vec3::X), f32::INFINITY).is_none());
        assert!(p.intersect(&Ray::new(Vec3::ZERO, Vec3::Y), f32::INFINITY).is_none());
        assert!(Plane::new(Vec3::ZERO, Vec3::ZERO, &Transform::IDENTITY).is_none());
    }
}
