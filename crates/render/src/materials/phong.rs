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
use penumbra_core::Rgb;
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
#[derive(Clone, Copy, Debug, PartialEq)]
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
        let cos_alpha = reflect(wi, n).dot(wo).max(0.0);
        diffuse + self.specular * ((self.exponent + 2.0) / (2.0 * PI) * cos_alpha.powf(self.exponent))
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
