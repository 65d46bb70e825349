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

use crate::optics::{fresnel_dielectric, reflect, refract};
use crate::Texture;
use glam::{Vec2, Vec3};
use penumbra_core::{warp, Frame, Rgb};
use std::f32::consts::PI;

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

/// A secondary ray the material asks for: its direction and weight.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpecularRay {
    pub wi: Vec3,
    pub weight: Rgb,
}

impl Phong {
    /// The local BRDF f(wo, wi) without the cosine; `n` is the shading normal on the side
    /// of `wo`.
    pub fn eval(&self, uv: Vec2, n: Vec3, wo: Vec3, wi: Vec3) -> Rgb {
        let diffuse = self.diffuse.eval(uv) / PI;
        if self.specular.is_black() {
            return diffuse;
        }
        // Zero outside the lobe's hemisphere (also for exponent 0, where 0^0 would be 1).
        let cos_alpha = reflect(wi, n).dot(wo);
        if cos_alpha <= 0.0 {
            return diffuse;
        }
        diffuse + self.specular * ((self.exponent + 2.0) / (2.0 * PI) * cos_alpha.powf(self.exponent))
    }

    /// Probabilities of sampling the diffuse and the glossy lobe at `uv`: in proportion to
    /// their albedos' luminance; `None` when the material has neither (pure specular).
    fn lobe_probabilities(&self, uv: Vec2) -> Option<(f32, f32)> {
        let d = self.diffuse.eval(uv).luminance().max(0.0);
        let s = self.specular.luminance().max(0.0);
        (d + s > 0.0).then(|| (d / (d + s), s / (d + s)))
    }

    /// Whether the material has a non-specular (diffuse or glossy) part at `uv`.
    pub fn has_lobes(&self, uv: Vec2) -> bool {
        self.lobe_probabilities(uv).is_some()
    }

    /// A direction for the diffuse + glossy part, drawn from the mixture of a cosine-weighted
    /// hemisphere about `n` and the Phong lobe about the mirror direction of `wo` (density
    /// [`Phong::pdf`]); `u_lobe` picks the lobe. `None` when there is nothing to sample or
    /// the glossy lobe points below the surface.
    pub fn sample(&self, uv: Vec2, n: Vec3, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<Vec3> {
        let (pd, _) = self.lobe_probabilities(uv)?;
        let wi = if u_lobe < pd {
            Frame::from_normal(n).to_world(warp::cosine_hemisphere(u))
        } else {
            Frame::from_normal(reflect(wo, n)).to_world(warp::phong_lobe(u, self.exponent))
        };
        (wi.dot(n) > 0.0).then_some(wi)
    }

    /// Solid-angle density of [`Phong::sample`] at `wi`.
    pub fn pdf(&self, uv: Vec2, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        let Some((pd, ps)) = self.lobe_probabilities(uv) else {
            return 0.0;
        };
        let cos = wi.dot(n);
        if cos <= 0.0 {
            return 0.0;
        }
        let mut pdf = pd * cos / PI;
        if ps > 0.0 {
            pdf += ps * warp::phong_lobe_pdf(Vec3::new(0.0, 0.0, reflect(wo, n).dot(wi)), self.exponent);
        }
        pdf
    }

    pub fn albedo(&self, uv: Vec2) -> Rgb {
        self.diffuse.eval(uv)
    }

    /// The perfectly specular rays leaving the surface towards `wo`: mirror reflection,
    /// and for a transmissive material the Fresnel-weighted reflection and refraction.
    /// `n` is the shading normal on the outside of the surface, `wo` the unit direction
    /// towards the viewer. Radiance crossing into a denser medium is scaled by
    /// `(eta_i / eta_t)^2` (pbrt-v4, section 9.5.2).
    pub fn specular_rays(&self, n: Vec3, wo: Vec3) -> impl Iterator<Item = SpecularRay> {
        let entering = wo.dot(n) > 0.0;
        let n_wo = if entering { n } else { -n };
        let mirror = (!self.mirror.is_black()).then(|| SpecularRay {
            wi: reflect(wo, n_wo),
            weight: self.mirror,
        });
        let (mut fresnel_reflect, mut fresnel_refract) = (None, None);
        if !self.transmission.is_black() {
            // eta = n_t / n_i for light going from the wo side to the other.
            let eta = if entering {
                self.ior / self.ior_outside
            } else {
                self.ior_outside / self.ior
            };
            let cos_o = wo.dot(n_wo);
            let f = fresnel_dielectric(cos_o, eta);
            fresnel_reflect = Some(SpecularRay {
                wi: reflect(wo, n_wo),
                weight: self.transmission * f,
            });
            if f < 1.0 {
                fresnel_refract = refract(wo, n_wo, eta).map(|wi| SpecularRay {
                    wi,
                    weight: self.transmission * ((1.0 - f) / (eta * eta)),
                });
            }
        }
        mirror.into_iter().chain(fresnel_reflect).chain(fresnel_refract)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass() -> Phong {
        Phong {
            diffuse: Texture::Constant(Rgb::BLACK),
            transmission: Rgb::WHITE,
            ..Phong::default()
        }
    }

    #[test]
    fn glass_splits_by_fresnel() {
        let rays: Vec<_> = glass().specular_rays(Vec3::Z, Vec3::Z).collect();
        assert_eq!(rays.len(), 2);
        assert!((rays[0].weight.r - 0.04).abs() < 1e-6 && rays[0].wi == Vec3::Z);
        assert!((rays[1].weight.r - 0.96 / 2.25).abs() < 1e-6 && (rays[1].wi - Vec3::NEG_Z).length() < 1e-6);
    }

    #[test]
    fn total_internal_reflection_from_inside() {
        // Viewed from inside the glass at 60 degrees from the normal: beyond 41.8, all reflects.
        let t = 60f32.to_radians();
        let wo = Vec3::new(t.sin(), 0.0, -t.cos());
        let rays: Vec<_> = glass().specular_rays(Vec3::Z, wo).collect();
        assert_eq!(rays.len(), 1);
        assert_eq!(rays[0].weight, Rgb::WHITE);
        assert!(rays[0].wi.z < 0.0, "reflected back inside");
    }

    /// The diffuse + glossy sampling fits its density (chi-square over the sphere), for
    /// diffuse, glossy and mixed materials at normal and oblique views.
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
        ];
        let n = Vec3::Z;
        for (seed, (m, theta)) in cases.iter().enumerate() {
            let wo = Vec3::new(theta.sin(), 0.05, theta.cos()).normalize();
            let mut lobe = penumbra_testkit::Uniforms::new(100 + seed as u64);
            let r = penumbra_testkit::chi2_directions(
                seed as u64,
                300_000,
                |u| m.sample(Vec2::ZERO, n, wo, lobe.next_f32(), u),
                |wi| m.pdf(Vec2::ZERO, n, wo, wi),
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
        let steps = 20_000;
        let mut sum = 0.0;
        for i in 0..steps {
            let theta = (i as f32 + 0.5) / steps as f32 * PI / 2.0;
            let wi = Vec3::new(theta.sin(), 0.0, theta.cos());
            let f = m.eval(Vec2::ZERO, Vec3::Z, Vec3::Z, wi).r;
            sum += f * theta.cos() * theta.sin() * 2.0 * PI * (PI / 2.0 / steps as f32);
        }
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }
}
