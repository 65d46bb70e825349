//! Phase functions: how a medium scatters light, per unit solid angle. Both directions
//! point away from the scattering point (pbrt-v4's convention), so light going straight
//! on is `wi = -wo`.

use glam::{Vec2, Vec3};
use penumbra_core::frame::Basis;
use penumbra_core::lanes::{Real, V3};
use penumbra_core::trig;
use std::f32::consts::PI;

/// Every phase function a medium may have. Both sample exactly their density, so a
/// sample's weight p/pdf is 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Phase {
    /// The same in every direction: 1/(4π).
    Isotropic,
    HenyeyGreenstein(HenyeyGreenstein),
}

impl Phase {
    /// The name of each kind, as scenes spell it (Mitsuba's `isotropic` and `hg`).
    pub const NAMES: [&'static str; 2] = ["isotropic", "hg"];

    /// p(wo, wi), which is also the density of [`Phase::sample`].
    pub fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Phase::Isotropic => 0.25 / PI,
            Phase::HenyeyGreenstein(hg) => hg.p(wo, wi),
        }
    }

    /// A direction with density p(wo, ·), and that density.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        match self {
            Phase::Isotropic => (penumbra_core::warp::uniform_sphere(u), 0.25 / PI),
            Phase::HenyeyGreenstein(hg) => hg.sample(wo, u),
        }
    }
}

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
        hg(V3::from(wo).dot(wi.into()), self.g)
    }

    /// A direction with density p(wo, ·), and that density (the one-lane instance of
    /// [`sample_hg`]).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let (wi, p) = sample_hg(self.g, wo.into(), (u.x, u.y));
        (wi.into(), p)
    }
}

/// The phase function's value for the cosine `cos` of the angle between wo and wi, per lane
/// of any [`Real`] type.
#[inline(always)]
pub fn hg<R: Real>(cos: R, g: R) -> R {
    let one = R::splat(1.0);
    let d = one + g * g + R::splat(2.0) * g * cos;
    (one - g * g) / (R::splat(4.0 * PI) * d * d.max(R::splat(0.0)).sqrt())
}

/// A direction about `wo` with density p(wo, ·) for the asymmetry `g` (kept inside
/// (-0.99, 0.99) by [`HenyeyGreenstein::new`]), and that density, per lane: cos θ by
/// inverting the cumulative distribution (pbrt-v4's `SampleHenyeyGreenstein`), φ uniform.
#[inline(always)]
pub fn sample_hg<R: Real>(g: R, wo: V3<R>, u: (R, R)) -> (V3<R>, R) {
    let (one, two) = (R::splat(1.0), R::splat(2.0));
    let isotropic = g.abs().cmp_lt(R::splat(1e-3));
    let s = (one - g * g) / (one + g - two * g * u.0);
    let cos = R::select(isotropic, one - two * u.0, -(one + g * g - s * s) / (two * g));
    // As f32::clamp(-1, 1) (a NaN stays NaN).
    let cos = R::select(cos.cmp_lt(-one), -one, cos);
    let cos = R::select(cos.cmp_gt(one), one, cos);
    let sin = (one - cos * cos).max(R::splat(0.0)).sqrt();
    let (sin_phi, cos_phi) = trig::sin_cos_turns(u.1);
    let local = V3::new(sin * cos_phi, sin * sin_phi, cos);
    (Basis::from_normal(wo).to_world(local), hg(cos, g))
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_testkit::chi2_directions;

    /// Both kinds of [`Phase`] sample their density (chi-square over the sphere) and
    /// their densities integrate to 1.
    #[test]
    fn every_phase_function_samples_its_density() {
        let wo = Vec3::new(-0.2, 0.9, 0.1).normalize();
        let kinds = [Phase::Isotropic, Phase::HenyeyGreenstein(HenyeyGreenstein::new(0.7))];
        assert_eq!(kinds.len(), Phase::NAMES.len());
        for (k, phase) in kinds.iter().enumerate() {
            let r = chi2_directions(
                70 + k as u64,
                200_000,
                |u| Some(phase.sample(wo, u).0),
                |wi| phase.p(wo, wi),
            );
            r.assert_fits(Phase::NAMES[k], kinds.len());
            assert!((r.integral - 1.0).abs() < 5e-3, "{}: {}", Phase::NAMES[k], r.describe());
            let (wi, pdf) = phase.sample(wo, Vec2::new(0.3, 0.6));
            assert!((pdf - phase.p(wo, wi)).abs() < 1e-4 * pdf, "{}", Phase::NAMES[k]);
        }
    }

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
