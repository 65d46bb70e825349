//! The statistical test kit every sampling routine in Penumbra passes: a chi-square
//! goodness-of-fit test of samples against the density the routine claims (the test
//! Mitsuba 3's `ChiSquareTest` and pbrt-v4's `ChiSquareTest` run), which also measures the
//! density's integral over the domain (it must be 1, or the fraction of directions a light
//! covers).
//!
//! The domain is a rectangle cut into equal bins; directions use (cos θ, φ), in which equal
//! bins have equal solid angle and a solid-angle density needs no Jacobian. The expected
//! count of a bin is the sample count times the density's integral over the bin (an open
//! Gauss–Legendre rule across, adaptive Simpson along; see [`integrate_2d`]), so densities
//! with edges (a cone's rim) are integrated accurately. Bins expecting fewer than five samples are pooled; a sample in a bin whose
//! density integrates to zero fails at once. The statistic is compared with the chi-square
//! distribution (via `statrs`) at a significance level corrected for the number of tests
//! run (Šidák).

pub mod furnace;
mod mean;
mod quadrature;

pub use mean::{assert_within_3se, assert_within_se, MeanEstimate};

use glam::{Vec2, Vec3};
use std::f64::consts::PI;

pub use quadrature::integrate_2d;

/// A uniform random point in the unit square, from SplitMix64: enough for tests, and
/// independent of the renderer's own generators so a flaw there cannot hide itself.
pub struct Uniforms(u64);

impl Uniforms {
    pub fn new(seed: u64) -> Self {
        Uniforms(seed)
    }
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }
    pub fn next_vec2(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }
}

/// The outcome of one chi-square test.
#[derive(Clone, Debug)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The density's integral over the whole domain (sum of the bins' integrals).
    pub integral: f64,
    /// Why the test failed before any statistic, if it did.
    pub error: Option<String>,
}

impl Chi2 {
    /// Whether the samples fit the density at significance `alpha`, corrected for `tests`
    /// tests run together: reject when p < 1 - (1 - alpha)^(1/tests).
    pub fn passes(&self, alpha: f64, tests: usize) -> bool {
        self.error.is_none() && self.p_value >= 1.0 - (1.0 - alpha).powf(1.0 / tests.max(1) as f64)
    }

    /// Panics with the figures unless the test passes at 1% over `tests` tests.
    pub fn assert_fits(&self, what: &str, tests: usize) {
        assert!(
            self.passes(0.01, tests),
            "{what}: samples do not fit the density: {}",
            self.describe()
        );
    }

    pub fn describe(&self) -> String {
        match &self.error {
            Some(e) => e.clone(),
            None => format!(
                "chi2 = {:.1} with {} degrees of freedom, p = {:.3e}; density integrates to {:.5}",
                self.statistic, self.dof, self.p_value, self.integral
            ),
        }
    }
}

/// A rectangle `[min, max]` cut into `bins[0] x bins[1]` equal bins.
#[derive(Clone, Copy, Debug)]
pub struct Grid2 {
    pub min: [f64; 2],
    pub max: [f64; 2],
    pub bins: [usize; 2],
}

impl Grid2 {
    fn bin_of(&self, p: [f64; 2]) -> Option<usize> {
        let mut index = [0usize; 2];
        for a in 0..2 {
            let x = (p[a] - self.min[a]) / (self.max[a] - self.min[a]);
            if !(0.0..=1.0).contains(&x) {
                return None;
            }
            index[a] = ((x * self.bins[a] as f64) as usize).min(self.bins[a] - 1);
        }
        Some(index[1] * self.bins[0] + index[0])
    }

    fn bin_bounds(&self, i: usize) -> ([f64; 2], [f64; 2]) {
        let (ix, iy) = (i % self.bins[0], i / self.bins[0]);
        let w = [
            (self.max[0] - self.min[0]) / self.bins[0] as f64,
            (self.max[1] - self.min[1]) / self.bins[1] as f64,
        ];
        let lo = [self.min[0] + ix as f64 * w[0], self.min[1] + iy as f64 * w[1]];
        (lo, [lo[0] + w[0], lo[1] + w[1]])
    }
}

/// Chi-square test of `n` samples (points of `grid`'s rectangle, `None` for a sample the
/// routine rejected) against `pdf`, a density over the rectangle's area.
pub fn chi2_test(
    grid: Grid2,
    n: usize,
    mut sample: impl FnMut() -> Option<[f64; 2]>,
    pdf: impl Fn([f64; 2]) -> f64,
) -> Chi2 {
    let bins = grid.bins[0] * grid.bins[1];
    let mut observed = vec![0f64; bins];
    let fail = |e: String| Chi2 {
        statistic: f64::NAN,
        dof: 0,
        p_value: 0.0,
        integral: f64::NAN,
        error: Some(e),
    };
    for _ in 0..n {
        if let Some(p) = sample() {
            if p.iter().any(|x| !x.is_finite()) {
                return fail(format!("a sample is not finite: {p:?}"));
            }
            match grid.bin_of(p) {
                Some(b) => observed[b] += 1.0,
                None => return fail(format!("a sample {p:?} lies outside the domain")),
            }
        }
    }
    let integrals: Vec<f64> = (0..bins)
        .map(|i| {
            let (lo, hi) = grid.bin_bounds(i);
            integrate_2d(&pdf, lo, hi)
        })
        .collect();
    let integral: f64 = integrals.iter().sum();
    // Pool the bins expecting few samples, smallest first, into one bin.
    let mut order: Vec<usize> = (0..bins).collect();
    order.sort_by(|&a, &b| integrals[a].total_cmp(&integrals[b]));
    let (mut statistic, mut cells) = (0.0, 0usize);
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for i in order {
        let expected = integrals[i] * n as f64;
        if expected <= 0.0 {
            if observed[i] > 0.0 {
                let (lo, hi) = grid.bin_bounds(i);
                return fail(format!(
                    "{} samples in the bin {lo:?}..{hi:?}, where the density is zero",
                    observed[i]
                ));
            }
            continue;
        }
        if expected < 5.0 {
            pool_obs += observed[i];
            pool_exp += expected;
            if pool_exp >= 5.0 {
                statistic += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
                cells += 1;
                (pool_obs, pool_exp) = (0.0, 0.0);
            }
            continue;
        }
        statistic += (observed[i] - expected) * (observed[i] - expected) / expected;
        cells += 1;
    }
    if pool_exp > 0.0 {
        // What is left over joins the statistic as one more cell.
        statistic += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        cells += 1;
    }
    if cells < 2 {
        return fail("fewer than two bins expect samples: use more samples or fewer bins".into());
    }
    let dof = cells - 1;
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let p_value = ChiSquared::new(dof as f64).map_or(0.0, |d| d.sf(statistic));
    Chi2 {
        statistic,
        dof,
        p_value,
        integral,
        error: None,
    }
}

/// Chi-square test of a direction sampler against its solid-angle density: `n` samples
/// of `sample(u)` for uniform `u` (seeded), binned in (cos θ, φ) over the whole sphere
/// (10 x 20 bins).
pub fn chi2_directions(
    seed: u64,
    n: usize,
    mut sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) -> Chi2 {
    let grid = Grid2 {
        min: [-1.0, 0.0],
        max: [1.0, 2.0 * PI],
        bins: [10, 20],
    };
    let mut u = Uniforms::new(seed);
    chi2_test(
        grid,
        n,
        || sample(u.next_vec2()).map(|w| direction_coords(w.normalize())),
        |[z, phi]| {
            let r = (1.0 - z * z).max(0.0).sqrt();
            pdf(Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32)) as f64
        },
    )
}

/// (cos θ, φ in [0, 2π)) of a unit direction.
fn direction_coords(w: Vec3) -> [f64; 2] {
    let phi = (w.y as f64).atan2(w.x as f64);
    [
        (w.z as f64).clamp(-1.0, 1.0),
        if phi < 0.0 { phi + 2.0 * PI } else { phi },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI as PI32;

    /// The kit's own uniform sphere: it does not depend on the renderer it tests.
    fn uniform_sphere(u: Vec2) -> Vec3 {
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI32 * u.y;
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    #[test]
    fn a_right_density_passes_and_integrates_to_one() {
        let r = chi2_directions(1, 200_000, |u| Some(uniform_sphere(u)), |_| 1.0 / (4.0 * PI32));
        r.assert_fits("uniform sphere", 1);
        assert!((r.integral - 1.0).abs() < 1e-6, "{}", r.describe());
    }

    #[test]
    fn wrong_densities_and_stray_samples_fail() {
        // The uniform sphere tested against cos-weighted and slightly tilted densities.
        let cosine = chi2_directions(2, 200_000, |u| Some(uniform_sphere(u)), |w| w.z.max(0.0) / PI32);
        assert!(!cosine.passes(0.01, 1), "{}", cosine.describe());
        let tilted = chi2_directions(
            3,
            200_000,
            |u| Some(uniform_sphere(u)),
            |w| (1.0 + 0.1 * w.x) / (4.0 * PI32),
        );
        assert!(!tilted.passes(0.01, 1), "{}", tilted.describe());
        // A hemisphere sampler claiming the upper hemisphere but leaking below it.
        let leaky = chi2_directions(
            4,
            50_000,
            |u| {
                let w = uniform_sphere(u);
                Some(if u.y < 0.99 { Vec3::new(w.x, w.y, w.z.abs()) } else { w })
            },
            |w| if w.z >= 0.0 { 1.0 / (2.0 * PI32) } else { 0.0 },
        );
        assert!(leaky.error.is_some(), "{}", leaky.describe());
    }

    #[test]
    fn the_significance_level_holds_under_the_null_hypothesis() {
        // With a right density, p-values are uniform: at 5% about 1 test in 20 rejects.
        // 200 tests: expected 10 rejections, standard deviation sqrt(200 * 0.05 * 0.95) = 3.1;
        // accept 2 to 22 (beyond 3.9 standard deviations either side).
        let rejected = (0..200)
            .filter(|&seed| {
                !chi2_directions(100 + seed, 20_000, |u| Some(uniform_sphere(u)), |_| 1.0 / (4.0 * PI32))
                    .passes(0.05, 1)
            })
            .count();
        assert!((2..=22).contains(&rejected), "{rejected} of 200 rejected at 5%");
    }
}
