//! Spheres, and ellipsoids as spheres under a non-uniform placement.
//!
//! Object space holds a unit sphere at the origin; the placement carries centre, radius
//! and any transform. The quadratic is solved in the numerically stable form of Haines et
//! al., "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7).

use super::{ShapeHit, ShapeSurface};
use crate::Placement;
use glam::{Vec2, Vec3};
use penumbra_core::{trig, Aabb, Ray, Transform};
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    placement: Placement,
}

impl Sphere {
    /// A sphere of `radius` at `center`, then placed by `to_world`; `None` if the radius is
    /// zero or too small or large to invert.
    pub fn new(center: Vec3, radius: f32, to_world: &Transform) -> Option<Self> {
        let local = Transform::scale(Vec3::splat(radius))?
            .then(Transform::translate(center))
            .then(*to_world);
        Some(Sphere {
            placement: Placement::new(&local),
        })
    }

    pub fn bounds(&self) -> Aabb {
        self.placement.bounds(Aabb::new(Vec3::splat(-1.0), Vec3::ONE))
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let r = self.placement.ray_to_object(ray);
        let f = r.origin;
        let a = r.dir.length_squared();
        let b = f.dot(r.dir);
        let c = f.length_squared() - 1.0;
        // Discriminant from the distance between the centre and the line (eq. 7.7).
        let l = f - (b / a) * r.dir;
        let disc = 1.0 - l.length_squared();
        if disc < 0.0 {
            return None;
        }
        let q = -(b + b.signum() * (a * disc).sqrt());
        let (t0, t1) = {
            let (x, y) = (c / q, q / a);
            if x <= y {
                (x, y)
            } else {
                (y, x)
            }
        };
        let t = if t0 > 0.0 { t0 } else { t1 };
        (t > 0.0 && t < t_max).then_some((t, Vec2::ZERO))
    }

    pub fn surface(&self, ray: &Ray, (t, _): ShapeHit) -> ShapeSurface {
        let r = self.placement.ray_to_object(ray);
        // Re-project onto the sphere to remove the error of `origin + t * dir`.
        let local = r.at(t).normalize();
        // Texture coordinates: longitude about the object's y axis, latitude from +y.
        let phi = trig::atan2(local.z, local.x);
        let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
        let theta = trig::acos(local.y.clamp(-1.0, 1.0));
        ShapeSurface {
            p: self.placement.point_to_world(local),
            n: self.placement.normal_to_world(local),
            uv: Vec2::new(phi / (2.0 * PI), theta / PI),
            // ∂p/∂φ of (cos φ sin θ, cos θ, sin φ sin θ).
            dpdu: self.placement.vector_to_world(Vec3::new(-local.z, 0.0, local.x)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Sphere {
        Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0, &Transform::IDENTITY).unwrap()
    }

    #[test]
    fn hit_from_outside_and_inside() {
        let s = unit();
        let (t, _) = s.intersect(&Ray::new(Vec3::ZERO, Vec3::NEG_Z), f32::INFINITY).unwrap();
        assert!((t - 4.0).abs() < 1e-6);
        let inside = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::X);
        let (t, _) = s.intersect(&inside, f32::INFINITY).unwrap();
        assert!((t - 1.0).abs() < 1e-6);
        let surf = s.surface(&inside, (t, Vec2::ZERO));
        assert!(
            (surf.n - Vec3::X).length() < 1e-6,
            "normal points outward even from inside"
        );
    }

    #[test]
    fn misses_behind_and_beyond_t_max() {
        let s = unit();
        assert!(
            s.intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY).is_none(),
            "sphere behind the origin"
        );
        assert!(
            s.intersect(&Ray::new(Vec3::ZERO, Vec3::NEG_Z), 3.9).is_none(),
            "t_max respected"
        );
        assert!(s
            .intersect(&Ray::new(Vec3::new(0.0, 1.01, 0.0), Vec3::NEG_Z), f32::INFINITY)
            .is_none());
    }

    #[test]
    fn grazing_ray_and_precision_far_away() {
        let s = unit();
        let graze = Ray::new(Vec3::new(0.0, 0.999_999, 0.0), Vec3::NEG_Z);
        let (t, _) = s.intersect(&graze, f32::INFINITY).unwrap();
        assert!((t - 5.0).abs() < 2e-3);
        // A small sphere seen from far away: the naive quadratic loses it to cancellation.
        let tiny = Sphere::new(Vec3::new(0.0, 0.0, -1e4), 1e-2, &Transform::IDENTITY).unwrap();
        let (t, _) = tiny
            .intersect(&Ray::new(Vec3::ZERO, Vec3::NEG_Z), f32::INFINITY)
            .unwrap();
        assert!((t - (1e4 - 1e-2)).abs() < 1e-2);
    }

    #[test]
    fn degenerate_radius_is_refused() {
        assert!(Sphere::new(Vec3::ZERO, 0.0, &Transform::IDENTITY).is_none());
        assert!(Sphere::new(Vec3::ZERO, 1e-40, &Transform::IDENTITY).is_none());
    }

    #[test]
    fn ellipsoid_normal() {
        let squash = Transform::scale(Vec3::new(2.0, 1.0, 1.0)).unwrap();
        let s = Sphere::new(Vec3::ZERO, 1.0, &squash).unwrap();
        let ray = Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::NEG_X);
        let hit = s.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.0 - 3.0).abs() < 1e-5);
        let surf = s.surface(&ray, hit);
        assert!((surf.p - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-5);
        assert!((surf.n - Vec3::X).length() < 1e-5);
        let b = s.bounds();
        assert!((b.max - Vec3::new(2.0, 1.0, 1.0)).length() < 1e-5);
    }
}
