//! Owen-scrambled Sobol points by hashing (Burley, "Practical Hash-based Owen Scrambling",
//! JCGT 2020). Each 2D request takes the first two Sobol dimensions (a (0,2)-sequence:
//! every power-of-two prefix is stratified in every elementary interval), Owen-scrambled
//! by the Laine–Karras hash with a seed from (seed, pixel, dimension), at an index shuffled
//! by the same kind of scramble, so the pairs of different dimensions do not correlate
//! ("padding", as pbrt-v4's padded Sobol sampler does).

use super::Key;
use crate::hash::u32_to_unit as to_unit;
use glam::Vec2;

/// Direction numbers of Sobol dimensions 0 and 1 (Joe and Kuo): van der Corput, and the
/// polynomial x + 1 with m = 1.
const DIRECTIONS: [[u32; 32]; 2] = directions();

const fn directions() -> [[u32; 32]; 2] {
    let mut v = [[0u32; 32]; 2];
    let mut i = 0;
    while i < 32 {
        v[0][i] = 1 << (31 - i);
        v[1][i] = if i == 0 {
            1 << 31
        } else {
            v[1][i - 1] ^ (v[1][i - 1] >> 1)
        };
        i += 1;
    }
    v
}

fn sobol(index: u32, dim: usize) -> u32 {
    let mut x = 0;
    let mut bits = index;
    let mut bit = 0;
    while bits != 0 {
        if bits & 1 != 0 {
            x ^= DIRECTIONS[dim][bit];
        }
        bits >>= 1;
        bit += 1;
    }
    x
}

/// Laine and Karras's hash, which scrambles like Owen's nested uniform permutation when
/// applied to bit-reversed values (Burley's improved constants).
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Owen's nested uniform scramble of the bits of `x` (most significant first).
pub(super) fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

fn seed(key: &Key, k: u64) -> u32 {
    key.seed(k) as u32
}

fn shuffled(key: &Key) -> u32 {
    nested_uniform_scramble(key.index, seed(key, 0))
}

pub(super) fn sample_1d(key: &Key) -> f32 {
    to_unit(nested_uniform_scramble(sobol(shuffled(key), 0), seed(key, 1)))
}

pub(super) fn sample_2d(key: &Key) -> Vec2 {
    let i = shuffled(key);
    Vec2::new(
        to_unit(nested_uniform_scramble(sobol(i, 0), seed(key, 1))),
        to_unit(nested_uniform_scramble(sobol(i, 1), seed(key, 2))),
    )
}
