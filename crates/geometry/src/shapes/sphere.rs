//! Spheres, and ellipsoids as spheres under a non-uniform placement.
//!
//! Object space holds a unit sphere at the origin; the placement carries centre, radius
//! and any transform. The quadratic is solved in the numerically stable form of Haines et
//! al., "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7).

use super::{one_lane, GatherSurface, ShapeHit, ShapeSurface, SurfaceKernel};
use crate::placement::PlacementLanes;
use crate::triangle_lanes::SurfaceLanes;
use crate::Placement;
use glam::{Vec2, Vec3, Vec4};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::{trig, Aabb, Ray, Transform};
use std::f32::consts::PI;
use std::ops::{Add, Div, Mul, Neg, Sub};

#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    placement: Placement,
    /// Centre and radius in world space when the placement keeps the sphere round (a
    /// rotation, one scale and a translation): rays are then tested in world space, with
    /// no transform of the ray.
    round: Option<(Vec3, f32)>,
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
            round: round(&local),
        })
    }

    /// Centre and radius in world space, when the sphere is round there (see
    /// [`Sphere::intersect`]).
    pub fn world_round(&self) -> Option<(Vec3, f32)> {
        self.round
    }

    pub fn bounds(&self) -> Aabb {
        self.placement.bounds(Aabb::new(Vec3::splat(-1.0), Vec3::ONE))
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        // The ray from the centre, and the squared radius, in world or object space (the
        // ray parameter is the same in both).
        let (f, dir, r2) = match self.round {
            Some((centre, radius)) => (ray.origin - centre, ray.dir, radius * radius),
            None => {
                let r = self.placement.ray_to_object(ray);
                (r.origin, r.dir, 1.0)
            }
        };
        let t = nearest_root(f.to_array(), dir.to_array(), dir.length_squared(), r2);
        (t > 0.0 && t < t_max).then_some((t, Vec2::ZERO))
    }

    /// The one-lane instance of the surface kernel.
    #[inline(always)]
    pub fn lanes(&self) -> SphereLanes<f32> {
        SphereLanes {
            placement: self.placement.lanes(),
        }
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ShapeSurface {
        one_lane(&self.lanes(), ray, hit)
    }
}

/// What [`nearest_root`] computes with: `f32`, or four lanes of it (`Vec4`, the
/// shapes' packets in `object_set.rs`), the same floats per lane.
pub(crate) trait RootLanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    fn signum(self) -> Self;
    /// Correctly rounded, as `f32::sqrt`.
    fn sqrt(self) -> Self;
    /// `(x, y)` if `x <= y`, else `(y, x)`.
    fn ordered(x: Self, y: Self) -> (Self, Self);
    /// `a` where `a > 0`, else `b`.
    fn positive_or(a: Self, b: Self) -> Self;
    /// NaN where `disc < 0`, else `t`.
    fn unless_negative(disc: Self, t: Self) -> Self;
}

impl RootLanes for f32 {
    fn signum(self) -> f32 {
        f32::signum(self)
    }
    fn sqrt(self) -> f32 {
        f32::sqrt(self)
    }
    fn ordered(x: f32, y: f32) -> (f32, f32) {
        if x <= y {
            (x, y)
        } else {
            (y, x)
        }
    }
    fn positive_or(a: f32, b: f32) -> f32 {
        if a > 0.0 {
            a
        } else {
            b
        }
    }
    fn unless_negative(disc: f32, t: f32) -> f32 {
        if disc < 0.0 {
            f32::NAN
        } else {
            t
        }
    }
}

impl RootLanes for Vec4 {
    fn signum(self) -> Vec4 {
        Vec4::signum(self)
    }
    fn sqrt(self) -> Vec4 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: SSE is part of the x86-64 baseline, so every x86-64 CPU runs it.
            Vec4::from(unsafe { std::arch::x86_64::_mm_sqrt_ps(self.into()) })
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            Vec4::from_array(self.to_array().map(f32::sqrt))
        }
    }
    fn ordered(x: Vec4, y: Vec4) -> (Vec4, Vec4) {
        let le = x.cmple(y);
        (Vec4::select(le, x, y), Vec4::select(le, y, x))
    }
    fn positive_or(a: Vec4, b: Vec4) -> Vec4 {
        Vec4::select(a.cmpgt(Vec4::ZERO), a, b)
    }
    fn unless_negative(disc: Vec4, t: Vec4) -> Vec4 {
        Vec4::select(disc.cmplt(Vec4::ZERO), Vec4::NAN, t)
    }
}

/// The distance to the nearer positive crossing of a ray (from `f`, the origin relative to
/// the centre, along `dir` with `a = |dir|²`) with a sphere of squared radius `r2`, in the
/// numerically stable form of Haines et al. (eq. 7.7 for the discriminant, from the
/// distance between the centre and the line); NaN where the ray misses (a negative
/// discriminant), which no distance test passes. The caller keeps it if it lies in
/// `(0, t_max)`.
#[inline(always)]
pub(crate) fn nearest_root<T: RootLanes>(f: [T; 3], dir: [T; 3], a: T, r2: T) -> T {
    let b = f[0] * dir[0] + f[1] * dir[1] + f[2] * dir[2];
    let c = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) - r2;
    let s = b / a;
    let l = [f[0] - s * dir[0], f[1] - s * dir[1], f[2] - s * dir[2]];
    let disc = r2 - (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    let q = -(b + b.signum() * (a * disc).sqrt());
    let (t0, t1) = T::ordered(c / q, q / a);
    T::unless_negative(disc, T::positive_or(t0, t1))
}

/// Spheres' surfaces, each lane its own placement.
#[derive(Clone, Copy, Debug)]
pub struct SphereLanes<R: Real> {
    pub placement: PlacementLanes<R>,
}

impl<R: Real> SurfaceKernel<R> for SphereLanes<R> {
    #[inline(always)]
    fn surface(&self, origin: V3<R>, dir: V3<R>, t: R, _: (R, R)) -> SurfaceLanes<R> {
        let (zero, one, two_pi) = (R::splat(0.0), R::splat(1.0), R::splat(2.0 * PI));
        let (o, d) = self.placement.ray_to_object(origin, dir);
        // Re-project onto the sphere to remove the error of `origin + t * dir`.
        let (local, _) = (o + d.scale(t)).try_normalize();
        // Texture coordinates: longitude about the object's y axis, latitude from +y.
        let phi = trig::atan2(local.z, local.x);
        let phi = R::select(phi.cmp_lt(zero), phi + two_pi, phi);
        let y = R::select(local.y.cmp_lt(-one), -one, local.y);
        let theta = trig::acos(R::select(y.cmp_gt(one), one, y));
        let n = self.placement.normal_to_world(local);
        SurfaceLanes {
            p: self.placement.to_world.point(local),
            ng: n,
            ns: n,
            uv: (phi / two_pi, theta / R::splat(PI)),
            // ∂p/∂φ of (cos φ sin θ, cos θ, sin φ sin θ).
            dpdu: self.placement.to_world.vector(V3::new(-local.z, zero, local.x)),
        }
    }
}

impl GatherSurface for SphereLanes<f32> {
    type Lanes<L: Lane8> = SphereLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> SphereLanes<L> {
        SphereLanes {
            placement: PlacementLanes::gather(&one.map(|s| s.placement)),
        }
    }
}

/// The world centre and radius of the unit sphere under `t`, when `t`'s linear part is a
/// rotation times one scale (columns orthogonal and of one length, to 1e-6).
fn round(t: &Transform) -> Option<(Vec3, f32)> {
    let m = glam::Mat3::from_mat4(t.m);
    let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
    let s = x.length();
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * s * s;
    let same_length = close(y.length_squared(), s * s) && close(z.length_squared(), s * s);
    let orthogonal = close(x.dot(y), 0.0) && close(y.dot(z), 0.0) && close(z.dot(x), 0.0);
    (same_length && orthogonal && s > 0.0).then(|| (t.m.w_axis.truncate(), s))
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

    /// A rotated, scaled sphere is tested in world space, a squashed one (an ellipsoid) in
    /// object space; both agree with the object-space answer on 2,000 random rays (the
    /// same hit or miss, t within 1e-5 relative).
    #[test]
    fn round_spheres_are_tested_in_world_space_with_the_same_hits() {
        let turn = Transform::rotate(Vec3::new(1.0, 2.0, 3.0), 40.0).unwrap();
        let round = Sphere::new(
            Vec3::new(0.5, -1.0, 2.0),
            0.7,
            &turn.then(Transform::scale(Vec3::splat(3.0)).unwrap()),
        )
        .unwrap();
        let squashed = Sphere::new(Vec3::ZERO, 1.0, &Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap()).unwrap();
        assert!(round.round.is_some() && squashed.round.is_none());
        let object_space = Sphere {
            round: None,
            ..round.clone()
        };
        let mut rng = penumbra_core::Pcg32::new(5, 1);
        let centre = round.round.unwrap().0;
        let mut hits = 0;
        for _ in 0..2000 {
            let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
            // From anywhere around, towards a point near the sphere (most rays hit it).
            let origin = v() * 10.0;
            let ray = Ray::new(origin, centre + v() * 2.5 - origin);
            let (a, b) = (
                round.intersect(&ray, f32::INFINITY),
                object_space.intersect(&ray, f32::INFINITY),
            );
            assert_eq!(a.is_some(), b.is_some(), "{ray:?}");
            if let (Some((ta, _)), Some((tb, _))) = (a, b) {
                assert!((ta - tb).abs() <= 1e-5 * tb.abs().max(1.0), "{ta} vs {tb}");
                hits += 1;
            }
        }
        assert!(hits > 500, "only {hits} hits");
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
