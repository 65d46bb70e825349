//! Reflection, refraction and the Fresnel equations for dielectrics.
//!
//! Directions point away from the surface (`wi`, `wo`), and `n` is on the side of the
//! incident direction; `eta` is the relative index `n_t / n_i` (transmitted over incident).

use glam::Vec3;
use penumbra_core::lanes::{Real, V3};

/// Mirror reflection of `wo` about `n`.
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// The refracted direction by Snell's law, `None` on total internal reflection.
/// `wi` and `n` on the same side; the result is on the other side of the surface.
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let (t, ok) = refract_lanes(wi.into(), n.into(), eta);
    ok.then(|| t.into())
}

/// [`refract`] over lanes of any [`Real`] type: the direction, and where it exists.
#[inline(always)]
pub fn refract_lanes<R: Real>(wi: V3<R>, n: V3<R>, eta: R) -> (V3<R>, R::Mask) {
    let one = R::splat(1.0);
    let cos_i = wi.dot(n);
    let sin2_t = (one - cos_i * cos_i).max(R::splat(0.0)) / (eta * eta);
    let cos_t = (one - sin2_t).sqrt();
    let t = (-wi).div_by(eta) + n.scale(cos_i / eta - cos_t);
    (t, R::not(sin2_t.cmp_ge(one)))
}

/// Unpolarised Fresnel reflectance of a dielectric interface (the exact equations, e.g.
/// pbrt-v4 eq. 9.5-9.6) for incidence cosine `cos_i` in [0, 1]; 1 on total internal reflection.
/// Written over [`Real`], for one path or for lanes.
#[inline(always)]
pub fn fresnel_dielectric<R: Real>(cos_i: R, eta: R) -> R {
    let one = R::splat(1.0);
    let cos_i = clamp_unit(cos_i);
    let sin2_t = (one - cos_i * cos_i) / (eta * eta);
    let cos_t = (one - sin2_t).sqrt();
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let f = R::splat(0.5) * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
    R::select(sin2_t.cmp_ge(one), one, f)
}

/// Unpolarised Fresnel reflectance of a conductor of complex relative index `eta + i k`
/// for incidence cosine `cos_i` (the exact equations, as in pbrt-v3's `FrConductor` and
/// Mitsuba's `fresnel_conductor`); written over [`Real`], for one path or for lanes.
#[inline(always)]
pub fn fresnel_conductor<R: Real>(cos_i: R, eta: R, k: R) -> R {
    let c = R::splat;
    let cos = clamp_unit(cos_i);
    let cos2 = cos * cos;
    let sin2 = c(1.0) - cos2;
    let t0 = eta * eta - k * k - sin2;
    let a2_plus_b2 = (t0 * t0 + c(4.0) * eta * eta * k * k).max(c(0.0)).sqrt();
    let a = (c(0.5) * (a2_plus_b2 + t0)).max(c(0.0)).sqrt();
    let t1 = a2_plus_b2 + cos2;
    let t2 = c(2.0) * a * cos2.sqrt();
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = a2_plus_b2 * cos2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    let r = c(0.5) * (rs + rp);
    R::select(r.abs().cmp_lt(c(f32::INFINITY)), clamp_unit(r), c(1.0))
}

/// `x` clamped to [0, 1] (NaN stays NaN, as `f32::clamp` leaves it).
#[inline(always)]
pub fn clamp_unit<R: Real>(x: R) -> R {
    let (zero, one) = (R::splat(0.0), R::splat(1.0));
    R::select(x.cmp_lt(zero), zero, R::select(x.cmp_gt(one), one, x))
}

/// Hemispherical average of the dielectric Fresnel reflectance, 2 ∫ F(μ, η) μ dμ: the
/// fraction of diffuse light an interface of relative index `eta` reflects (total internal
/// reflection included when `eta` < 1). Midpoint rule on 1024 cells: error below 1e-6.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    const N: usize = 1024;
    let sum: f64 = (0..N)
        .map(|i| {
            let mu = (i as f64 + 0.5) / N as f64;
            fresnel_dielectric(mu as f32, eta) as f64 * mu
        })
        .sum();
    (2.0 * sum / N as f64) as f32
}

/// The critical angle (radians) beyond which light inside a medium of relative index
/// `1 / eta` (`eta` < 1) is totally reflected.
pub fn critical_angle(eta: f32) -> Option<f32> {
    (eta < 1.0).then(|| eta.asin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conductor_fresnel_limits() {
        // k = 0 is a dielectric; normal incidence is ((η-1)² + k²) / ((η+1)² + k²); grazing is 1.
        for c in [0.1, 0.5, 0.9, 1.0] {
            assert!((fresnel_conductor(c, 1.5, 0.0) - fresnel_dielectric(c, 1.5)).abs() < 1e-5);
        }
        let (eta, k) = (0.2, 3.9);
        let normal = ((eta - 1.0f32).powi(2) + k * k) / ((eta + 1.0f32).powi(2) + k * k);
        assert!((fresnel_conductor(1.0, eta, k) - normal).abs() < 1e-5);
        assert!((fresnel_conductor(0.0, eta, k) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn diffuse_fresnel_reflectance_matches_known_values() {
        // Glass from outside reflects about 9.2% of diffuse light; from inside, total
        // internal reflection adds 1 - 1/η² of it: 1 - (1 - 0.0918)/1.5² = 0.5963.
        let outside = fresnel_diffuse_reflectance(1.5);
        assert!((outside - 0.0918).abs() < 5e-4, "{outside}");
        let inside = fresnel_diffuse_reflectance(1.0 / 1.5);
        assert!((inside - (1.0 - (1.0 - outside) / 2.25)).abs() < 1e-4, "{inside}");
    }

    #[test]
    fn normal_incidence_glass_reflects_four_percent() {
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Same from the inside.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
    }

    #[test]
    fn critical_angle_and_total_internal_reflection() {
        let theta_c = critical_angle(1.0 / 1.5).unwrap().to_degrees();
        assert!((theta_c - 41.81).abs() < 0.005, "{theta_c}");
        let n = Vec3::Z;
        for (deg, tir) in [(41.7, false), (41.9, true), (60.0, true), (10.0, false)] {
            let t = (deg as f32).to_radians();
            let wi = Vec3::new(t.sin(), 0.0, t.cos());
            assert_eq!(refract(wi, n, 1.0 / 1.5).is_none(), tir, "{deg} degrees");
            assert_eq!(fresnel_dielectric(t.cos(), 1.0 / 1.5) == 1.0, tir, "{deg} degrees");
        }
        assert!(critical_angle(1.5).is_none());
    }

    #[test]
    fn snell_and_reflection_identities() {
        let n = Vec3::Z;
        for deg in [0.0f32, 15.0, 30.0, 60.0, 89.0] {
            let t = deg.to_radians();
            let wi = Vec3::new(t.sin(), 0.0, t.cos());
            let r = reflect(wi, n);
            assert!((r.length() - 1.0).abs() < 1e-6 && (r.z - wi.z).abs() < 1e-6 && (r.x + wi.x).abs() < 1e-6);
            let eta = 1.5;
            let wt = refract(wi, n, eta).unwrap();
            assert!((wt.length() - 1.0).abs() < 1e-5);
            assert!(wt.z < 0.0);
            // n_i sin(theta_i) = n_t sin(theta_t).
            let sin_t = (wt.x * wt.x + wt.y * wt.y).sqrt();
            assert!((t.sin() - eta * sin_t).abs() < 1e-5);
            // Refracting back reverses the path.
            let back = refract(wt, -n, 1.0 / eta).unwrap();
            assert!((back - wi).length() < 1e-4, "{back} vs {wi}");
        }
    }

    #[test]
    fn reflectance_and_transmittance_sum_to_one() {
        // R + T = 1 with T from the transmitted Fresnel amplitudes, with the beam-area
        // factor: T = (n_t cos_t / n_i cos_i) (t_s^2 + t_p^2) / 2.
        for eta in [1.33f32, 1.5, 2.4, 1.0 / 1.5] {
            for deg in [0.0f32, 20.0, 40.0, 41.0, 70.0, 89.0] {
                let cos_i = deg.to_radians().cos();
                let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
                if sin2_t >= 1.0 {
                    continue;
                }
                let cos_t = (1.0 - sin2_t).sqrt();
                let t_s = 2.0 * cos_i / (cos_i + eta * cos_t);
                let t_p = 2.0 * cos_i / (eta * cos_i + cos_t);
                let transmitted = eta * cos_t / cos_i * 0.5 * (t_s * t_s + t_p * t_p);
                let r = fresnel_dielectric(cos_i, eta);
                assert!(
                    (r + transmitted - 1.0).abs() < 1e-5,
                    "eta {eta} at {deg}: R {r} T {transmitted}"
                );
            }
        }
    }
}
