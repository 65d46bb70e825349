//! A blend of two materials, f = (1 - w) f_a + w f_b (Mitsuba's `blendbsdf`). Sampling
//! picks one by its weight; a smooth direction is then weighted by the whole mixture's f
//! and density, so that multiple importance sampling sees one BSDF.

use super::{Bsdf, BsdfModel, BsdfSample, SpecularRays, TransportMode};
use crate::Material;
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug)]
pub struct Blend<'a> {
    pub a: &'a Material,
    pub b: &'a Material,
    /// Weight of `b`, in [0, 1].
    pub weight: f32,
    /// Where the two materials' textures are looked up.
    pub uv: Vec2,
}

impl<'a> Blend<'a> {
    fn parts(&self) -> [(f32, Bsdf<'a>); 2] {
        [
            (1.0 - self.weight, self.a.bsdf(self.uv)),
            (self.weight, self.b.bsdf(self.uv)),
        ]
    }
}

impl BsdfModel for Blend<'_> {
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        mixture_eval(&self.parts(), wo, wi, mode)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        mixture_pdf(&self.parts(), wo, wi, mode)
    }

    fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let parts = self.parts();
        let [(wa, a), (wb, b)] = parts;
        let (chosen, p, u) = if u < wa {
            (a, wa, u / wa)
        } else {
            (b, wb, (u - wa) / wb)
        };
        let s = chosen.sample(wo, u.min(penumbra_core::samplers::ONE_MINUS_EPSILON), u2, mode)?;
        if s.delta {
            return Some(BsdfSample { pdf: s.pdf * p, ..s });
        }
        let pdf = mixture_pdf(&parts, wo, s.wi, mode);
        (pdf > 0.0).then(|| BsdfSample {
            weight: mixture_eval(&parts, wo, s.wi, mode) * (s.wi.z.abs() / pdf),
            pdf,
            ..s
        })
    }

    fn specular_rays(&self, wo: Vec3, mode: TransportMode, rays: &mut SpecularRays) {
        for (w, b) in self.parts() {
            if w > 0.0 {
                rays.extend_scaled(&b.specular_rays(wo, mode), w);
            }
        }
    }

    fn has_smooth(&self) -> bool {
        self.parts().iter().any(|(w, b)| *w > 0.0 && b.has_smooth())
    }

    fn albedo(&self) -> Rgb {
        self.parts().iter().fold(Rgb::BLACK, |a, (w, b)| a + b.albedo() * *w)
    }
}

/// (1 - w) f_a + w f_b of the weighted parts.
fn mixture_eval(parts: &[(f32, Bsdf)], wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
    parts
        .iter()
        .filter(|(w, _)| *w > 0.0)
        .fold(Rgb::BLACK, |f, (w, b)| f + b.eval(wo, wi, mode) * *w)
}

/// The mixture's density: (1 - w) pdf_a + w pdf_b.
fn mixture_pdf(parts: &[(f32, Bsdf)], wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
    parts
        .iter()
        .filter(|(w, _)| *w > 0.0)
        .map(|(w, b)| w * b.pdf(wo, wi, mode))
        .sum()
}
