//! Lane types: numeric code written once for one value (`f32`) or for eight at a time
//! ([`F8`], a `wide::f32x8`: one AVX register), the way Enoki and Dr.Jit let Mitsuba 3 run
//! the same renderer scalar or vectorised. A routine generic over [`Real`] performs the
//! same IEEE operations in the same order for either type, so lane `k` of its eight-wide
//! result is bit for bit the scalar result for input `k` (branches become [`Real::select`]).
//!
//! This is the first layer of a path tracer that shades eight paths per instruction
//! (docs/performance.md); the warps and frames built on it are in [`crate::warp`] and
//! [`crate::frame`].

pub use crate::v3::V3;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Eight `f32` lanes: a `wide::f32x8` whose negation flips the sign bit as `f32`'s does
/// (`wide` computes 0 - x, which turns -0 into +0 and so breaks lane-for-lane equality).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct F8(pub wide::f32x8);

impl F8 {
    pub const ZERO: F8 = F8(wide::f32x8::ZERO);

    #[inline(always)]
    pub fn to_array(self) -> [f32; 8] {
        self.0.to_array()
    }

    /// The mask that holds in lane `k` where `b[k]`.
    #[inline(always)]
    pub fn mask(b: [bool; 8]) -> wide::f32x8 {
        wide::f32x8::from(b.map(|b| f32::from_bits(if b { u32::MAX } else { 0 })))
    }

    /// Bit `k` set where `mask` holds in lane `k`.
    #[inline(always)]
    pub fn mask_bits(mask: wide::f32x8) -> u32 {
        mask.move_mask() as u32
    }
}

impl From<[f32; 8]> for F8 {
    #[inline(always)]
    fn from(a: [f32; 8]) -> Self {
        F8(wide::f32x8::from(a))
    }
}

macro_rules! lanewise {
    ($($op:ident $f:ident),*) => {$(
        impl $op for F8 {
            type Output = F8;
            #[inline(always)]
            fn $f(self, o: F8) -> F8 {
                F8(self.0.$f(o.0))
            }
        }
    )*};
}
lanewise!(Add add, Sub sub, Mul mul, Div div);

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        F8(self.0 ^ wide::f32x8::splat(-0.0))
    }
}

/// What lane-generic numeric code needs of its number type.
pub trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// One truth value per lane.
    type Mask: Copy;
    fn splat(v: f32) -> Self;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    /// The larger of the two. (`f32::max` and `wide`'s may differ at `max(+0, -0)`: a
    /// lane-generic routine must not let that choice reach its result, e.g. use the
    /// maximum of two zeros only where a select drops it.)
    fn max(self, other: Self) -> Self;
    /// `self`'s magnitude with `sign`'s sign.
    fn copysign(self, sign: Self) -> Self;
    fn cmp_lt(self, other: Self) -> Self::Mask;
    fn cmp_le(self, other: Self) -> Self::Mask;
    fn cmp_gt(self, other: Self) -> Self::Mask;
    fn cmp_ge(self, other: Self) -> Self::Mask;
    fn cmp_eq(self, other: Self) -> Self::Mask;
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    fn not(a: Self::Mask) -> Self::Mask;
    /// The mask that holds in every lane where `b`, in none otherwise.
    #[inline(always)]
    fn splat_mask(b: bool) -> Self::Mask {
        let zero = Self::splat(0.0);
        if b {
            zero.cmp_le(zero)
        } else {
            zero.cmp_lt(zero)
        }
    }
    /// Whether `mask` holds in any lane: work whose lanes would all be dropped by a select
    /// may be skipped (for one lane, the scalar code's branch).
    fn any(mask: Self::Mask) -> bool;
    /// Per lane: `t` where `mask` holds, else `f`.
    fn select(mask: Self::Mask, t: Self, f: Self) -> Self;
    /// Per lane: mask `t` where `mask` holds, else mask `f`.
    #[inline(always)]
    fn select_mask(mask: Self::Mask, t: Self::Mask, f: Self::Mask) -> Self::Mask {
        Self::or(Self::and(mask, t), Self::and(Self::not(mask), f))
    }
    /// The coordinate `self` of a surface point moved along the normal component `n` by a
    /// few units in the last place ([`crate::ray::offset_origin`], one coordinate).
    fn offset_along(self, n: Self) -> Self;
    /// The largest integer not above each lane (exact, as `f32::floor`).
    fn floor(self) -> Self;
    /// A scalar step per lane with `N` inputs and `M` results, for what lanes cannot do
    /// together (a table walk, a gather, a lookup in a table of the lane's own): lane `k`
    /// of the results is `f(k, lane k of each input)`. The closure sees only `f32`s, so it
    /// needs no SIMD level of its own.
    fn map_lanes<const N: usize, const M: usize>(
        inputs: [Self; N],
        f: impl FnMut(usize, [f32; N]) -> [f32; M],
    ) -> [Self; M];
    /// `self` to the power `e`, lane by lane as `f32::powf` computes it.
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        let [p] = Self::map_lanes([self, e], |_, [x, e]| [x.powf(e)]);
        p
    }
    /// Per lane: whether the value is finite (neither infinite nor NaN).
    /// (x - x is 0 for a finite x, NaN for an infinite or NaN one.)
    #[inline(always)]
    #[allow(clippy::eq_op)]
    fn is_finite(self) -> Self::Mask {
        (self - self).cmp_eq(Self::splat(0.0))
    }
}

/// [`Real::offset_along`]'s constants (Wächter and Binder 2019): below `ORIGIN` a fixed
/// step `FLOAT_SCALE` n, else `INT_SCALE` n units in the last place.
pub(crate) const ORIGIN: f32 = 1.0 / 32.0;
pub(crate) const FLOAT_SCALE: f32 = 1.0 / 65536.0;
pub(crate) const INT_SCALE: f32 = 256.0;

impl Real for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        v
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        f32::copysign(self, sign)
    }
    #[inline(always)]
    fn cmp_lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn cmp_le(self, other: Self) -> bool {
        self <= other
    }
    #[inline(always)]
    fn cmp_gt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn cmp_ge(self, other: Self) -> bool {
        self >= other
    }
    #[inline(always)]
    fn cmp_eq(self, other: Self) -> bool {
        self == other
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a && b
    }
    #[inline(always)]
    fn or(a: bool, b: bool) -> bool {
        a || b
    }
    #[inline(always)]
    fn not(a: bool) -> bool {
        !a
    }
    #[inline(always)]
    fn any(mask: bool) -> bool {
        mask
    }
    #[inline(always)]
    fn select(mask: bool, t: Self, f: Self) -> Self {
        if mask {
            t
        } else {
            f
        }
    }
    #[inline(always)]
    fn floor(self) -> Self {
        f32::floor(self)
    }
    #[inline(always)]
    fn map_lanes<const N: usize, const M: usize>(
        inputs: [Self; N],
        mut f: impl FnMut(usize, [f32; N]) -> [f32; M],
    ) -> [Self; M] {
        f(0, inputs)
    }
    #[inline(always)]
    fn offset_along(self, n: Self) -> Self {
        if self.abs() < ORIGIN {
            self + FLOAT_SCALE * n
        } else {
            let of_i = (INT_SCALE * n) as i32;
            let bits = self.to_bits() as i32;
            let moved = if self < 0.0 { bits - of_i } else { bits + of_i };
            f32::from_bits(moved as u32)
        }
    }
}

/// `F8`'s comparisons: `wide`'s lane masks.
macro_rules! lane_comparisons {
    ($($f:ident $trait:ident),*) => {$(
        #[inline(always)]
        fn $f(self, other: Self) -> wide::f32x8 {
            wide::$trait::$f(self.0, other.0)
        }
    )*};
}

impl Real for F8 {
    /// All ones or all zeros per lane.
    type Mask = wide::f32x8;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        F8(wide::f32x8::splat(v))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F8(self.0.sqrt())
    }
    #[inline(always)]
    fn abs(self) -> Self {
        F8(self.0.abs())
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        F8(self.0.max(other.0))
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        F8(self.0.copysign(sign.0))
    }
    lane_comparisons!(cmp_lt CmpLt, cmp_le CmpLe, cmp_gt CmpGt, cmp_ge CmpGe, cmp_eq CmpEq);
    #[inline(always)]
    fn and(a: wide::f32x8, b: wide::f32x8) -> wide::f32x8 {
        a & b
    }
    #[inline(always)]
    fn or(a: wide::f32x8, b: wide::f32x8) -> wide::f32x8 {
        a | b
    }
    #[inline(always)]
    fn not(a: wide::f32x8) -> wide::f32x8 {
        !a
    }
    #[inline(always)]
    fn any(mask: wide::f32x8) -> bool {
        mask.move_mask() != 0
    }
    #[inline(always)]
    fn select(mask: wide::f32x8, t: Self, f: Self) -> Self {
        F8(mask.blend(t.0, f.0))
    }
    #[inline(always)]
    fn floor(self) -> Self {
        F8(self.0.floor())
    }
    #[inline(always)]
    fn map_lanes<const N: usize, const M: usize>(
        inputs: [Self; N],
        f: impl FnMut(usize, [f32; N]) -> [f32; M],
    ) -> [Self; M] {
        map_columns(inputs.map(F8::to_array), f).map(F8::from)
    }
    #[inline(always)]
    fn offset_along(self, n: Self) -> Self {
        use wide::{i32x8, CmpLt};
        let near_origin = self.0.abs().cmp_lt(wide::f32x8::splat(ORIGIN));
        let fixed = self.0 + wide::f32x8::splat(FLOAT_SCALE) * n.0;
        // `trunc_int` saturates and maps NaN to 0, as `as i32` does.
        let of_i = (wide::f32x8::splat(INT_SCALE) * n.0).trunc_int();
        let bits: i32x8 = bytemuck::cast(self.0);
        let negative: i32x8 = bytemuck::cast(self.0.cmp_lt(wide::f32x8::ZERO));
        let moved: wide::f32x8 = bytemuck::cast(negative.blend(bits - of_i, bits + of_i));
        F8(near_origin.blend(fixed, moved))
    }
}

/// Values of lanes that a mask can choose between, lane by lane.
pub trait Choose<R: Real> {
    /// `a` where `mask` holds, else `b`.
    fn choose(mask: R::Mask, a: Self, b: Self) -> Self;
}

impl<R: Real> Choose<R> for R {
    #[inline(always)]
    fn choose(mask: R::Mask, a: Self, b: Self) -> Self {
        R::select(mask, a, b)
    }
}

impl<R: Real> Choose<R> for V3<R> {
    #[inline(always)]
    fn choose(mask: R::Mask, a: Self, b: Self) -> Self {
        V3::select(mask, a, b)
    }
}

/// `$a` where `$mask` holds, else `$b`, per lane of the [`Real`] type `$r` (any
/// [`Choose`] value), evaluating only the sides some lane takes, so that a one-lane
/// instance runs only its own branch. A macro, not a function of closures: a closure is
/// not compiled for the SIMD level of the kernel it sits in, so its lane instructions
/// would become calls.
#[macro_export]
macro_rules! choose_lanes {
    ($r:ty, $mask:expr, $a:expr, $b:expr) => {{
        let mask = $mask;
        if !<$r as $crate::lanes::Real>::any(mask) {
            $b
        } else if !<$r as $crate::lanes::Real>::any(<$r as $crate::lanes::Real>::not(mask)) {
            $a
        } else {
            $crate::lanes::Choose::<$r>::choose(mask, $a, $b)
        }
    }};
}

/// [`Real::map_lanes`] over eight lanes held as arrays.
#[inline(always)]
pub(crate) fn map_columns<const N: usize, const M: usize>(
    inputs: [[f32; 8]; N],
    mut f: impl FnMut(usize, [f32; N]) -> [f32; M],
) -> [[f32; 8]; M] {
    let mut out = [[0.0; 8]; M];
    for k in 0..8 {
        for (column, v) in out.iter_mut().zip(f(k, inputs.map(|i| i[k]))) {
            column[k] = v;
        }
    }
    out
}

/// An eight-lane [`Real`]: [`F8`] (portable), or `F8Avx` (`crate::lanes_avx`, inside the
/// kernels compiled for AVX2). Code generic over it runs at either SIMD level.
pub trait Lane8: Real {
    fn from_array(a: [f32; 8]) -> Self;
    fn to_array(self) -> [f32; 8];
    /// The mask that holds in lane `k` where `b[k]`.
    fn mask_of(b: [bool; 8]) -> Self::Mask;
    /// Bit `k` set where `mask` holds in lane `k`.
    fn bits(mask: Self::Mask) -> u32;
    /// The lanewise minimum as x86's `minps` takes it: `other` where either lane is NaN
    /// (so a NaN `self` is passed over).
    fn min_or_other(self, other: Self) -> Self;
    /// The lanewise maximum as x86's `maxps` takes it: `other` where either lane is NaN.
    fn max_or_other(self, other: Self) -> Self;
}

impl Lane8 for F8 {
    #[inline(always)]
    fn from_array(a: [f32; 8]) -> Self {
        F8::from(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        self.0.to_array()
    }
    #[inline(always)]
    fn mask_of(b: [bool; 8]) -> wide::f32x8 {
        F8::mask(b)
    }
    #[inline(always)]
    fn bits(mask: wide::f32x8) -> u32 {
        F8::mask_bits(mask)
    }
    #[inline(always)]
    fn min_or_other(self, other: Self) -> Self {
        // `minps`'s definition, spelt out (x86 compiles it to `minps`).
        F8(wide::CmpLt::cmp_lt(self.0, other.0).blend(self.0, other.0))
    }
    #[inline(always)]
    fn max_or_other(self, other: Self) -> Self {
        F8(wide::CmpGt::cmp_gt(self.0, other.0).blend(self.0, other.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{Basis, Frame};
    use crate::{warp, Pcg32};
    use glam::{Vec2, Vec3};

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    /// Inputs that reach every select: both octant halves, the disk centre, the edges of the
    /// square, normals on both sides of z = 0 (and on it), along the axes.
    fn inputs(rng: &mut Pcg32, k: usize) -> (Vec2, Vec3) {
        let t = rng.next_f32();
        let u = match k % 9 {
            0 => Vec2::splat(0.5),
            1 => Vec2::new(0.0, t),
            2 => Vec2::new(t, 1.0 - f32::EPSILON / 2.0),
            // |2u - 1| equal in x and y: the octant boundary, where the disk map's
            // comparison decides which of sin and cos (an ulp apart at π/4) goes where.
            3 => [Vec2::ZERO, Vec2::splat(t), Vec2::new(t, 1.0 - t), Vec2::new(0.25, 0.75)][k / 9 % 4],
            _ => Vec2::new(t, rng.next_f32()),
        };
        let n = match k % 5 {
            0 => Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 0.0),
            1 => [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::NEG_Y, Vec3::new(0.6, 0.8, -0.0)][k / 5 % 5],
            _ => Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5),
        };
        (u, n.try_normalize().unwrap_or(Vec3::Z))
    }

    /// The disk map at the octant boundary |x| = |y| as the scalar code had it before it was
    /// written over lanes (the x > y branch for |x| > |y| only): sin and cos of π/4 differ
    /// by an ulp, so a `<` for the `<=` would swap them and change images.
    #[test]
    fn disk_map_keeps_its_octant_convention() {
        let d = warp::uniform_disk(Vec2::ZERO);
        let (sin, cos) = warp::sin_cos_octant(std::f32::consts::FRAC_PI_4);
        assert_ne!(sin, cos);
        assert_eq!([d.x, d.y].map(f32::to_bits), [-sin, -cos].map(f32::to_bits));
    }

    /// The offset ray origin in eight lanes equals the scalar one: points near the origin
    /// (the fixed step), on either side of it, large ones, zero and negative-zero
    /// coordinates, normals of every sign.
    #[test]
    fn offset_origin_in_eight_lanes_equals_the_scalar_floats() {
        let mut rng = Pcg32::new(2, 8);
        let coordinate = |rng: &mut Pcg32, k: usize| {
            let r = rng.next_f32() * 2.0 - 1.0;
            match k % 6 {
                0 => r / 64.0,
                1 => 0.0,
                2 => -0.0,
                3 => r * 1e5,
                4 => (1.0 / 32.0) * r.signum(),
                _ => r * 4.0,
            }
        };
        for round in 0..10_000 {
            let p: [Vec3; 8] = std::array::from_fn(|k| {
                let i = 8 * round + k;
                Vec3::new(
                    coordinate(&mut rng, i),
                    coordinate(&mut rng, i / 6),
                    coordinate(&mut rng, i / 36),
                )
            });
            let n: [Vec3; 8] = std::array::from_fn(|_| {
                Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5).normalize()
            });
            let lanes = crate::ray::offset_origin_lanes(V3::<F8>::from_lanes(&p), V3::<F8>::from_lanes(&n)).to_lanes();
            for k in 0..8 {
                let scalar = crate::ray::offset_origin(p[k], n[k]);
                assert_eq!(bits(lanes[k]), bits(scalar), "{} along {}", p[k], n[k]);
            }
        }
    }

    /// Eight lanes give, lane by lane, exactly the scalar routines' floats: the lane type
    /// behaves as `f32` does (the routines' own correctness is tested in `warp` and `frame`:
    /// the chi-square fits of the warps to their densities, orthonormality).
    #[test]
    fn eight_lanes_equal_the_scalar_routines_bit_for_bit() {
        let mut rng = Pcg32::new(5, 9);
        for round in 0..20_000 {
            let cases: [(Vec2, Vec3); 8] = std::array::from_fn(|k| inputs(&mut rng, 8 * round + k));
            let (ux, uy) = (F8::from(cases.map(|c| c.0.x)), F8::from(cases.map(|c| c.0.y)));
            let normals = V3::from_lanes(&cases.map(|c| c.1));
            let local = warp::cosine_hemisphere_lanes(ux, uy);
            let basis = Basis::from_normal(normals);
            let world = basis.to_world(local).to_lanes();
            let (local, s, t) = (local.to_lanes(), basis.s.to_lanes(), basis.t.to_lanes());
            let tangents: [Vec3; 8] = std::array::from_fn(|k| match (8 * round + k) % 6 {
                0 => Vec3::ZERO,
                1 => cases[k].1 * 3.0,
                _ => Vec3::new(rng.next_f32() - 0.5, rng.next_f32(), rng.next_f32() * 2.0 - 1.0),
            });
            let tangent_basis = Basis::from_normal_tangent(normals, V3::from_lanes(&tangents));
            let (ts, tt) = (tangent_basis.s.to_lanes(), tangent_basis.t.to_lanes());
            let back = tangent_basis.to_local(V3::from_lanes(&world)).to_lanes();
            let (b1, b2) = warp::uniform_triangle_lanes(ux, uy);
            let (b1, b2) = (b1.to_array(), b2.to_array());
            for (k, &(u, n)) in cases.iter().enumerate() {
                let frame = Frame::from_normal(n);
                let w = warp::cosine_hemisphere(u);
                assert_eq!(bits(local[k]), bits(w), "cosine_hemisphere({u})");
                assert_eq!((bits(s[k]), bits(t[k])), (bits(frame.s), bits(frame.t)), "frame of {n}");
                assert_eq!(bits(world[k]), bits(frame.to_world(w)), "to_world, {u} {n}");
                let f = Frame::from_normal_tangent(n, tangents[k]);
                assert_eq!(
                    (bits(ts[k]), bits(tt[k])),
                    (bits(f.s), bits(f.t)),
                    "frame of {n}, {}",
                    tangents[k]
                );
                assert_eq!(bits(back[k]), bits(f.to_local(world[k])), "to_local {n}");
                let b = warp::uniform_triangle(u);
                assert_eq!(
                    [b1[k], b2[k]].map(f32::to_bits),
                    [b.x, b.y].map(f32::to_bits),
                    "triangle {u}"
                );
            }
        }
    }
}
