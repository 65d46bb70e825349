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

/// Sobol points in the bit-reversed domain where Burley's scrambles work: for `j` the
/// bit-reversed index, `REVERSED[dim][k][b]` is the XOR, over the bits set in byte value
/// `b` at byte position `k` of `j`, of the matching direction numbers bit-reversed. So
/// `reversed_sobol(j, dim)` = reverse(sobol(reverse(j), dim)) in four table lookups, and a
/// scrambled point costs two bit reversals instead of four.
static REVERSED: [[[u32; 256]; 4]; 2] = reversed_tables();

const fn reversed_tables() -> [[[u32; 256]; 4]; 2] {
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
                        x ^= DIRECTIONS[dim][31 - (8 * k + bit)].reverse_bits();
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

/// reverse(sobol(reverse(j), dim)): Sobol dimension `dim` (0 or 1) in the reversed domain.
#[inline]
pub(super) fn reversed_sobol(j: u32, dim: usize) -> u32 {
    let t = &REVERSED[dim];
    t[0][(j & 0xff) as usize]
        ^ t[1][(j >> 8 & 0xff) as usize]
        ^ t[2][(j >> 16 & 0xff) as usize]
        ^ t[3][(j >> 24) as usize]
}

/// Laine and Karras's hash, which scrambles like Owen's nested uniform permutation when
/// applied to bit-reversed values (Burley's improved constants).
#[inline]
pub(super) fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// The scramble seeds of a key: the shuffle's and one per coordinate. The pattern is
/// already a 64-bit hash, so its halves serve for the first two.
#[inline]
fn seeds(key: &Key) -> [u32; 3] {
    [key.pattern as u32, (key.pattern >> 32) as u32, second_seed(key.pattern)]
}

/// The scramble seed of a 2D point's second coordinate, from the key's pattern
/// ([`Key::seed`]`(2)`).
#[inline]
pub(super) fn second_seed(pattern: u64) -> u32 {
    super::seed_of(pattern, 2) as u32
}

/// The shuffled index in the reversed domain: reverse(nested_uniform_scramble(index)).
#[inline]
fn shuffled_reversed(key: &Key, seed: u32) -> u32 {
    laine_karras(key.index_reversed, seed)
}

/// Coordinate `dim` of the point at reversed shuffled index `j`, Owen-scrambled.
#[inline]
fn coordinate(j: u32, dim: usize, seed: u32) -> f32 {
    to_unit(laine_karras(reversed_sobol(j, dim), seed).reverse_bits())
}

#[inline]
pub(super) fn sample_1d(key: &Key) -> f32 {
    let s = seeds(key);
    coordinate(shuffled_reversed(key, s[0]), 0, s[1])
}

#[inline]
pub(super) fn sample_2d(key: &Key) -> Vec2 {
    let s = seeds(key);
    let j = shuffled_reversed(key, s[0]);
    Vec2::new(coordinate(j, 0, s[1]), coordinate(j, 1, s[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Owen's nested uniform scramble of the bits of `x` (most significant first).
    fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
        laine_karras(x.reverse_bits(), seed).reverse_bits()
    }

    /// Point `index` of Sobol dimension `dim` by its definition: the XOR of the direction
    /// numbers of the index's set bits.
    fn sobol(index: u32, dim: usize) -> u32 {
        (0..32)
            .filter(|b| index >> b & 1 != 0)
            .fold(0, |x, b| x ^ DIRECTIONS[dim][b])
    }

    /// The reversed-domain tables give exactly Burley's scrambled, shuffled Sobol points
    /// computed from the definition.
    #[test]
    fn reversed_tables_give_the_scrambled_points_of_the_definition() {
        let mut i = 0u32;
        for step in 0..100_000u32 {
            for dim in 0..2 {
                let j = i.reverse_bits();
                assert_eq!(
                    reversed_sobol(j, dim),
                    sobol(i, dim).reverse_bits(),
                    "index {i} dim {dim}"
                );
            }
            let key = Key {
                pattern: crate::hash::mix64(step as u64),
                index: i % 4096,
                index_hash: crate::hash::mix64((i % 4096) as u64),
                index_reversed: (i % 4096).reverse_bits(),
                count: 4096,
                grid: [64, 64],
            };
            let s = seeds(&key);
            let shuffled = nested_uniform_scramble(key.index, s[0]);
            let expected = [0, 1].map(|d| to_unit(nested_uniform_scramble(sobol(shuffled, d), s[1 + d])));
            let got = sample_2d(&key);
            assert_eq!([got.x, got.y], expected, "step {step}");
            assert_eq!(sample_1d(&key), expected[0]);
            i = i.wrapping_mul(747_796_405).wrapping_add(step);
        }
    }
}
