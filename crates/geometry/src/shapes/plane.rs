//! The infinite plane: a point and a normal. Texture coordinates are world distances
//! along two tangent directions, so a checkerboard's scale is in scene units.

use super::{one_lane, plane_hit, GatherSurface, ShapeHit, ShapeSurface, SurfaceKernel};
use crate::triangle_lanes::SurfaceLanes;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
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

    /// The one-lane instance of the surface kernel.
    #[inline(always)]
    pub fn lanes(&self) -> PlaneLanes<f32> {
        PlaneLanes {
            origin: self.origin.into(),
            s: self.frame.s.into(),
            t: self.frame.t.into(),
            n: self.frame.n.into(),
        }
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ShapeSurface {
        one_lane(&self.lanes(), ray, hit)
    }
}

/// Planes' surfaces: each lane its own point and frame.
#[derive(Clone, Copy, Debug)]
pub struct PlaneLanes<R: Real> {
    pub origin: V3<R>,
    pub s: V3<R>,
    pub t: V3<R>,
    pub n: V3<R>,
}

impl<R: Real> SurfaceKernel<R> for PlaneLanes<R> {
    #[inline(always)]
    fn surface(&self, origin: V3<R>, dir: V3<R>, t: R, _: (R, R)) -> SurfaceLanes<R> {
        let p = origin + dir.scale(t);
        let d = p - self.origin;
        SurfaceLanes {
            // Projected back onto the plane to remove rounding error along the normal.
            p: p - self.n.scale(d.dot(self.n)),
            ng: self.n,
            ns: self.n,
            uv: (d.dot(self.s), d.dot(self.t)),
            dpdu: self.s,
        }
    }
}

impl GatherSurface for PlaneLanes<f32> {
    type Lanes<L: Lane8> = PlaneLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> PlaneLanes<L> {
        PlaneLanes {
            origin: V3::gather(one, |p| p.origin),
            s: V3::gather(one, |p| p.s),
            t: V3::gather(one, |p| p.t),
            n: V3::gather(one, |p| p.n),
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
