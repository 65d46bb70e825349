//! [`F8Avx`]: eight `f32` lanes in one AVX register, operated on by AVX2 intrinsics; the
//! lane type of the kernels [`crate::simd`] compiles for AVX2. It performs exactly the IEEE
//! operations [`F8`](crate::lanes::F8) performs (which, in the portable build, are two SSE
//! halves), so a routine generic over [`Real`] gives the same bits with either.
//!
//! Safety: every method runs AVX2 instructions. A value of this type may only be made and
//! used inside a function compiled with `#[target_feature(enable = "avx2")]` that is
//! entered after [`crate::simd::level`] said the CPU runs AVX2; the methods are
//! `#[inline(always)]` so that they compile into that function.

#![cfg(target_arch = "x86_64")]

use crate::lanes::{Lane8, Real};
use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Eight `f32` lanes in an AVX register (see the module's safety note).
#[derive(Clone, Copy, Debug)]
pub struct F8Avx(__m256);

macro_rules! lanewise {
    ($($op:ident $f:ident $intrinsic:ident),*) => {$(
        impl $op for F8Avx {
            type Output = F8Avx;
            #[inline(always)]
            fn $f(self, o: F8Avx) -> F8Avx {
                // SAFETY: see the module's note.
                F8Avx(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    )*};
}
lanewise!(Add add _mm256_add_ps, Sub sub _mm256_sub_ps, Mul mul _mm256_mul_ps, Div div _mm256_div_ps);

impl Neg for F8Avx {
    type Output = F8Avx;
    /// Flips the sign bit, as `f32`'s negation does.
    #[inline(always)]
    fn neg(self) -> F8Avx {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
    }
}

/// A comparison of two lane vectors, quiet and ordered (false where either is NaN), as
/// `f32`'s and `wide`'s comparisons are.
macro_rules! comparisons {
    ($($f:ident $predicate:ident),*) => {$(
        #[inline(always)]
        fn $f(self, other: Self) -> __m256 {
            // SAFETY: see the module's note.
            unsafe { _mm256_cmp_ps::<$predicate>(self.0, other.0) }
        }
    )*};
}

impl Real for F8Avx {
    /// All ones or all zeros per lane.
    type Mask = __m256;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_set1_ps(v) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    /// As `wide`'s: `self` where `other` is NaN, else `maxps(self, other)` (which gives
    /// `other` where `self` is NaN or both are zeros).
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        // SAFETY: see the module's note.
        unsafe {
            let other_nan = _mm256_cmp_ps::<_CMP_UNORD_Q>(other.0, other.0);
            F8Avx(_mm256_blendv_ps(_mm256_max_ps(self.0, other.0), self.0, other_nan))
        }
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        // SAFETY: see the module's note.
        unsafe {
            let bit = _mm256_set1_ps(-0.0);
            F8Avx(_mm256_or_ps(_mm256_andnot_ps(bit, self.0), _mm256_and_ps(bit, sign.0)))
        }
    }
    comparisons!(cmp_lt _CMP_LT_OQ, cmp_le _CMP_LE_OQ, cmp_gt _CMP_GT_OQ, cmp_ge _CMP_GE_OQ, cmp_eq _CMP_EQ_OQ);
    #[inline(always)]
    fn and(a: __m256, b: __m256) -> __m256 {
        // SAFETY: see the module's note.
        unsafe { _mm256_and_ps(a, b) }
    }
    #[inline(always)]
    fn or(a: __m256, b: __m256) -> __m256 {
        // SAFETY: see the module's note.
        unsafe { _mm256_or_ps(a, b) }
    }
    #[inline(always)]
    fn not(a: __m256) -> __m256 {
        // SAFETY: see the module's note.
        unsafe { _mm256_xor_ps(a, _mm256_castsi256_ps(_mm256_set1_epi32(-1))) }
    }
    #[inline(always)]
    fn any(mask: __m256) -> bool {
        // SAFETY: see the module's note.
        unsafe { _mm256_movemask_ps(mask) != 0 }
    }
    #[inline(always)]
    fn select(mask: __m256, t: Self, f: Self) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_blendv_ps(f.0, t.0, mask) })
    }
    #[inline(always)]
    fn floor(self) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_floor_ps(self.0) })
    }
    #[inline(always)]
    fn map_lanes<const N: usize, const M: usize>(
        inputs: [Self; N],
        f: impl FnMut(usize, [f32; N]) -> [f32; M],
    ) -> [Self; M] {
        // Loops, not `array::map`: the conversions must compile into this (inlined)
        // method, at the kernel's SIMD level.
        let mut arrays = [[0.0; 8]; N];
        for (a, x) in arrays.iter_mut().zip(inputs) {
            *a = Lane8::to_array(x);
        }
        let columns = crate::lanes::map_columns(arrays, f);
        let mut out = [Self::splat(0.0); M];
        for (o, c) in out.iter_mut().zip(columns) {
            *o = Self::from_array(c);
        }
        out
    }
    /// [`Real::offset_along`] as `f32` computes it: the integer step truncated towards
    /// zero, saturated, NaN giving 0 (as `as i32` does).
    #[inline(always)]
    fn offset_along(self, n: Self) -> Self {
        // SAFETY: see the module's note.
        unsafe {
            let x = self.0;
            let near_origin = _mm256_cmp_ps::<_CMP_LT_OQ>(self.abs().0, _mm256_set1_ps(super::lanes::ORIGIN));
            let fixed = _mm256_add_ps(x, _mm256_mul_ps(_mm256_set1_ps(super::lanes::FLOAT_SCALE), n.0));
            let step = _mm256_mul_ps(_mm256_set1_ps(super::lanes::INT_SCALE), n.0);
            let truncated = _mm256_cvttps_epi32(step);
            // cvtt gives i32::MIN out of range and for NaN: saturate above, zero NaN.
            let above = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(step, _mm256_set1_ps(2147483648.0)));
            let not_nan = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_ORD_Q>(step, step));
            let of_i = _mm256_and_si256(
                _mm256_blendv_epi8(truncated, _mm256_set1_epi32(i32::MAX), above),
                not_nan,
            );
            let bits = _mm256_castps_si256(x);
            let negative = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(x, _mm256_setzero_ps()));
            let moved = _mm256_blendv_epi8(_mm256_add_epi32(bits, of_i), _mm256_sub_epi32(bits, of_i), negative);
            F8Avx(_mm256_blendv_ps(_mm256_castsi256_ps(moved), fixed, near_origin))
        }
    }
}

impl Lane8 for F8Avx {
    #[inline(always)]
    fn from_array(a: [f32; 8]) -> Self {
        // SAFETY: see the module's note; the load reads the eight floats of `a`.
        F8Avx(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let mut a = [0.0; 8];
        // SAFETY: see the module's note; the store writes the eight floats of `a`.
        unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    fn mask_of(b: [bool; 8]) -> __m256 {
        Self::from_array(b.map(|b| f32::from_bits(if b { u32::MAX } else { 0 }))).0
    }
    #[inline(always)]
    fn bits(mask: __m256) -> u32 {
        // SAFETY: see the module's note.
        unsafe { _mm256_movemask_ps(mask) as u32 }
    }
    #[inline(always)]
    fn min_or_other(self, other: Self) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_min_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn max_or_other(self, other: Self) -> Self {
        // SAFETY: see the module's note.
        F8Avx(unsafe { _mm256_max_ps(self.0, other.0) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::F8;
    use crate::simd::Level;

    /// Every operation gives `F8`'s bits (NaN payloads aside), over inputs that include
    /// zeros of both signs, NaN, infinities, subnormals and values near the offset's
    /// thresholds.
    #[test]
    fn every_operation_gives_the_portable_lanes_bits() {
        if !Level::Avx2.supported() {
            println!("note: this CPU lacks AVX2: F8Avx is not exercised");
            return;
        }
        // SAFETY: the CPU runs AVX2 (checked above).
        unsafe { compare_avx2() }
        if Level::Avx512.supported() {
            // SAFETY: the CPU runs AVX-512 (checked just above).
            unsafe { compare_avx512() }
        } else {
            println!("note: this CPU lacks AVX-512: F8Avx compiled for it is not exercised");
        }
    }

    crate::level_fns! {
        unsafe fn [compare_avx2, compare_avx512]() {
            compare()
        }
    }

    #[inline(always)]
    unsafe fn compare() {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-40,
            -1e-40,
            1.0 / 32.0,
            -1.0 / 32.0,
            0.03,
            3e9,
            -3e9,
            8.4e6,
            1e30,
            -2.5,
            7.0,
        ];
        let mut state = 0x9e37_79b9u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            if state.is_multiple_of(3) {
                special[(state / 3) as usize % special.len()]
            } else {
                f32::from_bits(state)
            }
        };
        for _ in 0..20_000 {
            let a: [f32; 8] = std::array::from_fn(|_| next());
            let b: [f32; 8] = std::array::from_fn(|_| next());
            let (pa, pb) = (F8::from(a), F8::from(b));
            let (xa, xb) = (F8Avx::from_array(a), F8Avx::from_array(b));
            // Bits, all NaNs alike: which operand's payload a NaN result carries is the
            // compiler's choice (it may swap the operands of + and *), at every level.
            let bits = |v: [f32; 8]| v.map(|x| if x.is_nan() { u32::MAX } else { x.to_bits() });
            let same = |p: F8, x: F8Avx, what: &str| {
                assert_eq!(bits(p.to_array()), bits(x.to_array()), "{what} of {a:?} and {b:?}");
            };
            same(pa + pb, xa + xb, "+");
            same(pa - pb, xa - xb, "-");
            same(pa * pb, xa * xb, "*");
            same(pa / pb, xa / xb, "/");
            same(-pa, -xa, "neg");
            same(pa.sqrt(), xa.sqrt(), "sqrt");
            same(pa.abs(), xa.abs(), "abs");
            same(pa.max(pb), xa.max(xb), "max");
            same(pa.min_or_other(pb), xa.min_or_other(xb), "min_or_other");
            same(pa.max_or_other(pb), xa.max_or_other(xb), "max_or_other");
            let minps: [f32; 8] = std::array::from_fn(|k| if a[k] < b[k] { a[k] } else { b[k] });
            let maxps: [f32; 8] = std::array::from_fn(|k| if a[k] > b[k] { a[k] } else { b[k] });
            assert_eq!(
                bits(pa.min_or_other(pb).to_array()),
                bits(minps),
                "minps of {a:?} and {b:?}"
            );
            assert_eq!(
                bits(pa.max_or_other(pb).to_array()),
                bits(maxps),
                "maxps of {a:?} and {b:?}"
            );
            same(pa.copysign(pb), xa.copysign(xb), "copysign");
            same(pa.offset_along(pb), xa.offset_along(xb), "offset_along");
            same(pa.floor(), xa.floor(), "floor");
            assert_eq!(bits(pa.floor().to_array()), bits(a.map(f32::floor)), "floor of {a:?}");
            let masks = [
                (F8::bits(pa.cmp_lt(pb)), F8Avx::bits(xa.cmp_lt(xb))),
                (F8::bits(pa.cmp_le(pb)), F8Avx::bits(xa.cmp_le(xb))),
                (F8::bits(pa.cmp_gt(pb)), F8Avx::bits(xa.cmp_gt(xb))),
                (F8::bits(pa.cmp_ge(pb)), F8Avx::bits(xa.cmp_ge(xb))),
                (F8::bits(pa.cmp_eq(pb)), F8Avx::bits(xa.cmp_eq(xb))),
                (
                    F8::bits(F8::and(pa.cmp_lt(pb), F8::not(pa.cmp_eq(pa)))),
                    F8Avx::bits(F8Avx::and(xa.cmp_lt(xb), F8Avx::not(xa.cmp_eq(xa)))),
                ),
                (
                    F8::bits(F8::or(pa.cmp_gt(pb), pa.cmp_eq(pb))),
                    F8Avx::bits(F8Avx::or(xa.cmp_gt(xb), xa.cmp_eq(xb))),
                ),
            ];
            for (k, (p, x)) in masks.into_iter().enumerate() {
                assert_eq!(p, x, "mask {k} of {a:?} and {b:?}");
            }
            same(
                F8::select(pa.cmp_lt(pb), pa, pb),
                F8Avx::select(xa.cmp_lt(xb), xa, xb),
                "select",
            );
            let bools: [bool; 8] = std::array::from_fn(|k| a[k].to_bits() & 1 == 0);
            assert_eq!(F8::bits(F8::mask_of(bools)), F8Avx::bits(F8Avx::mask_of(bools)));
        }
    }
}
