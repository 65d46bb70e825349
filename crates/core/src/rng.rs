//! The PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast
//! Space-Efficient Statistically Good Algorithms for Random Number Generation").

use crate::hash::{mix64, u32_to_unit};

const MULTIPLIER: u64 = 0x5851_f42d_4c95_7f2d;

/// PCG-XSH-RR with 64-bit state and a selectable stream.
#[derive(Clone, Debug)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// A generator for `stream`, started from `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(mix64(seed));
        rng.next_u32();
        rng
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// A uniform float in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        u32_to_unit(self.next_u32())
    }

    /// A uniform integer in [0, bound), without modulo bias.
    pub fn next_below(&mut self, bound: u32) -> u32 {
        let threshold = bound.wrapping_neg() % bound;
        loop {
            let r = self.next_u32();
            if r >= threshold {
                return r % bound;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproducible_and_uniform() {
        let mut a = Pcg32::new(7, 3);
        let mut b = Pcg32::new(7, 3);
        let mut c = Pcg32::new(7, 4);
        let xs: Vec<u32> = (0..16).map(|_| a.next_u32()).collect();
        assert_eq!(xs, (0..16).map(|_| b.next_u32()).collect::<Vec<_>>());
        assert_ne!(xs, (0..16).map(|_| c.next_u32()).collect::<Vec<_>>());
        // Mean of n uniforms: 0.5 with standard error sqrt(1/12/n) = 0.00091 for n = 1e5.
        let n = 100_000;
        let mean = (0..n).map(|_| a.next_f32() as f64).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 4.0 * 0.00091, "mean {mean}");
        assert!((0..1000).all(|_| a.next_below(7) < 7));
    }
}
