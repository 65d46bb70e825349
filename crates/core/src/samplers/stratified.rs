//! Stratified samples after Kensler, "Correlated Multi-Jittered Sampling" (Pixar technical
//! memo 13-01, 2013): any sample count, each sample computed on its own from its index.

use super::{Key, ONE_MINUS_EPSILON};
use glam::Vec2;

/// Sample `index` of `count` jittered strata of [0, 1), the strata visited in a random order.
pub(super) fn sample_1d(key: &Key) -> f32 {
    let p = key.pattern as u32;
    let stratum = permute(key.index, key.count, p.wrapping_mul(0x51633e2d));
    let jitter = rand_float(key.index, p.wrapping_mul(0x68bc21eb));
    ((stratum as f32 + jitter) / key.count as f32).min(ONE_MINUS_EPSILON)
}

/// Kensler's correlated multi-jittered 2D pattern (listing 6 of the memo), aspect ratio 1.
pub(super) fn sample_2d(key: &Key) -> Vec2 {
    let p = key.pattern as u32;
    let n_total = key.count;
    let [m, n] = key.grid;
    let s = permute(key.index, n_total, p.wrapping_mul(0x51633e2d));
    let sx = permute(s % m, m, p.wrapping_mul(0x68bc21eb));
    let sy = permute(s / m, n, p.wrapping_mul(0x02e5be93));
    let jx = rand_float(s, p.wrapping_mul(0x967a889b));
    let jy = rand_float(s, p.wrapping_mul(0x368cc8b7));
    let x = (sx as f32 + (sy as f32 + jx) / n as f32) / m as f32;
    let y = (s as f32 + jy) / n_total as f32;
    Vec2::new(x.min(ONE_MINUS_EPSILON), y.min(ONE_MINUS_EPSILON))
}

/// A pseudo-random permutation of [0, l) indexed by `i`, keyed by `p` (Kensler, listing 3).
pub(super) fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    if l <= 1 {
        return 0;
    }
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dcb303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e501cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    // Kensler's final `(i + p) % l` as a rotation by an offset drawn from `p` by a
    // multiply-high (Lemire 2019) instead of a division: still a permutation of [0, l).
    let offset = ((p as u64 * l as u64) >> 32) as u32;
    let j = i as u64 + offset as u64;
    (if j >= l as u64 { j - l as u64 } else { j }) as u32
}

/// The `m` x `n` grid of Kensler's 2D pattern for `count` samples: m = floor(sqrt(count)),
/// n = ceil(count / m). Computed once per sampler.
pub(super) fn grid(count: u32) -> [u32; 2] {
    let m = ((count as f32).sqrt() as u32).max(1);
    [m, count.div_ceil(m)]
}

/// A hashed float in [0, 1) (Kensler, listing 4).
fn rand_float(mut i: u32, p: u32) -> f32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb36534e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc4795);
    i ^= 0xdf6e307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | p >> 18);
    crate::hash::u32_to_unit(i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permute_is_a_permutation() {
        for l in [1, 2, 3, 10, 64, 100] {
            let mut seen: Vec<u32> = (0..l).map(|i| permute(i, l, 0xdead_beef)).collect();
            seen.sort();
            assert_eq!(seen, (0..l).collect::<Vec<_>>());
        }
    }
}
