//! A path's four wavelengths: hero-wavelength sampling (Wilkie, Nawaz, Droske, Weidlich and
//! Hanika 2014) with the three others rotated by quarters of the unit interval, each drawn
//! from pbrt-v4's distribution over the visible range, p(λ) ∝ 1/cosh²(0.0072 (λ − 538))
//! on [360, 830] nm (Pharr, Jakob and Humphreys, 4th edition, section 5.4.2), which
//! Mitsuba 3's spectral variants also use. Radiance at the four becomes XYZ by the
//! Monte Carlo estimate of ∫ L x̄ dλ / ∫ ȳ dλ.

use super::cie::{self, CIE_Y_INTEGRAL, LAMBDA_MAX, LAMBDA_MIN};

/// How many wavelengths a path carries.
pub const N: usize = 4;

/// Four wavelengths (nanometres) and their densities; a density of 0 marks a wavelength
/// dropped (after a dispersive refraction only the hero, the first, is kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wavelengths {
    pub lambda: [f32; N],
    pub pdf: [f32; N],
}

/// The wavelength of the visible distribution at `u` in [0, 1) (its inverse CDF).
#[inline]
pub fn sample_visible(u: f32) -> f32 {
    538.0 - 138.888_89 * (0.856_910_6 - 1.827_502 * u).atanh()
}

/// The density of [`sample_visible`] at `lambda`.
#[inline]
pub fn visible_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let c = (0.0072 * (lambda - 538.0)).cosh();
    0.003_939_804 / (c * c)
}

impl Wavelengths {
    /// The hero wavelength at `u` and three more at `u` + 1/4, 2/4, 3/4 (mod 1).
    pub fn sample_visible(u: f32) -> Self {
        let mut lambda = [0.0; N];
        let mut pdf = [0.0; N];
        for i in 0..N {
            let mut up = u + i as f32 / N as f32;
            if up >= 1.0 {
                up -= 1.0;
            }
            lambda[i] = sample_visible(up).clamp(LAMBDA_MIN, LAMBDA_MAX);
            pdf[i] = visible_pdf(lambda[i]);
        }
        Wavelengths { lambda, pdf }
    }

    /// Keeps the hero wavelength alone (as after a dispersive refraction): the others'
    /// densities become 0 and the hero's is divided by [`N`], so the estimate stays unbiased.
    pub fn keep_hero_only(&mut self) {
        if self.is_hero_only() {
            return;
        }
        for p in &mut self.pdf[1..] {
            *p = 0.0;
        }
        self.pdf[0] /= N as f32;
    }

    /// Whether only the hero wavelength is left.
    pub fn is_hero_only(&self) -> bool {
        self.pdf[1..].iter().all(|&p| p == 0.0)
    }

    /// The XYZ of radiance `values` at these wavelengths: the mean of L x̄ / p over them,
    /// over ∫ȳ (dropped wavelengths count as zeros).
    pub fn to_xyz(&self, values: [f32; N]) -> [f32; 3] {
        let mut xyz = [0.0f32; 3];
        for ((&v, &p), &lambda) in values.iter().zip(&self.pdf).zip(&self.lambda) {
            if p == 0.0 {
                continue;
            }
            let w = v / p;
            let bar = cie::xyz_bar(lambda);
            for c in 0..3 {
                xyz[c] += w * bar[c];
            }
        }
        xyz.map(|c| c / (N as f32 * CIE_Y_INTEGRAL))
    }

    /// The linear sRGB of radiance `values` at these wavelengths.
    pub fn to_srgb(&self, values: [f32; N]) -> [f32; 3] {
        cie::apply(&cie::XYZ_TO_SRGB, self.to_xyz(values))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Pcg32;

    /// The density integrates to 1 and the sampler follows it (chi-square over 47 bins of
    /// 10 nm, 200,000 draws, expected counts computed from the density).
    #[test]
    fn visible_wavelengths_follow_their_density() {
        let integral: f64 = (0..47_000)
            .map(|i| visible_pdf(360.0 + (i as f32 + 0.5) * 0.01) as f64 * 0.01)
            .sum();
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
        let mut rng = Pcg32::new(3, 5);
        let n = 200_000;
        let mut counts = [0f64; 47];
        for _ in 0..n {
            let l = sample_visible(rng.next_f32());
            counts[(((l - 360.0) / 10.0) as usize).min(46)] += 1.0;
        }
        let chi2: f64 = (0..47)
            .map(|b| {
                let expected: f64 = (0..100)
                    .map(|k| visible_pdf(360.0 + b as f32 * 10.0 + (k as f32 + 0.5) * 0.1) as f64 * 0.1)
                    .sum::<f64>()
                    * n as f64;
                (counts[b] - expected).powi(2) / expected
            })
            .sum();
        // 46 degrees of freedom: the 99.9% quantile is 81.4.
        assert!(chi2 < 81.4, "chi-square {chi2}");
    }

    /// The estimate of XYZ from four wavelengths averages to the integral: D65 (Y = 1) to
    /// within 3 standard errors; dropping all but the hero keeps the mean.
    #[test]
    fn four_wavelengths_estimate_xyz_without_bias() {
        let exact = cie::xyz_of(cie::d65_unit);
        for hero_only in [false, true] {
            let mut rng = Pcg32::new(11, 2);
            let n = 100_000;
            let (mut sum, mut sum2) = ([0f64; 3], [0f64; 3]);
            for _ in 0..n {
                let mut wl = Wavelengths::sample_visible(rng.next_f32());
                if hero_only {
                    wl.keep_hero_only();
                }
                let xyz = wl.to_xyz(wl.lambda.map(cie::d65_unit));
                for c in 0..3 {
                    sum[c] += xyz[c] as f64;
                    sum2[c] += (xyz[c] as f64).powi(2);
                }
            }
            for c in 0..3 {
                let mean = sum[c] / n as f64;
                let se = ((sum2[c] / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - exact[c] as f64).abs() < 3.0 * se + 1e-4,
                    "hero only {hero_only}, channel {c}: {mean} ± {se} against {}",
                    exact[c]
                );
            }
        }
    }
}
