//! Independent uniform random numbers: SplitMix64 (Steele, Lea and Flood, "Fast Splittable
//! Pseudorandom Number Generators", OOPSLA 2014) over the dimensions of one pixel sample,
//! its sequence seeded by the hashes of the pixel and of the sample index: one 64-bit mix
//! per draw, a pure function of (seed, pixel, sample index, dimension).

use crate::hash::{mix64, u32_to_unit};
use crate::simd::Level;
use glam::Vec2;

/// SplitMix64's increment, the odd integer nearest 2^64 / golden ratio.
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// The 64 bits of dimension `d` of the sample keyed `key` (the pixel's hash xor the
/// sample index's): SplitMix64's output at step `d + 1` of the sequence seeded with `key`.
#[inline(always)]
fn bits(key: u64, d: u32) -> u64 {
    mix64(key.wrapping_add((d as u64 + 1).wrapping_mul(GAMMA)))
}

#[inline]
pub(super) fn sample_1d(key: u64, d: u32) -> f32 {
    u32_to_unit(bits(key, d) as u32)
}

#[inline]
pub(super) fn sample_2d(key: u64, d: u32) -> Vec2 {
    let b = bits(key, d);
    Vec2::new(u32_to_unit(b as u32), u32_to_unit((b >> 32) as u32))
}

/// Eight samplers' state for [`sample_lanes`]: lane `k` is the sample keyed `key[k]`
/// (see [`bits`]) at dimension `dims[k]`.
pub(super) struct LaneKeys {
    pub key: [u64; 8],
    pub dims: [u32; 8],
}

/// The numbers of eight samplers at once: lane `k` is what [`sample_2d`] (with `two`, else
/// [`sample_1d`] in `x` and 0 in `y`) gives for dimension `dims[k] + offset` of its keys.
/// The same integer operations per lane, written so that the compiler turns the loop into
/// SIMD code at the CPU's level (64-bit lane products where AVX-512 has them), so every
/// level gives the same bits.
#[inline]
pub(super) fn sample_lanes(keys: &LaneKeys, offset: u32, two: bool) -> ([f32; 8], [f32; 8]) {
    // SAFETY: the CPU runs the level's instructions (checked when the level was set).
    #[cfg(target_arch = "x86_64")]
    match crate::simd::level() {
        Level::Avx512 => return unsafe { lanes_avx512(keys, offset, two) },
        Level::Avx2 => return unsafe { lanes_avx2(keys, offset, two) },
        Level::Sse2 => {}
    }
    lanes(keys, offset, two)
}

#[cfg(target_arch = "x86_64")]
crate::level_fns! {
    unsafe fn [lanes_avx2, lanes_avx512](keys: &LaneKeys, offset: u32, two: bool) -> ([f32; 8], [f32; 8]) {
        lanes(keys, offset, two)
    }
}

#[inline(always)]
fn lanes(keys: &LaneKeys, offset: u32, two: bool) -> ([f32; 8], [f32; 8]) {
    let mut lane_bits = [0u64; 8];
    for (k, b) in lane_bits.iter_mut().enumerate() {
        *b = bits(keys.key[k], keys.dims[k] + offset);
    }
    let (mut x, mut y) = ([0.0; 8], [0.0; 8]);
    for k in 0..8 {
        x[k] = u32_to_unit(lane_bits[k] as u32);
    }
    if two {
        for k in 0..8 {
            y[k] = u32_to_unit((lane_bits[k] >> 32) as u32);
        }
    }
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every level's lanes give the numbers drawing one key at a time gives, for any
    /// offset, in 1D and 2D.
    #[test]
    fn lanes_at_every_level_are_the_scalar_draws() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state = mix64(state);
            state
        };
        for round in 0..2_000u32 {
            let key: [u64; 8] = std::array::from_fn(|_| next());
            let dims: [u32; 8] = std::array::from_fn(|k| (next() % 64) as u32 + k as u32);
            let keys = LaneKeys { key, dims };
            let (offset, two) = (round % 5, round % 2 == 0);
            let mut expected = ([0.0f32; 8], [0.0f32; 8]);
            for k in 0..8 {
                if two {
                    let p = sample_2d(key[k], dims[k] + offset);
                    (expected.0[k], expected.1[k]) = (p.x, p.y);
                } else {
                    expected.0[k] = sample_1d(key[k], dims[k] + offset);
                }
            }
            let bits = |v: ([f32; 8], [f32; 8])| (v.0.map(f32::to_bits), v.1.map(f32::to_bits));
            let want = bits(expected);
            assert_eq!(bits(lanes(&keys, offset, two)), want, "portable, round {round}");
            #[cfg(target_arch = "x86_64")]
            {
                if Level::Avx2.supported() {
                    // SAFETY: the CPU runs AVX2 (checked just above).
                    let got = unsafe { lanes_avx2(&keys, offset, two) };
                    assert_eq!(bits(got), want, "avx2, round {round}");
                }
                if Level::Avx512.supported() {
                    // SAFETY: the CPU runs AVX-512 (checked just above).
                    let got = unsafe { lanes_avx512(&keys, offset, two) };
                    assert_eq!(bits(got), want, "avx512, round {round}");
                }
            }
        }
    }
}
