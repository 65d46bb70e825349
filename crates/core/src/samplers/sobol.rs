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
/// polynomial x + 1 with m = 1 (the definition the closed forms below are tested against).
#[cfg(test)]
const DIRECTIONS: [[u32; 32]; 2] = directions();

#[cfg(test)]
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

/// reverse(sobol(reverse(j), dim)): Sobol dimension `dim` (0 or 1) in the bit-reversed
/// domain where Burley's scrambles work, so a scrambled point costs two bit reversals
/// instead of four. Dimension 0 (van der Corput) is reverse(j); dimension 1 is
/// [`pascal`] of it.
#[inline]
pub(super) fn reversed_sobol(j: u32, dim: usize) -> u32 {
    let a = j.reverse_bits();
    if dim == 0 {
        a
    } else {
        pascal(a)
    }
}

/// The shift and mask of each of [`pascal`]'s steps.
pub(super) const PASCAL_STEPS: [(u32, u32); 5] = [
    (1, 0x5555_5555),
    (2, 0x3333_3333),
    (4, 0x0f0f_0f0f),
    (8, 0x00ff_00ff),
    (16, 0x0000_ffff),
];

/// Sobol's second dimension from the reversed index `a`: its generator is the Pascal
/// matrix mod 2 (entry (i, k) is 1 where the bits of i are a subset of those of k, by
/// Lucas's theorem), and in the reversed domain its product with a vector is the
/// subset-XOR (zeta) transform over the five bits of a bit position: five shift-mask-XOR
/// steps instead of the 32 direction numbers.
#[inline]
pub(super) fn pascal(a: u32) -> u32 {
    PASCAL_STEPS.iter().fold(a, |y, &(shift, mask)| y ^ (y >> shift) & mask)
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
pub(super) fn coordinate(j: u32, dim: usize, seed: u32) -> f32 {
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

    /// The reversed-domain closed forms give exactly Burley's scrambled, shuffled Sobol
    /// points computed from the definition.
    #[test]
    fn closed_forms_give_the_scrambled_points_of_the_definition() {
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
