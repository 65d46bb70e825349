//! The primary sample space of Kelemen et al., "A Simple and Robust Mutation Strategy for
//! the Metropolis Light Transport Algorithm" (Eurographics 2002): a path is the image of
//! a vector of uniform numbers, and the Markov chain mutates the vector. A large step
//! draws every number afresh; a small step moves each by a normal offset of standard
//! deviation `sigma`, wrapped into [0, 1). Numbers are made lazily, as the path asks for
//! them, with the mutations they missed applied at once (pbrt-v4's `MLTSampler`): n small
//! steps missed are one step of σ√n, and a large step since their last change means a
//! fresh number. Three interleaved streams (camera, light, connection) keep a change in
//! one subpath's length from shifting the numbers of the others.

use glam::Vec2;
use penumbra_core::{Draws, Pcg32};

/// One coordinate of the primary sample vector, with its value before the mutation in
/// flight (to restore on rejection).
#[derive(Clone, Copy, Debug)]
struct Coordinate {
    value: f32,
    modified: u64,
    backup: f32,
    backup_modified: u64,
}

/// `modified` of a coordinate never drawn: its first read makes it uniform.
const NEVER: u64 = u64::MAX;

impl Default for Coordinate {
    fn default() -> Self {
        Coordinate {
            value: 0.0,
            modified: NEVER,
            backup: 0.0,
            backup_modified: NEVER,
        }
    }
}

/// The streams the numbers are drawn from, interleaved in the vector.
const STREAMS: usize = 3;

#[derive(Clone, Debug)]
pub struct PrimarySamples {
    rng: Pcg32,
    sigma: f32,
    large_step_probability: f32,
    x: Vec<Coordinate>,
    iteration: u64,
    large_step: bool,
    last_large_step: u64,
    stream: usize,
    index: usize,
}

impl PrimarySamples {
    /// A vector whose numbers come from the random stream (`seed`, `stream`): the same
    /// arguments give the same vector and the same mutations.
    pub fn new(seed: u64, stream: u64, sigma: f32, large_step_probability: f32) -> Self {
        PrimarySamples {
            rng: Pcg32::new(seed, stream),
            sigma,
            large_step_probability,
            x: Vec::new(),
            iteration: 0,
            large_step: true,
            last_large_step: 0,
            stream: 0,
            index: 0,
        }
    }

    /// Starts a mutation: large with the large-step probability, else small.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.rng.next_f32() < self.large_step_probability;
        self.stream = 0;
        self.index = 0;
    }

    /// Whether the mutation in flight is a large step.
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Keeps the mutated vector.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// Restores the vector from before the mutation.
    pub fn reject(&mut self) {
        for c in &mut self.x {
            if c.modified == self.iteration {
                (c.value, c.modified) = (c.backup, c.backup_modified);
            }
        }
        self.iteration -= 1;
    }

    /// Gives the chain a random stream of its own (`seed`, `stream`) for its mutations
    /// from now on: chains started from the same bootstrap state then part ways.
    pub fn reseed(&mut self, seed: u64, stream: u64) {
        self.rng = Pcg32::new(seed, stream);
    }

    /// A uniform number from the chain's own generator (acceptance tests, choices).
    pub fn uniform(&mut self) -> f32 {
        self.rng.next_f32()
    }

    /// Brings coordinate `i` up to the current iteration.
    fn ready(&mut self, i: usize) -> f32 {
        if i >= self.x.len() {
            self.x.resize(i + 1, Coordinate::default());
        }
        let c = &mut self.x[i];
        // A number never drawn, or last drawn before the latest large step, is uniform.
        if c.modified == NEVER || c.modified < self.last_large_step {
            (c.value, c.modified) = (self.rng.next_f32(), self.last_large_step);
        }
        (c.backup, c.backup_modified) = (c.value, c.modified);
        if self.large_step {
            c.value = self.rng.next_f32();
        } else {
            let missed = self.iteration.saturating_sub(c.modified).max(1) as f32;
            let normal = std::f32::consts::SQRT_2 * erf_inv(2.0 * self.rng.next_f32() - 1.0);
            let v = c.value + normal * self.sigma * missed.sqrt();
            c.value = v - v.floor();
            if c.value >= 1.0 {
                c.value = 0.0;
            }
        }
        c.modified = self.iteration;
        c.value
    }
}

impl Draws for PrimarySamples {
    fn next_1d(&mut self) -> f32 {
        let i = self.stream + STREAMS * self.index;
        self.index += 1;
        self.ready(i)
    }

    fn next_2d(&mut self) -> Vec2 {
        let x = self.next_1d();
        Vec2::new(x, self.next_1d())
    }

    fn start_stream(&mut self, k: usize) {
        self.stream = k;
        self.index = 0;
    }
}

/// The inverse error function, from Giles, "Approximating the erfinv function" (GPU
/// Computing Gems, 2011), single-precision version.
pub fn erf_inv(x: f32) -> f32 {
    let x = x.clamp(-0.99999, 0.99999);
    let mut w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        w -= 2.5;
        let mut p = 2.810_226_4e-08;
        for c in [
            3.432_739_4e-07,
            -3.523_387_7e-06,
            -4.391_506_5e-06,
            0.000_218_580_87,
            -0.001_253_725,
            -0.004_177_681_6,
            0.246_640_72,
            1.501_409_4,
        ] {
            p = c + p * w;
        }
        p
    } else {
        w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_26;
        for c in [
            0.000_100_950_56,
            0.001_349_343_2,
            -0.003_673_428_4,
            0.005_739_507_7,
            -0.007_622_461,
            0.009_438_870_5,
            1.001_674_2,
            2.832_976_8,
        ] {
            p = c + p * w;
        }
        p
    };
    p * x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_inv_inverts_erf() {
        // erf by its Taylor-free numerical integral: erf(y) = 2/√π ∫0^y e^{-t²} dt.
        for y in [-2.0f64, -1.0, -0.3, 0.0, 0.2, 0.9, 1.7] {
            let n = 20_000;
            let h = y / n as f64;
            let erf: f64 = (0..n).map(|i| (-(h * (i as f64 + 0.5)).powi(2)).exp() * h).sum::<f64>() * 2.0
                / std::f64::consts::PI.sqrt();
            let back = erf_inv(erf as f32) as f64;
            assert!((back - y).abs() < 2e-3 * (1.0 + y.abs()), "{y}: {back}");
        }
    }

    /// Rejected mutations restore the vector exactly; accepted ones keep it; large steps
    /// renew every coordinate as it is next read, small ones stay close.
    #[test]
    fn mutations_restore_and_move() {
        let mut s = PrimarySamples::new(3, 1, 0.01, 0.0);
        // The first path is read before any mutation: a large step.
        let first: Vec<f32> = (0..6).map(|_| s.next_1d()).collect();
        s.accept();
        s.start_iteration();
        let moved: Vec<f32> = (0..6).map(|_| s.next_1d()).collect();
        s.reject();
        s.start_iteration();
        s.reject();
        // After the rejections the stored vector holds the accepted values again (stream 0's
        // numbers sit at every third place).
        let stored: Vec<f32> = s.x.iter().step_by(STREAMS).map(|c| c.value).collect();
        assert_eq!(stored, first);
        for (a, b) in first.iter().zip(&moved) {
            let d = (a - b).abs().min(1.0 - (a - b).abs());
            assert!(d > 0.0 && d < 0.08, "{a} -> {b}");
        }
    }
}
