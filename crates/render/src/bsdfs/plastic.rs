//! Plastic (coated diffuse): a diffuse base under a dielectric coating of relative index
//! `eta`, as Mitsuba 3's `plastic` and `roughplastic` model it. Light is reflected by the
//! coating (F), or enters it, scatters diffusely in the base with multiple internal
//! reflections (the base albedo ρ divided by 1 - F_dr,int, F_dr,int the coating's diffuse
//! internal reflectance; Mitsuba's linear model), and leaves through it:
//! f_diffuse = (1 - F(cos θi)) (1 - F(cos θo)) ρ / (π η² (1 - F_dr,int)).
//! The smooth coating reflects as a mirror; the rough one by the isotropic GGX microfacet
//! BRDF. For the rough coating the transmission factors use the smooth Fresnel term at the
//! macroscopic angles (Mitsuba 3 tabulates the rough transmittance instead).

use super::microfacet::Ggx;
use super::{reflect_z, BsdfSample, SpecularRays};
use crate::optics::fresnel_dielectric;
use glam::{Vec2, Vec3};
use penumbra_core::{warp, Rgb};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    pub diffuse: Rgb,
    pub specular: Rgb,
    /// Coating over exterior index of refraction.
    pub eta: f32,
    /// The coating's diffuse internal reflectance F_dr,int (worked out once per material).
    pub fdr_int: f32,
    /// Share of the specular lobe in sampling, before Fresnel: mean specular over the sum
    /// of the mean diffuse and specular reflectances (as Mitsuba).
    pub specular_weight: f32,
    /// The coating's roughness; `None` for a smooth coating.
    pub alpha: Option<Ggx>,
}

impl Plastic {
    /// Probability of sampling the coating's reflection, seen from `wo`.
    fn specular_probability(&self, cos_o: f32) -> f32 {
        let f = fresnel_dielectric(cos_o, self.eta);
        let ps = f * self.specular_weight;
        let pd = (1.0 - f) * (1.0 - self.specular_weight);
        if ps + pd > 0.0 {
            ps / (ps + pd)
        } else {
            0.0
        }
    }

    fn diffuse_part(&self, cos_o: f32, cos_i: f32) -> Rgb {
        let t = (1.0 - fresnel_dielectric(cos_i, self.eta)) * (1.0 - fresnel_dielectric(cos_o, self.eta));
        self.diffuse * (t * FRAC_1_PI / (self.eta * self.eta * (1.0 - self.fdr_int)))
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let mut f = self.diffuse_part(wo.z, wi.z);
        if let (Some(ggx), Some(m)) = (self.alpha, Ggx::reflection_half_vector(wo, wi)) {
            f += self.specular * (fresnel_dielectric(wo.dot(m), self.eta) * ggx.reflection(wo, wi, m));
        }
        f
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let ps = self.specular_probability(wo.z);
        let mut pdf = (1.0 - ps) * warp::cosine_hemisphere_pdf(wi);
        if let (Some(ggx), Some(m)) = (self.alpha, Ggx::reflection_half_vector(wo, wi)) {
            pdf += ps * ggx.reflection_pdf(wo, m);
        }
        pdf
    }

    pub fn sample(&self, wo: Vec3, u: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let ps = self.specular_probability(wo.z);
        if u < ps && self.alpha.is_none() {
            return Some(BsdfSample {
                wi: reflect_z(wo),
                weight: self.specular * (fresnel_dielectric(wo.z, self.eta) / ps),
                pdf: ps,
                delta: true,
                eta: 1.0,
            });
        }
        let wi = match self.alpha {
            Some(ggx) if u < ps => ggx.sample_reflection(wo, u2)?.0,
            _ => warp::cosine_hemisphere(u2),
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z / pdf),
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    pub fn specular_rays(&self, wo: Vec3, rays: &mut SpecularRays) {
        if self.alpha.is_none() && wo.z > 0.0 {
            rays.push(reflect_z(wo), self.specular * fresnel_dielectric(wo.z, self.eta));
        }
    }
}
