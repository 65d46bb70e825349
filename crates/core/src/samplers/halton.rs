//! Owen-scrambled Halton points: each 2D request takes the radical inverses in bases 2 and
//! 3 (Halton 1964) of the sample's index, with every digit permuted by a hash of the digits
//! above it (Owen's nested scrambling, as pbrt-v4's `OwenScrambledRadicalInverse` does; in
//! base 2 by one Laine-Karras hash, as the Sobol sampler scrambles), at an index permuted
//! within the pixel's samples (Kensler's permutation) so that the pairs of different
//! dimensions do not correlate.

use super::sobol::laine_karras;
use super::stratified::permute;
use super::{Key, ONE_MINUS_EPSILON};
use crate::hash::{mix64, u32_to_unit as to_unit};
use glam::Vec2;

/// The radical inverse of `a` in base 2, Owen-scrambled: the base-2 radical inverse is the
/// bit reversal of `a`, and Owen's nested scramble of a bit-reversed value is the
/// Laine-Karras hash of the unreversed one (Burley 2020), so one hash does the work of a
/// digit-by-digit scramble.
fn scrambled_radical_inverse_2(a: u32, seed: u64) -> f32 {
    to_unit(laine_karras(a, seed as u32).reverse_bits())
}

/// The radical inverse of `a` in `base`, each digit permuted by a hash of `seed` and the
/// digits below it in `a` (the ones above it in the result), down to float precision.
fn scrambled_radical_inverse(mut a: u32, base: u32, seed: u64) -> f32 {
    let inv_base = 1.0 / base as f64;
    let (mut inv_base_m, mut reversed, mut k) = (1.0f64, 0u64, 0u64);
    // Digits until they fall below f32 precision (24 bits).
    while inv_base_m > 1.0 / (1u64 << 26) as f64 {
        let digit = a % base;
        a /= base;
        // The permutation depends on the digits above and on the position: prefixes of
        // different lengths with the same value ("0" and "00") must not share one.
        let hash = mix64(seed ^ reversed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ k << 58) as u32;
        k += 1;
        reversed = reversed * base as u64 + permute_digit(digit, base, hash) as u64;
        inv_base_m *= inv_base;
    }
    ((reversed as f64 * inv_base_m) as f32).min(ONE_MINUS_EPSILON)
}

/// One of the `base!` permutations of a digit, chosen by `hash` with equal probability
/// (Kensler's hash permutation is not uniform over the permutations of two or three items).
fn permute_digit(digit: u32, base: u32, hash: u32) -> u32 {
    const PERMUTATIONS_3: [[u32; 3]; 6] = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
    match base {
        2 => digit ^ (hash & 1),
        3 => PERMUTATIONS_3[(hash % 6) as usize][digit as usize],
        _ => permute(digit, base, hash),
    }
}

/// The index permuted within its block of `count` samples (blocks beyond the first serve
/// progressive renders that go past the planned count).
fn index(key: &Key) -> u32 {
    let block = key.index / key.count * key.count;
    block + permute(key.index - block, key.count, key.seed(0) as u32)
}

pub(super) fn sample_1d(key: &Key) -> f32 {
    scrambled_radical_inverse_2(index(key), key.seed(1))
}

pub(super) fn sample_2d(key: &Key) -> Vec2 {
    let i = index(key);
    Vec2::new(
        scrambled_radical_inverse_2(i, key.seed(1)),
        scrambled_radical_inverse(i, 3, key.seed(2)),
    )
}
