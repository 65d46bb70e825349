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

/// The contribution of each byte of an index to a Sobol point: `BYTES[dim][k][b]` is the
/// XOR of the direction numbers of the bits set in byte value `b` at byte position `k`, so a
/// point is four table lookups instead of a loop over up to 32 bits.
static BYTES: [[[u32; 256]; 4]; 2] = byte_tables();

const fn byte_tables() -> [[[u32; 256]; 4]; 2] {
    let mut t = [[[0u32; 256]; 4]; 2];
    let mut dim = 0;
    while dim < 2 {
        let mut k = 0;
        while k < 4 {
            let mut b = 0;
            while b < 256 {
                let mut x = 0;
                let mut bit = 0;
                while bit < 8 {
                    if b & (1 << bit) != 0 {
                        x ^= DIRECTIONS[dim][8 * k + bit];
                    }
                    bit += 1;
                }
                t[dim][k][b] = x;
                b += 1;
            }
            k += 1;
        }
        dim += 1;
    }
    t
}

/// Point `index` of Sobol dimension `dim` (0 or 1), as a 32-bit fixed-point fraction.
#[inline]
fn sobol(index: u32, dim: usize) -> u32 {
    let t = &BYTES[dim];
    t[0][(index & 0xff) as usize]
        ^ t[1][(index >> 8 & 0xff) as usize]
        ^ t[2][(index >> 16 & 0xff) as usize]
        ^ t[3][(index >> 24) as usize]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables give exactly the bit-by-bit definition of a Sobol point.
    #[test]
    fn table_lookup_equals_the_bit_loop() {
        let by_bits = |index: u32, dim: usize| {
            (0..32)
                .filter(|b| index >> b & 1 != 0)
                .fold(0, |x, b| x ^ DIRECTIONS[dim][b])
        };
        let mut i = 0u32;
        for step in 0..100_000u32 {
            for dim in 0..2 {
                assert_eq!(sobol(i, dim), by_bits(i, dim), "index {i} dim {dim}");
            }
            i = i.wrapping_mul(747_796_405).wrapping_add(step);
        }
        assert_eq!(sobol(0, 1), 0);
        assert_eq!(sobol(u32::MAX, 0), u32::MAX);
    }
}
