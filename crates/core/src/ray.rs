//! Rays, and the robust origin offset that keeps secondary rays off the surface they leave.

use crate::lanes::{Real, V3};
use glam::Vec3;

/// A ray `origin + t * dir`. Directions need not be normalised; the interval of valid `t`
/// is `(0, t_max)`, with `t_max` passed to each query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// A ray leaving the surface point `p` with geometric normal `n` in direction `dir`,
    /// its origin pushed to the side of the surface that `dir` points into.
    pub fn spawn(p: Vec3, n: Vec3, dir: Vec3) -> Self {
        let n = if n.dot(dir) < 0.0 { -n } else { n };
        Ray::new(offset_origin(p, n), dir)
    }
}

/// Relative shortening of shadow rays so they do not hit the surface they aim at.
pub const SHADOW_EPSILON: f32 = 1e-4;

/// Offsets a surface point along its normal by a few units in the last place, after
/// Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection"
/// (Ray Tracing Gems, chapter 6, 2019). Near the origin, where ULPs are tiny, a fixed
/// offset is used instead.
pub fn offset_origin(p: Vec3, n: Vec3) -> Vec3 {
    offset_origin_lanes(p.into(), n.into()).into()
}

/// [`offset_origin`] for lanes of any [`Real`] type.
#[inline(always)]
pub fn offset_origin_lanes<R: Real>(p: V3<R>, n: V3<R>) -> V3<R> {
    V3::new(p.x.offset_along(n.x), p.y.offset_along(n.y), p.z.offset_along(n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_normal_side() {
        for p in [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1e4, -3e3, 2.5),
            Vec3::new(-0.01, 7.0, -1e-6),
        ] {
            for n in [Vec3::X, Vec3::NEG_Y, Vec3::new(1.0, 1.0, 1.0).normalize()] {
                let q = offset_origin(p, n);
                assert!((q - p).dot(n) > 0.0, "p {p} n {n} q {q}");
                assert!((q - p).length() < 1e-3 * (1.0 + p.abs().max_element()));
            }
        }
    }
}
