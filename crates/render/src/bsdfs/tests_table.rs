//! The BSDF test table's reach: every registered kind has a case in it, and the kinds
//! whose `eval` and `pdf` are estimates (layered BSDFs) are checked in expectation: what
//! sampling puts into each bin of directions equals the bin's integral of eval |cos θi|.

use super::tests::{cases, view};
use super::*;
use penumbra_testkit::{MeanEstimate, Uniforms};
use std::f64::consts::PI;

/// Kinds a case reaches, its own and those inside blends.
fn kinds_of(material: &crate::Material, into: &mut Vec<&'static str>) {
    into.push(material.bsdf(Vec2::ZERO).kind.name());
    match material {
        crate::Material::Blend { a, b, .. } => {
            kinds_of(a, into);
            kinds_of(b, into);
        }
        crate::Material::TwoSided(inner) | crate::Material::NormalMapped { inner, .. } => kinds_of(inner, into),
        _ => {}
    }
}

#[test]
fn every_registered_bsdf_kind_is_in_the_test_table() {
    let mut covered = Vec::new();
    for (_, material, _) in cases() {
        kinds_of(&material, &mut covered);
    }
    for name in BsdfKind::NAMES {
        assert!(
            covered.contains(name),
            "BSDF kind `{name}` is registered but has no case in bsdfs/tests.rs::cases()"
        );
    }
}

/// Bins of (cos θ, φ) over the sphere: 2 x 6 in cos θ, 8 in φ.
const Z_BINS: usize = 12;
const PHI_BINS: usize = 8;
/// Directions per bin at which eval is taken, jittered on a 32 x 32 grid: walks through a
/// rough coating onto rough metal are heavy-tailed, and 96 random ones under-estimated a
/// bin's standard error twofold (2,000,000 samples and 200,000 evals then agreed).
const EVALS_PER_BIN: usize = 1024;

fn bin_of(w: Vec3) -> usize {
    let z = ((w.z as f64 + 1.0) / 2.0 * Z_BINS as f64).clamp(0.0, Z_BINS as f64 - 1.0) as usize;
    let phi = (w.y as f64).atan2(w.x as f64).rem_euclid(2.0 * PI);
    let p = (phi / (2.0 * PI) * PHI_BINS as f64).min(PHI_BINS as f64 - 1.0) as usize;
    z * PHI_BINS + p
}

/// For each stochastic kind and view: per bin, E[weight · 1(wi in bin)] over 200,000
/// samples against the bin's ∫ f |cos θi| dω by 1024 jittered directions in it (f's own
/// walk noise included in that estimate's variance, which over-states a stratified
/// estimate's: a conservative tolerance). Each bin and the total may differ by
/// 4.5 combined standard errors plus 2e-4 (for bins where both are zero but rounding);
/// 96 bins x 7 views at 4.5 sigma leave a chance near 0.5% that a correct BSDF fails
/// somewhere, and the fixed seeds make the outcome repeatable. Each sample's reported
/// density is the kind's `pdf` at its direction, bit for bit (what MIS weights rely on).
#[test]
fn stochastic_sampling_agrees_with_eval() {
    let mode = TransportMode::Radiance;
    let mut checked = 0;
    for (name, material, views) in cases() {
        let bsdf = material.bsdf(Vec2::ZERO);
        if !bsdf.stochastic() {
            continue;
        }
        for theta in views {
            let wo = view(theta);
            let mut u = Uniforms::new(11 + checked);
            let n = 200_000;
            let mut sampled = vec![(0.0f64, 0.0f64); Z_BINS * PHI_BINS];
            for _ in 0..n {
                let Some(s) = bsdf.sample(wo, u.next_f32(), u.next_vec2(), mode) else {
                    continue;
                };
                if !s.delta {
                    assert_eq!(
                        s.pdf.to_bits(),
                        bsdf.pdf(wo, s.wi, mode).to_bits(),
                        "{name} from {theta}: the sample's density is not pdf's"
                    );
                    let w = s.weight.r as f64;
                    let b = &mut sampled[bin_of(s.wi)];
                    b.0 += w;
                    b.1 += w * w;
                }
            }
            let (mut total_s, mut total_e) = (MeanEstimate::default(), 0.0f64);
            let mut total_var = 0.0f64;
            let mut total_s_var = 0.0;
            for (k, &(sum, sq)) in sampled.iter().enumerate() {
                let mean_s = sum / n as f64;
                let var_s = (sq / n as f64 - mean_s * mean_s).max(0.0) / n as f64;
                let (zb, pb) = (k / PHI_BINS, k % PHI_BINS);
                let area = 2.0 / Z_BINS as f64 * 2.0 * PI / PHI_BINS as f64;
                let mut e = MeanEstimate::default();
                for j in 0..EVALS_PER_BIN {
                    let (jz, jp) = ((j / 32) as f64, (j % 32) as f64);
                    let z = -1.0 + 2.0 * (zb as f64 + (jz + u.next_f32() as f64) / 32.0) / Z_BINS as f64;
                    let phi = 2.0 * PI * (pb as f64 + (jp + u.next_f32() as f64) / 32.0) / PHI_BINS as f64;
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    let wi = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                    e.push(bsdf.eval(wo, wi, mode).r as f64 * z.abs() * area);
                }
                let (mean_e, se_e) = (e.mean(), e.standard_error());
                let tol = 4.5 * (var_s + se_e * se_e).sqrt() + 2e-4;
                assert!(
                    (mean_s - mean_e).abs() <= tol,
                    "{name} from {theta} degrees, bin {k}: sampled {mean_s:.5}, eval {mean_e:.5} (tolerance {tol:.5})"
                );
                total_s.push(mean_s);
                total_s_var += var_s;
                total_e += mean_e;
                total_var += se_e * se_e;
            }
            let total = total_s.mean() * (Z_BINS * PHI_BINS) as f64;
            let tol = 4.5 * (total_s_var + total_var).sqrt() + 1e-3;
            assert!(
                (total - total_e).abs() <= tol,
                "{name} from {theta} degrees: albedo by sampling {total:.4}, by eval {total_e:.4} (tolerance {tol:.4})"
            );
            checked += 1;
        }
    }
    assert!(checked > 0, "the table has no stochastic BSDF");
}
