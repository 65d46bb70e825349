//! Next-event estimation, shared by the `direct` and `path` integrators: a shadow ray to a
//! point chosen on a light, and the multiple-importance weights (Veach and Guibas 1995)
//! that combine it with BSDF sampling.

use super::{shadow_ray, MisHeuristic, RayCounts};
use crate::lights::{AreaLight, AreaSampling, LightSelection};
use crate::materials::{Material, Phong};
use crate::{Interaction, Scene};
use glam::{Vec2, Vec3};
use penumbra_core::ray::offset_origin;
use penumbra_core::Rgb;

/// A shading point: the surface, its material, and normals on the side of `wo`.
pub(super) struct Shading<'a> {
    pub it: &'a Interaction<'a>,
    pub m: &'a Phong,
    pub n: Vec3,
    pub ng: Vec3,
    /// Probability that the integrator's BSDF sampling takes the diffuse + glossy part (the
    /// rest goes to the perfectly specular rays): it scales the BSDF density in MIS weights.
    pub lobe_probability: f32,
    /// Where lights are seen from: the surface point pushed off the surface on the side of
    /// `wo`, the origin of every shadow and reflected ray. Sampling lights from the raw hit
    /// point would let a point on an emitter (its back, say) land on the emitting side by
    /// rounding and be lit by its own surface at full strength.
    pub origin: Vec3,
}

impl<'a> Shading<'a> {
    pub fn new(it: &'a Interaction<'a>, lobe_probability: f32) -> Self {
        let Material::Phong(m) = it.material;
        let side = |v: Vec3| if v.dot(it.wo) < 0.0 { -v } else { v };
        let ng = side(it.surface.ng);
        Shading {
            it,
            m,
            n: side(it.surface.ns),
            ng,
            lobe_probability,
            origin: offset_origin(it.surface.p, ng),
        }
    }

    /// f(wo, wi) of the diffuse + glossy part.
    pub fn eval(&self, wi: Vec3) -> Rgb {
        self.m.eval(self.it.surface.uv, self.n, self.it.wo, wi)
    }

    /// Solid-angle density with which the integrator's BSDF sampling produces `wi`.
    pub fn bsdf_pdf(&self, wi: Vec3) -> f32 {
        self.lobe_probability * self.m.pdf(self.it.surface.uv, self.n, self.it.wo, wi)
    }
}

/// How the light samples of one shading point are drawn and weighted.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightStrategy {
    pub sampling: AreaSampling,
    /// Light samples taken for the light's strategy (the batch).
    pub samples: f32,
    /// MIS against this many BSDF samples, or no MIS.
    pub mis: Option<(MisHeuristic, f32)>,
}

/// One light-sampling estimate for light `index`, picked with probability `p_pick`:
/// f L cos θ V / (p_pick pdf samples), MIS-weighted against BSDF sampling when asked.
pub(super) fn light_sample(
    scene: &Scene,
    sh: &Shading,
    index: u32,
    p_pick: f32,
    u: Vec2,
    strategy: &LightStrategy,
    counts: &mut RayCounts,
) -> Rgb {
    let light = &scene.lights.lights()[index as usize];
    let Some(ls) = light.sample_li(sh.origin, u, strategy.sampling) else {
        return Rgb::BLACK;
    };
    let cos = sh.n.dot(ls.wi);
    // (Written to reject NaN directions too.)
    if !(cos > 0.0 && sh.ng.dot(ls.wi) > 0.0) || ls.li.is_black() {
        return Rgb::BLACK;
    }
    let f = sh.eval(ls.wi);
    if f.is_black() {
        return Rgb::BLACK;
    }
    counts.shadow += 1;
    let (shadow, t_max) = shadow_ray(sh.origin, &ls);
    if scene.occluded(&shadow, t_max) {
        return Rgb::BLACK;
    }
    let weight = match strategy.mis {
        Some((heuristic, n_bsdf)) if !ls.delta => {
            heuristic.weight(strategy.samples * p_pick * ls.pdf, n_bsdf * sh.bsdf_pdf(ls.wi))
        }
        _ => 1.0,
    };
    f * ls.li * (cos * weight / (p_pick * ls.pdf * strategy.samples))
}

/// The MIS weight of a BSDF sample from `p` (density `n_bsdf` x `p_bsdf`) that reached
/// `point` (normal `normal`) on area light `index`, against the light strategy of
/// `n_light` samples by `sampling` per shading point with lights chosen by `selection`.
#[allow(clippy::too_many_arguments)]
pub(super) fn emitter_weight(
    scene: &Scene,
    (selection, sampling): (LightSelection, AreaSampling),
    heuristic: MisHeuristic,
    p: Vec3,
    (index, light): (u32, &AreaLight),
    point: Vec3,
    normal: Vec3,
    (n_bsdf, p_bsdf): (f32, f32),
    n_light: f32,
) -> f32 {
    let p_pick = scene.lights.pmf(selection, index);
    let p_light = light.pdf(p, point, normal, sampling);
    heuristic.weight(n_bsdf * p_bsdf, n_light * p_pick * p_light)
}
