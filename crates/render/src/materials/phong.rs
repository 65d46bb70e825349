//! The classic ray-tracing material of Whitted (1980) and the course: a diffuse and
//! Phong-glossy local reflection, plus perfect mirror reflection and Fresnel-weighted
//! refraction, combined in any proportion.
//!
//! Native format (`type = "phong"`), every key optional:
//! - `diffuse` (colour or texture, default `[0.8, 0.8, 0.8]`): Lambertian albedo, f = kd / pi.
//! - `specular` (colour, default black) and `exponent` (default 32): energy-normalised Phong
//!   lobe f = ks (n + 2) / (2 pi) cos^n(alpha) (Lafortune and Willems 1994), alpha the angle
//!   between the mirror direction of the light and the viewer.
//! - `mirror` (colour, default black): weight of the perfect mirror reflection ray.
//! - `transmission` (colour, default black): weight of the dielectric interface, which
//!   reflects a fraction F and refracts 1 - F (exact Fresnel), totally reflecting beyond
//!   the critical angle.
//! - `ior` (default 1.5) inside the surface, `ior_outside` (default 1.0) outside it.

use crate::bsdfs::PhongBsdf;
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Phong {
    pub diffuse: Texture,
    pub specular: Rgb,
    pub exponent: f32,
    pub mirror: Rgb,
    pub transmission: Rgb,
    pub ior: f32,
    pub ior_outside: f32,
}

impl Default for Phong {
    fn default() -> Self {
        Phong {
            diffuse: Texture::Constant(Rgb::splat(0.8)),
            specular: Rgb::BLACK,
            exponent: 32.0,
            mirror: Rgb::BLACK,
            transmission: Rgb::BLACK,
            ior: 1.5,
            ior_outside: 1.0,
        }
    }
}

impl Phong {
    /// The BSDF at texture coordinates `uv`: both-sided diffuse and glossy lobes, with the
    /// mirror and the dielectric interface as delta lobes.
    pub fn bsdf(&self, uv: Vec2) -> PhongBsdf {
        PhongBsdf {
            diffuse: self.diffuse.eval(uv),
            specular: self.specular,
            exponent: self.exponent,
            mirror: self.mirror,
            transmission: self.transmission,
            eta: self.ior / self.ior_outside,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::{Bsdf, BsdfKind, TransportMode};
    use glam::Vec3;
    use std::f32::consts::PI;

    const MODE: TransportMode = TransportMode::Radiance;

    fn glass() -> Phong {
        Phong {
            diffuse: Texture::Constant(Rgb::BLACK),
            transmission: Rgb::WHITE,
            ..Phong::default()
        }
    }

    fn bsdf(m: &Phong) -> Bsdf<'static> {
        Bsdf::one_sided(BsdfKind::Phong(m.bsdf(Vec2::ZERO)))
    }

    #[test]
    fn glass_splits_by_fresnel() {
        let rays = bsdf(&glass()).specular_rays(Vec3::Z, MODE);
        let rays = rays.as_slice();
        assert_eq!(rays.len(), 2);
        assert!((rays[0].weight.r - 0.04).abs() < 1e-6 && rays[0].wi == Vec3::Z);
        assert!((rays[1].weight.r - 0.96 / 2.25).abs() < 1e-6 && (rays[1].wi - Vec3::NEG_Z).length() < 1e-6);
    }

    #[test]
    fn total_internal_reflection_from_inside() {
        // Viewed from inside the glass at 60 degrees from the normal: beyond 41.8, all reflects.
        let t = 60f32.to_radians();
        let wo = Vec3::new(t.sin(), 0.0, -t.cos());
        let rays = bsdf(&glass()).specular_rays(wo, MODE);
        let rays = rays.as_slice();
        assert_eq!(rays.len(), 1);
        assert_eq!(rays[0].weight, Rgb::WHITE);
        assert!(rays[0].wi.z < 0.0, "reflected back inside");
    }

    /// The diffuse + glossy sampling fits its density (chi-square over the sphere), for
    /// diffuse, glossy and mixed materials at normal and oblique views, from either side.
    #[test]
    fn sampling_fits_its_density() {
        let mixed = |kd: f32, ks: f32, n: f32| Phong {
            diffuse: Texture::Constant(Rgb::splat(kd)),
            specular: Rgb::splat(ks),
            exponent: n,
            ..Phong::default()
        };
        let cases = [
            (mixed(0.8, 0.0, 1.0), 0.0f32),
            (mixed(0.0, 0.9, 20.0), 0.0),
            (mixed(0.0, 0.9, 20.0), 1.2),
            (mixed(0.3, 0.6, 5.0), 0.7),
            (mixed(0.5, 0.5, 200.0), 1.0),
            (mixed(0.0, 0.7, 0.0), 0.4),
            (mixed(0.3, 0.6, 5.0), 2.5),
        ];
        for (seed, (m, theta)) in cases.iter().enumerate() {
            let wo = Vec3::new(theta.sin(), 0.05, theta.cos()).normalize();
            let mut lobe = penumbra_testkit::Uniforms::new(100 + seed as u64);
            let b = bsdf(m);
            let r = penumbra_testkit::chi2_directions(
                seed as u64,
                300_000,
                |u| b.sample(wo, lobe.next_f32(), u, MODE).map(|s| s.wi),
                |wi| b.pdf(wo, wi, MODE),
            );
            r.assert_fits(
                &format!(
                    "Phong kd {:?} ks {:?} n {} at {theta}",
                    m.diffuse, m.specular, m.exponent
                ),
                cases.len(),
            );
            assert!(r.integral <= 1.0 + 1e-3, "{}", r.describe());
        }
    }

    #[test]
    fn phong_lobe_is_energy_normalised() {
        // Directional albedo of the lobe at normal incidence: integral of f cos over the
        // hemisphere = ks (n + 2)/(2 pi) * 2 pi / (n + 2) = ks, by midpoint quadrature in theta.
        let m = Phong {
            diffuse: Texture::Constant(Rgb::BLACK),
            specular: Rgb::WHITE,
            exponent: 20.0,
            ..Phong::default()
        };
        let b = bsdf(&m);
        let steps = 20_000;
        let mut sum = 0.0;
        for i in 0..steps {
            let theta = (i as f32 + 0.5) / steps as f32 * PI / 2.0;
            let wi = Vec3::new(theta.sin(), 0.0, theta.cos());
            let f = b.eval(Vec3::Z, wi, MODE).r;
            sum += f * theta.cos() * theta.sin() * 2.0 * PI * (PI / 2.0 / steps as f32);
        }
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }
}
