//! Axis-aligned bounding boxes and the slab test.

use crate::Ray;
use glam::Vec3;

/// An axis-aligned box; the empty box has `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    pub const INFINITE: Aabb = Aabb {
        min: Vec3::splat(f32::NEG_INFINITY),
        max: Vec3::splat(f32::INFINITY),
    };

    pub fn new(a: Vec3, b: Vec3) -> Self {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Aabb::EMPTY, |b, p| b.grow(p))
    }

    pub fn grow(self, p: Vec3) -> Self {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn union(self, o: Aabb) -> Self {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// The box both boxes cover (empty if they do not meet).
    pub fn intersection(self, o: Aabb) -> Self {
        let b = Aabb {
            min: self.min.max(o.min),
            max: self.max.min(o.max),
        };
        if b.is_empty() {
            Aabb::EMPTY
        } else {
            b
        }
    }

    /// Whether the boxes share a point (touching counts).
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.cmple(o.max).all() && o.min.cmple(self.max).all()
    }

    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    pub fn extent(&self) -> Vec3 {
        (self.max - self.min).max(Vec3::ZERO)
    }

    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn surface_area(&self) -> f32 {
        let d = self.extent();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// Index of the longest axis.
    pub fn max_axis(&self) -> usize {
        let d = self.extent();
        if d.x >= d.y && d.x >= d.z {
            0
        } else if d.y >= d.z {
            1
        } else {
            2
        }
    }

    /// Position of `p` relative to the box: 0 at `min`, 1 at `max`, per axis.
    pub fn offset(&self, p: Vec3) -> Vec3 {
        let d = self.max - self.min;
        let o = p - self.min;
        Vec3::new(
            if d.x > 0.0 { o.x / d.x } else { 0.0 },
            if d.y > 0.0 { o.y / d.y } else { 0.0 },
            if d.z > 0.0 { o.z / d.z } else { 0.0 },
        )
    }

    /// The slab test (Kay and Kajiya 1986): entry distance of `ray` if it overlaps the box
    /// within `(0, t_max)`. `inv_dir` is `1 / ray.dir`, computed once per ray. The
    /// exit distance is widened by 2 ulp-scale (pbrt-v4's `1 + 2 * gamma(3)`) so that
    /// rounding never skips a box the ray grazes. A ray with no motion along an axis that
    /// lies exactly in one of the box's faces gets 0 * inf = NaN there; NaN distances are
    /// ignored (as in pbrt), so such a ray counts as touching the box. A ray with a NaN in
    /// its origin or direction misses every box.
    #[inline]
    pub fn hit(&self, ray: &Ray, inv_dir: Vec3, t_max: f32) -> Option<f32> {
        if ray.origin.is_nan() || ray.dir.is_nan() {
            return None;
        }
        let t0 = (self.min - ray.origin) * inv_dir;
        let t1 = (self.max - ray.origin) * inv_dir;
        let (mut near, mut far) = (0.0f32, f32::INFINITY);
        for a in 0..3 {
            // Entry and exit planes by the direction's sign, not by comparing distances that
            // may be NaN.
            let (lo, hi) = if inv_dir[a].is_sign_negative() {
                (t1[a], t0[a])
            } else {
                (t0[a], t1[a])
            };
            if lo > near {
                near = lo;
            }
            if hi < far {
                far = hi;
            }
        }
        let far = far * (1.0 + 2.0 * GAMMA3);
        (near <= far && near < t_max).then_some(near)
    }
}

/// pbrt's gamma(3) = 3u / (1 - 3u), the relative error bound of three rounded operations.
const GAMMA3: f32 = 3.0 * (f32::EPSILON * 0.5) / (1.0 - 3.0 * (f32::EPSILON * 0.5));

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_test() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let r = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
        assert_eq!(b.hit(&r, r.dir.recip(), f32::INFINITY), Some(4.0));
        assert_eq!(b.hit(&r, r.dir.recip(), 3.0), None);
        let inside = Ray::new(Vec3::ZERO, Vec3::Y);
        assert_eq!(b.hit(&inside, inside.dir.recip(), 10.0), Some(0.0));
        let miss = Ray::new(Vec3::new(-5.0, 2.0, 0.0), Vec3::X);
        assert_eq!(b.hit(&miss, miss.dir.recip(), 10.0), None);
        let behind = Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::X);
        assert_eq!(behind.origin.x, 5.0);
        assert_eq!(b.hit(&behind, behind.dir.recip(), 10.0), None);
        let nan = Ray::new(Vec3::NAN, Vec3::Z);
        assert_eq!(b.hit(&nan, nan.dir.recip(), 10.0), None);
        let nan = Ray::new(Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 1.0));
        assert_eq!(b.hit(&nan, nan.dir.recip(), 10.0), None);
        // Rays inside a face's plane with no motion across it touch the box (0 * inf = NaN
        // ignored); one just outside the plane does not.
        for (x, dx) in [(-1.0, 0.0), (1.0, 0.0), (-1.0, -0.0), (1.0, -0.0)] {
            let grazing = Ray::new(Vec3::new(x, 0.0, -5.0), Vec3::new(dx, 0.0, 1.0));
            assert_eq!(b.hit(&grazing, grazing.dir.recip(), 10.0), Some(4.0), "{grazing:?}");
            let outside = Ray::new(Vec3::new(x * 1.000001, 0.0, -5.0), Vec3::Z);
            assert_eq!(b.hit(&outside, outside.dir.recip(), 10.0), None);
        }
    }

    #[test]
    fn grow_and_union() {
        let b = Aabb::from_points([Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)]);
        assert_eq!(b.max_axis(), 2);
        assert_eq!(b.surface_area(), 2.0 * (2.0 + 6.0 + 3.0));
        assert!(Aabb::EMPTY.is_empty());
        assert_eq!(Aabb::EMPTY.union(b), b);
    }
}
