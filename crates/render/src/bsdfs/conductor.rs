//! Conductors (metals): Fresnel reflection with a complex index of refraction η + ik per
//! colour channel. Smooth: a perfect mirror. Rough: the GGX microfacet BRDF
//! f = F(wo·m) D(m) G2(wo, wi) / (4 cos θo cos θi) (Walter et al. 2007), sampled by visible
//! normals (Heitz 2018), whose weight is F G2 / G1(wo). Single scattering only: rough
//! metals lose the energy of light that would bounce between microfacets, never gain any.
//! glTF's metals give their reflectance at normal incidence instead of an index: their F
//! is Schlick's approximation (Schlick 1994, eq. 24), as the glTF 2.0 specification's
//! appendix B defines it.

use super::microfacet::Ggx;
use super::{reflect_z, BsdfModel, BsdfSample, SpecularRays, TransportMode};
use crate::optics::fresnel_conductor;
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;

/// How a metal's reflectance varies with the angle of incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MetalFresnel {
    /// The exact Fresnel equations for the complex index `eta + i k`.
    Complex { eta: Rgb, k: Rgb },
    /// Schlick's F0 + (1 - F0)(1 - cos)^5 with F0 the conductor's `specular` tint.
    Schlick,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub fresnel: MetalFresnel,
    /// A tint on the reflection (1 for physical metals).
    pub specular: Rgb,
    /// The microfacet distribution; `None` for a smooth mirror.
    pub alpha: Option<Ggx>,
}

impl Conductor {
    /// F(cos) per channel, tinted by `specular`.
    pub(crate) fn fresnel(&self, cos: f32) -> Rgb {
        match self.fresnel {
            MetalFresnel::Complex { eta, k } => {
                Rgb::new(
                    fresnel_conductor(cos, eta.r, k.r),
                    fresnel_conductor(cos, eta.g, k.g),
                    fresnel_conductor(cos, eta.b, k.b),
                ) * self.specular
            }
            MetalFresnel::Schlick => {
                let f0 = self.specular;
                f0 + (Rgb::WHITE - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
            }
        }
    }
}

impl BsdfModel for Conductor {
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Rgb {
        match (self.alpha, Ggx::reflection_half_vector(wo, wi)) {
            (Some(ggx), Some(m)) => self.fresnel(wo.dot(m)) * ggx.reflection(wo, wi, m),
            _ => Rgb::BLACK,
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        match (self.alpha, Ggx::reflection_half_vector(wo, wi)) {
            (Some(ggx), Some(m)) => ggx.reflection_pdf(wo, m),
            _ => 0.0,
        }
    }

    fn sample(&self, wo: Vec3, _u: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
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
        let (wi, m) = ggx.sample_reflection(wo, u)?;
        Some(BsdfSample {
            wi,
            weight: self.fresnel(wo.dot(m)) * (ggx.g2(wo, wi) / ggx.g1(wo)),
            pdf: ggx.reflection_pdf(wo, m),
            delta: false,
            eta: 1.0,
        })
    }

    fn specular_rays(&self, wo: Vec3, _mode: TransportMode, rays: &mut SpecularRays) {
        if self.alpha.is_none() && wo.z > 0.0 {
            rays.push(reflect_z(wo), self.fresnel(wo.z));
        }
    }

    fn has_smooth(&self) -> bool {
        self.alpha.is_some()
    }

    fn albedo(&self) -> Rgb {
        self.specular
    }
}
