//! The BSDF of the classic ray-tracing material (see [`crate::materials::Phong`]): Lambertian
//! diffuse plus the energy-normalised Phong lobe f = ks (n + 2) / (2π) cos^n α (Lafortune
//! and Willems 1994), on both sides of the surface, plus perfect mirror reflection and a
//! Fresnel-weighted dielectric interface as delta lobes. `sample` chooses among the smooth
//! part and the delta rays in proportion to their albedos' luminance, and within the smooth
//! part between the cosine hemisphere and the Phong lobe likewise.

use super::{reflect_z, same_hemisphere, BsdfModel, BsdfSample, SpecularRays, TransportMode};
use crate::optics::{fresnel_dielectric, refract};
use glam::{Vec2, Vec3};
use penumbra_core::{warp, Frame, Rgb};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongBsdf {
    pub diffuse: Rgb,
    pub specular: Rgb,
    pub exponent: f32,
    pub mirror: Rgb,
    pub transmission: Rgb,
    /// Interior over exterior index of refraction.
    pub eta: f32,
}

/// `w` with the sign of its z taken from `side` (both-sided lobes are evaluated above).
#[inline]
fn upper(w: Vec3, side: f32) -> Vec3 {
    Vec3::new(w.x, w.y, w.z * side.signum())
}

impl PhongBsdf {
    /// Luminance of the diffuse and glossy albedos together.
    fn smooth_albedo(&self) -> f32 {
        self.diffuse.luminance().max(0.0) + self.specular.luminance().max(0.0)
    }

    /// The share of the smooth part in `sample`, seen from `wo`.
    fn smooth_probability(&self, wo: Vec3, mode: TransportMode) -> f32 {
        let smooth = self.smooth_albedo();
        let mut rays = SpecularRays::default();
        self.specular_rays(wo, mode, &mut rays);
        let total = smooth + rays.as_slice().iter().map(|r| r.weight.luminance()).sum::<f32>();
        if total > 0.0 {
            smooth / total
        } else {
            0.0
        }
    }

    /// Density of the smooth part's sampling, both directions above.
    fn smooth_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let smooth = self.smooth_albedo();
        if smooth <= 0.0 {
            return 0.0;
        }
        let pd = self.diffuse.luminance().max(0.0) / smooth;
        let mut pdf = pd * warp::cosine_hemisphere_pdf(wi);
        if pd < 1.0 {
            let lobe = Frame::from_normal(reflect_z(wo)).to_local(wi);
            pdf += (1.0 - pd) * warp::phong_lobe_pdf(lobe, self.exponent);
        }
        pdf
    }

    fn relative_eta(&self, wo: Vec3) -> f32 {
        if wo.z > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        }
    }
}

impl BsdfModel for PhongBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let diffuse = self.diffuse / PI;
        let cos_alpha = reflect_z(upper(wi, wi.z)).dot(upper(wo, wo.z));
        // Zero outside the lobe's hemisphere (also for exponent 0, where 0^0 would be 1).
        if self.specular.is_black() || cos_alpha <= 0.0 {
            return diffuse;
        }
        diffuse + self.specular * ((self.exponent + 2.0) / (2.0 * PI) * cos_alpha.powf(self.exponent))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        self.smooth_probability(wo, mode) * self.smooth_pdf(upper(wo, wo.z), upper(wi, wi.z))
    }

    fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let smooth = self.smooth_albedo();
        let mut rays = SpecularRays::default();
        self.specular_rays(wo, mode, &mut rays);
        let rays = rays.as_slice();
        let total = smooth + rays.iter().map(|r| r.weight.luminance()).sum::<f32>();
        if total.is_nan() || total <= 0.0 || wo.z == 0.0 {
            return None;
        }
        let mut x = u * total;
        if x < smooth {
            // The smooth part: cosine hemisphere or Phong lobe, by the rescaled u.
            let side = wo.z;
            let up = upper(wo, side);
            let pd = self.diffuse.luminance().max(0.0) / smooth;
            let wi = if x / smooth < pd {
                warp::cosine_hemisphere(u2)
            } else {
                Frame::from_normal(reflect_z(up)).to_world(warp::phong_lobe(u2, self.exponent))
            };
            if wi.z <= 0.0 {
                return None;
            }
            let wi = upper(wi, side);
            let pdf = smooth / total * self.smooth_pdf(up, upper(wi, wi.z));
            return (pdf > 0.0).then(|| BsdfSample {
                wi,
                weight: self.eval(wo, wi, mode) * (wi.z.abs() / pdf),
                pdf,
                delta: false,
                eta: 1.0,
            });
        }
        // A delta ray, by its share of the albedo (rounding may leave x at the very end:
        // then the last ray).
        x -= smooth;
        let chosen = rays
            .iter()
            .find(|r| {
                x -= r.weight.luminance();
                x < 0.0
            })
            .or(rays.last())?;
        let p = chosen.weight.luminance() / total;
        let refracted = !same_hemisphere(wo, chosen.wi);
        (p > 0.0).then(|| BsdfSample {
            wi: chosen.wi,
            weight: chosen.weight / p,
            pdf: p,
            delta: true,
            eta: if refracted { self.relative_eta(wo) } else { 1.0 },
        })
    }

    /// Mirror reflection, and for a transmissive material the Fresnel-weighted reflection
    /// and refraction, radiance crossing into a denser medium scaled by 1/η².
    fn specular_rays(&self, wo: Vec3, mode: TransportMode, rays: &mut SpecularRays) {
        if wo.z == 0.0 {
            return;
        }
        rays.push(reflect_z(wo), self.mirror);
        if self.transmission.is_black() {
            return;
        }
        let eta = self.relative_eta(wo);
        let f = fresnel_dielectric(wo.z.abs(), eta);
        rays.push(reflect_z(wo), self.transmission * f);
        if f < 1.0 {
            if let Some(wi) = refract(wo, Vec3::Z * wo.z.signum(), eta) {
                let scale = match mode {
                    TransportMode::Radiance => 1.0 / (eta * eta),
                    TransportMode::Importance => 1.0,
                };
                rays.push(wi, self.transmission * ((1.0 - f) * scale));
            }
        }
    }

    fn has_smooth(&self) -> bool {
        self.smooth_albedo() > 0.0
    }

    fn albedo(&self) -> Rgb {
        self.diffuse
    }
}
