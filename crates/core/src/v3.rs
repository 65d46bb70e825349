//! [`V3`]: a 3-vector whose components are lanes of any [`Real`] type (directions, points
//! and colours in lane-generic code), with the operations glam's `Vec3` performs, in the
//! same order, so that a one-lane `V3<f32>` gives glam's bits.

use crate::lanes::{Lane8, Real};
use std::ops::{Add, Neg};

/// A 3-vector of lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct V3<R> {
    pub x: R,
    pub y: R,
    pub z: R,
}

impl<R: Real> V3<R> {
    #[inline(always)]
    pub fn new(x: R, y: R, z: R) -> Self {
        V3 { x, y, z }
    }

    /// The dot product, summed as glam sums it: (x x' + y y') + z z'.
    #[inline(always)]
    pub fn dot(self, o: Self) -> R {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub fn scale(self, s: R) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }

    /// The cross product, each component as glam computes it.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        V3::new(
            self.y * o.z - o.y * self.z,
            self.z * o.x - o.z * self.x,
            self.x * o.y - o.x * self.y,
        )
    }

    /// `self` over its length, and where that is a unit vector: where 1/length is finite
    /// and positive, as glam's `try_normalize` decides.
    #[inline(always)]
    pub fn try_normalize(self) -> (Self, R::Mask) {
        let rcp = R::splat(1.0) / self.dot(self).sqrt();
        let ok = R::and(rcp.cmp_lt(R::splat(f32::INFINITY)), rcp.cmp_gt(R::splat(0.0)));
        (self.scale(rcp), ok)
    }

    /// Component by component, as glam multiplies vectors (and `Rgb` colours).
    #[inline(always)]
    pub fn mul_each(self, o: Self) -> Self {
        V3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }

    /// Each component over `s`, as glam divides a vector by a number (no reciprocal).
    #[inline(always)]
    pub fn div_by(self, s: R) -> Self {
        V3::new(self.x / s, self.y / s, self.z / s)
    }

    /// Every component `v`.
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        V3::new(R::splat(v), R::splat(v), R::splat(v))
    }

    /// Per lane: `t` where `mask` holds, else `f`.
    #[inline(always)]
    pub fn select(mask: R::Mask, t: Self, f: Self) -> Self {
        V3::new(
            R::select(mask, t.x, f.x),
            R::select(mask, t.y, f.y),
            R::select(mask, t.z, f.z),
        )
    }

    /// Per lane: whether all three components are zero (for a colour, `Rgb::is_black`).
    #[inline(always)]
    pub fn is_black(self) -> R::Mask {
        let zero = R::splat(0.0);
        R::and(R::and(self.x.cmp_eq(zero), self.y.cmp_eq(zero)), self.z.cmp_eq(zero))
    }

    /// A colour's luminance per lane, as `Rgb::luminance` sums it.
    #[inline(always)]
    pub fn luminance(self) -> R {
        R::splat(0.2126) * self.x + R::splat(0.7152) * self.y + R::splat(0.0722) * self.z
    }

    /// A vector in every lane.
    #[inline(always)]
    pub fn splat_vec(v: glam::Vec3) -> Self {
        V3::new(R::splat(v.x), R::splat(v.y), R::splat(v.z))
    }

    /// A colour in every lane.
    #[inline(always)]
    pub fn splat_rgb(c: crate::Rgb) -> Self {
        V3::new(R::splat(c.r), R::splat(c.g), R::splat(c.b))
    }
}

impl<R: Real> std::ops::Sub for V3<R> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<R: Real> Neg for V3<R> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3::new(-self.x, -self.y, -self.z)
    }
}

impl<R: Real> Add for V3<R> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl From<glam::Vec3> for V3<f32> {
    #[inline(always)]
    fn from(v: glam::Vec3) -> Self {
        V3::new(v.x, v.y, v.z)
    }
}

impl From<V3<f32>> for glam::Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Self {
        glam::Vec3::new(v.x, v.y, v.z)
    }
}

impl From<crate::Rgb> for V3<f32> {
    /// A colour's channels as (x, y, z): lane-generic shading carries colours as `V3`.
    #[inline(always)]
    fn from(c: crate::Rgb) -> Self {
        V3::new(c.r, c.g, c.b)
    }
}

impl From<V3<f32>> for crate::Rgb {
    #[inline(always)]
    fn from(v: V3<f32>) -> Self {
        crate::Rgb::new(v.x, v.y, v.z)
    }
}

impl<L: Lane8> V3<L> {
    /// Eight vectors, one per lane.
    #[inline(always)]
    pub fn from_lanes(v: &[glam::Vec3; 8]) -> Self {
        V3::new(
            L::from_array(v.map(|v| v.x)),
            L::from_array(v.map(|v| v.y)),
            L::from_array(v.map(|v| v.z)),
        )
    }

    /// The vector `f` gives of each of eight items, one item per lane (gathering eight
    /// one-lane kernels' fields into one eight-lane kernel).
    #[inline(always)]
    pub fn gather<T, V: Into<glam::Vec3>>(items: &[T; 8], f: impl Fn(&T) -> V) -> Self {
        V3::from_lanes(&items.each_ref().map(|t| f(t).into()))
    }

    /// The vector of lane `k`.
    #[inline(always)]
    pub fn lane(self, k: usize) -> glam::Vec3 {
        glam::Vec3::new(self.x.to_array()[k], self.y.to_array()[k], self.z.to_array()[k])
    }

    /// The vector of each lane.
    #[inline(always)]
    pub fn to_lanes(self) -> [glam::Vec3; 8] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        std::array::from_fn(|k| glam::Vec3::new(x[k], y[k], z[k]))
    }
}
