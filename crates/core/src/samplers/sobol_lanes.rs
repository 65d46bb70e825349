//! The Sobol sampler's points for eight pixel samples at once: the Laine–Karras scrambles,
//! the bit reversals and the dimension-1 transform of [`super::sobol`] in AVX2 integer
//! lanes (byte shuffles for the reversals), the same integer operations, so each lane's
//! point is bit for bit the scalar one. Below [`crate::simd::Level::Avx2`] the lanes are
//! computed one by one by the scalar code.

use super::sobol::{coordinate, laine_karras, second_seed};
use crate::simd::Level;

/// The 2D points of eight keys, given by their patterns and reversed sample indices:
/// `(x, y)` per lane as [`super::sobol::sample_2d`] computes them; with `two == false` only
/// `x` (then [`super::sobol::sample_1d`]'s value) and `y` is zero.
#[inline]
pub(super) fn sample_lanes(pattern: &[u64; 8], index_reversed: &[u32; 8], two: bool) -> ([f32; 8], [f32; 8]) {
    sample_lanes_at(crate::simd::level(), pattern, index_reversed, two)
}

/// [`sample_lanes`] with the kernels of `level`, which the CPU must run.
#[inline]
fn sample_lanes_at(level: Level, pattern: &[u64; 8], index_reversed: &[u32; 8], two: bool) -> ([f32; 8], [f32; 8]) {
    debug_assert!(level.supported());
    // SAFETY: the CPU runs the level's instructions (`Level::supported`, checked when the
    // level was set).
    #[cfg(target_arch = "x86_64")]
    match level {
        Level::Avx512 => return unsafe { avx2::sample_lanes_avx512(pattern, index_reversed, two) },
        Level::Avx2 => return unsafe { avx2::sample_lanes_avx2(pattern, index_reversed, two) },
        Level::Sse2 => {}
    }
    scalar(pattern, index_reversed, two)
}

/// The lanes one by one (the reference, and the code without AVX2).
fn scalar(pattern: &[u64; 8], index_reversed: &[u32; 8], two: bool) -> ([f32; 8], [f32; 8]) {
    let (mut x, mut y) = ([0.0; 8], [0.0; 8]);
    for k in 0..8 {
        let j = laine_karras(index_reversed[k], pattern[k] as u32);
        x[k] = coordinate(j, 0, (pattern[k] >> 32) as u32);
        if two {
            y[k] = coordinate(j, 1, second_seed(pattern[k]));
        }
    }
    (x, y)
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::super::sobol::PASCAL_STEPS;
    use super::second_seed;
    use core::arch::x86_64::*;

    /// [`super::laine_karras`] in eight lanes.
    #[inline(always)]
    unsafe fn laine_karras(x: __m256i, seed: __m256i) -> __m256i {
        let mut x = _mm256_add_epi32(x, seed);
        for c in [0x6c50_b47cu32, 0xb82f_1e52, 0xc7af_e638, 0x8d22_f6e6] {
            x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(c as i32)));
        }
        x
    }

    /// `u32::reverse_bits` in eight lanes: the bytes of each lane reversed, then the bits
    /// of each byte by two 16-entry nibble tables.
    #[inline(always)]
    unsafe fn reverse_bits(x: __m256i) -> __m256i {
        #[rustfmt::skip]
        let bswap = _mm256_setr_epi8(
            3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,
            3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,
        );
        // Nibble n with its four bits reversed, and that shifted to the high nibble.
        #[rustfmt::skip]
        let (low, high) = (
            _mm256_setr_epi8(
                0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf,
                0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf,
            ),
            _mm256_setr_epi8(
                0x00, 0x80u8 as i8, 0x40, 0xc0u8 as i8, 0x20, 0xa0u8 as i8, 0x60, 0xe0u8 as i8,
                0x10, 0x90u8 as i8, 0x50, 0xd0u8 as i8, 0x30, 0xb0u8 as i8, 0x70, 0xf0u8 as i8,
                0x00, 0x80u8 as i8, 0x40, 0xc0u8 as i8, 0x20, 0xa0u8 as i8, 0x60, 0xe0u8 as i8,
                0x10, 0x90u8 as i8, 0x50, 0xd0u8 as i8, 0x30, 0xb0u8 as i8, 0x70, 0xf0u8 as i8,
            ),
        );
        let x = _mm256_shuffle_epi8(x, bswap);
        let nibble = _mm256_set1_epi8(0x0f);
        let lo = _mm256_and_si256(x, nibble);
        let hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), nibble);
        _mm256_or_si256(_mm256_shuffle_epi8(high, lo), _mm256_shuffle_epi8(low, hi))
    }

    /// [`super::super::sobol::pascal`] in eight lanes.
    #[inline(always)]
    unsafe fn pascal(a: __m256i) -> __m256i {
        PASCAL_STEPS.iter().fold(a, |y, &(shift, mask)| {
            let moved = _mm256_srlv_epi32(y, _mm256_set1_epi32(shift as i32));
            _mm256_xor_si256(y, _mm256_and_si256(moved, _mm256_set1_epi32(mask as i32)))
        })
    }

    /// [`crate::hash::u32_to_unit`] in eight lanes (exact: the top 24 bits convert
    /// exactly and the scale is a power of two).
    #[inline(always)]
    unsafe fn to_unit(x: __m256i) -> [f32; 8] {
        let v = _mm256_mul_ps(
            _mm256_cvtepi32_ps(_mm256_srli_epi32(x, 8)),
            _mm256_set1_ps(1.0 / (1u32 << 24) as f32),
        );
        std::mem::transmute(v)
    }

    #[inline(always)]
    unsafe fn load(v: [u32; 8]) -> __m256i {
        _mm256_loadu_si256(v.as_ptr() as *const __m256i)
    }

    crate::level_fns! {
        /// [`super::sample_lanes`] compiled for AVX2 and for AVX-512.
        pub(super) unsafe fn [sample_lanes_avx2, sample_lanes_avx512](p: &[u64; 8], i: &[u32; 8], two: bool) -> ([f32; 8], [f32; 8]) {
            sample_lanes(p, i, two)
        }
    }

    /// [`super::sample_lanes`] in AVX2 integer lanes.
    #[inline(always)]
    unsafe fn sample_lanes(pattern: &[u64; 8], index_reversed: &[u32; 8], two: bool) -> ([f32; 8], [f32; 8]) {
        let s0 = load(pattern.map(|p| p as u32));
        let s1 = load(pattern.map(|p| (p >> 32) as u32));
        let j = laine_karras(load(*index_reversed), s0);
        // `reversed_sobol`: reverse(j) for dimension 0, its `pascal` for dimension 1.
        let a = reverse_bits(j);
        let x = to_unit(reverse_bits(laine_karras(a, s1)));
        if !two {
            return (x, [0.0; 8]);
        }
        let s2 = load(pattern.map(second_seed));
        let y = to_unit(reverse_bits(laine_karras(pascal(a), s2)));
        (x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::mix64;
    use crate::samplers::Key;

    /// Eight lanes give the scalar sampler's floats bit for bit, for patterns and indices
    /// over the whole 32 and 64 bits (reversals and scrambles of every bit position).
    #[test]
    fn lanes_equal_the_scalar_points() {
        let levels: Vec<Level> = Level::ALL.into_iter().filter(|l| l.supported()).collect();
        for l in Level::ALL.iter().filter(|l| !l.supported()) {
            println!("note: this CPU lacks {l}: its lanes are not checked here");
        }
        for round in 0..20_000u64 {
            let pattern = std::array::from_fn(|k| mix64(round * 8 + k as u64));
            let index_reversed = std::array::from_fn(|k| mix64(!(round * 8 + k as u64)) as u32);
            let keys: [Key; 8] = std::array::from_fn(|k| Key {
                pattern: pattern[k],
                index: index_reversed[k].reverse_bits(),
                index_reversed: index_reversed[k],
                count: 1 << 20,
                grid: [1024, 1024],
            });
            let points = keys.map(|k| super::super::sobol::sample_2d(&k));
            let ones = keys.map(|k| super::super::sobol::sample_1d(&k));
            assert_eq!(scalar(&pattern, &index_reversed, true).0, points.map(|p| p.x));
            assert_eq!(scalar(&pattern, &index_reversed, true).1, points.map(|p| p.y));
            assert_eq!(scalar(&pattern, &index_reversed, false).0, ones);
            for two in [false, true] {
                let want = scalar(&pattern, &index_reversed, two);
                for &l in &levels {
                    let got = sample_lanes_at(l, &pattern, &index_reversed, two);
                    assert_eq!(got.0.map(f32::to_bits), want.0.map(f32::to_bits), "{l} round {round}");
                    assert_eq!(got.1.map(f32::to_bits), want.1.map(f32::to_bits), "{l} round {round}");
                }
            }
        }
    }
}
