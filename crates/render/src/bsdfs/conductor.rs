//! Conductors (metals): Fresnel reflection with a complex index of refraction η + ik per
//! colour channel. Smooth: a perfect mirror. Rough: the GGX microfacet BRDF
//! f = F(wo·m) D(m) G2(wo, wi) / (4 cos θo cos θi) (Walter et al. 2007), sampled by visible
//! normals (Heitz 2018), whose weight is F G2 / G1(wo). Single scattering only: rough
//! metals lose the energy of light that would bounce between microfacets, never gain any.

use super::microfacet::Ggx;
use super::{reflect_z, BsdfSample, SpecularRays};
use crate::optics::fresnel_conductor;
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub eta: Rgb,
    pub k: Rgb,
    /// A tint on the reflection (1 for physical metals).
    pub specular: Rgb,
    /// The microfacet distribution; `None` for a smooth mirror.
    pub alpha: Option<Ggx>,
}

impl Conductor {
    fn fresnel(&self, cos: f32) -> Rgb {
        Rgb::new(
            fresnel_conductor(cos, self.eta.r, self.k.r),
            fresnel_conductor(cos, self.eta.g, self.k.g),
            fresnel_conductor(cos, self.eta.b, self.k.b),
        ) * self.specular
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some(ggx) = self.alpha else {
            return Rgb::BLACK;
        };
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let Some(m) = (wo + wi).try_normalize() else {
            return Rgb::BLACK;
        };
        self.fresnel(wo.dot(m)) * (ggx.d(m) * ggx.g2(wo, wi) / (4.0 * wo.z * wi.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(ggx) = self.alpha else {
            return 0.0;
        };
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some(m) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        ggx.visible_pdf(wo, m) / (4.0 * wo.dot(m))
    }

    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let Some(ggx) = self.alpha else {
            return Some(BsdfSample {
                wi: reflect_z(wo),
                weight: self.fresnel(wo.z),
                pdf: 1.0,
                delta: true,
                eta: 1.0,
            });
        };
        let m = ggx.sample_visible(wo, u);
        let cos_om = wo.dot(m);
        let wi = 2.0 * cos_om * m - wo;
        if wi.z <= 0.0 || cos_om <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.fresnel(cos_om) * (ggx.g2(wo, wi) / ggx.g1(wo)),
            pdf: ggx.visible_pdf(wo, m) / (4.0 * cos_om),
            delta: false,
            eta: 1.0,
        })
    }

    pub fn specular_rays(&self, wo: Vec3, rays: &mut SpecularRays) {
        if self.alpha.is_none() && wo.z > 0.0 {
            rays.push(reflect_z(wo), self.fresnel(wo.z));
        }
    }
}
