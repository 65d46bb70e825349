//! Phase functions: how a medium scatters light, per unit solid angle. Both directions
//! point away from the scattering point (pbrt-v4's convention), so light going straight
//! on is `wi = -wo`.

use glam::{Vec2, Vec3};
use penumbra_core::{trig, Frame};
use std::f32::consts::PI;

/// Henyey and Greenstein's phase function ("Diffuse radiation in the galaxy", ApJ 93,
/// 1941): p(θ) = (1 - g²) / (4π (1 + g² + 2g cos θ)^{3/2}) with cos θ = wo·wi; `g` in
/// (-1, 1) is the mean cosine of the deflection (0 isotropic, > 0 forward).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    /// A phase function of asymmetry `g`, kept inside (-0.99, 0.99) where single
    /// precision still resolves the peak.
    pub fn new(g: f32) -> Self {
        HenyeyGreenstein {
            g: g.clamp(-0.99, 0.99),
        }
    }

    /// p(wo, wi), which is also the density of [`HenyeyGreenstein::sample`].
    pub fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        hg(wo.dot(wi), self.g)
    }

    /// A direction with density p(wo, ·), and that density: cos θ by inverting the
    /// cumulative distribution (pbrt-v4's `SampleHenyeyGreenstein`), φ uniform.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let g = self.g;
        let cos = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
            -(1.0 + g * g - s * s) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (sin_phi, cos_phi) = trig::sin_cos_turns(u.y);
        let local = Vec3::new(sin * cos_phi, sin * sin_phi, cos);
        let wi = Frame::from_normal(wo).to_world(local);
        (wi, hg(cos, g))
    }
}

fn hg(cos: f32, g: f32) -> f32 {
    let d = 1.0 + g * g + 2.0 * g * cos;
    (1.0 - g * g) / (4.0 * PI * d * d.max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_testkit::chi2_directions;

    /// Sampling fits p (chi-square over the sphere, 400,000 samples), p integrates to 1,
    /// and the mean cosine of the deflection -wo·wi is g (within 4 standard errors).
    #[test]
    fn henyey_greenstein_sampling_fits_its_density() {
        let wo = Vec3::new(0.3, -0.4, 0.866).normalize();
        let gs = [-0.6f32, 0.0, 0.3, 0.85];
        for (k, &g) in gs.iter().enumerate() {
            let hg = HenyeyGreenstein::new(g);
            let r = chi2_directions(40 + k as u64, 400_000, |u| Some(hg.sample(wo, u).0), |wi| hg.p(wo, wi));
            r.assert_fits(&format!("HG g = {g}"), gs.len());
            assert!((r.integral - 1.0).abs() < 5e-3, "g = {g}: {}", r.describe());
            let mut rng = penumbra_core::Pcg32::new(9, k as u64);
            let n = 200_000;
            let (mut sum, mut sq) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let (wi, pdf) = hg.sample(wo, Vec2::new(rng.next_f32(), rng.next_f32()));
                assert!((pdf - hg.p(wo, wi)).abs() <= 1e-3 * pdf.max(1.0));
                let c = -wo.dot(wi) as f64;
                sum += c;
                sq += c * c;
            }
            let mean = sum / n as f64;
            let se = ((sq / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - g as f64).abs() < 4.0 * se + 1e-4,
                "g = {g}: mean cosine {mean} +- {se}"
            );
        }
    }
}
