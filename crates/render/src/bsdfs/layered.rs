//! Layered BSDFs: a dielectric coating over a diffuse or conductor base, with a medium
//! between them (pbrt-v4's `coateddiffuse` and `coatedconductor`). There is no closed
//! form: [`Layered`]'s `eval`, `sample` and `pdf` are Monte Carlo estimates by random walks
//! between the two interfaces, the position-free method of Guo, Hašan and Zhao,
//! "Position-Free Monte Carlo Simulation for Arbitrary Layered BSDFs" (ACM TOG 37(6), 2018),
//! as pbrt-v4's `LayeredBxDF` writes it (Pharr, Jakob and Humphreys, 4th ed., section
//! 14.3.2). `eval` walks in through the coating towards `wo` and, at every bounce on the
//! base or scattering in the medium, adds a next-event estimate out through the coating
//! towards `wi`, weighing by the power heuristic the direction sampled from `wi` against
//! the walk's own. The medium's extinction is 1 per unit of thickness: with albedo 0 it only
//! absorbs, exp(-thickness / |cos θ|) per crossing (pbrt-v4's `Tr`); otherwise the walk
//! samples free flights and Henyey-Greenstein scattering. Walks are at most `max_depth`
//! interface or scattering events long and cut by Russian roulette after four. The random
//! numbers come from a generator seeded by hashing the arguments, so that an estimate is a
//! deterministic function of them (as pbrt-v4 seeds its `RNG`): images stay reproducible.
//!
//! A smooth coating over a Lambertian base of albedo ρ gives, in expectation, exactly
//! f = (1 - F(θo)) (1 - F(θi)) ρ / (π η² (1 - ρ F_dr,int)): the diffuse light bounces
//! between base and coating any number of times (Mitsuba's `nonlinear` plastic; the
//! linear one divides by 1 - F_dr,int instead). The tests hold the walk to that.
//!
//! `sample`'s weight is the walk's f |cos θi| / pdf; the density it reports for multiple
//! importance sampling is [`Layered`]'s `pdf`, an estimate (pbrt-v4's
//! `pdfIsProportional`): 0.9 times the estimated density of the coating's reflection and
//! the base's lobe seen through the coating, plus 0.1 of uniform density (pbrt mixes with
//! the uniform sphere; the base is opaque here, so we use the upper hemisphere, where all
//! of the samples go). Any positive density keeps the MIS weights summing to one.

use super::layered_walk::{transmittance, BaseLanes, LayeredLanes};
use super::{
    one_lane_methods, reflect_z, BsdfModel, BsdfSample, Conductor, Dielectric, Diffuse, LaneKernel, MetalFresnel,
    SpecularRays, TransportMode,
};
use crate::optics::{fresnel_dielectric, refract};
use crate::phase::HenyeyGreenstein;
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;

#[cfg(test)]
#[path = "layered_tests.rs"]
mod tests;

/// What lies under the coating.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LayerBase {
    Diffuse(Diffuse),
    /// A conductor whose complex index is relative to the coating's (η and k over its η).
    Conductor(Conductor),
}

impl LayerBase {
    fn albedo(&self) -> Rgb {
        match self {
            LayerBase::Diffuse(b) => b.albedo(),
            LayerBase::Conductor(b) => b.albedo(),
        }
    }
}

/// A coating over a base, `thickness` apart, with a medium of single-scattering `albedo`
/// and Henyey-Greenstein asymmetry `g` between; estimates use `samples` walks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layered {
    /// The coating: a dielectric interface (reflectance and transmittance tints 1).
    pub coat: Dielectric,
    pub base: LayerBase,
    pub thickness: f32,
    pub albedo: Rgb,
    pub g: f32,
    pub max_depth: u32,
    pub samples: u32,
}

impl Layered {
    /// The one-lane instance of the walks, for transport `mode`.
    #[inline(always)]
    pub fn lanes(&self, mode: TransportMode) -> LayeredLanes<f32> {
        // The base kind a lane does not use is held as a black one.
        let black = Diffuse {
            reflectance: Rgb::BLACK,
        };
        let mirror = Conductor {
            fresnel: MetalFresnel::Schlick,
            specular: Rgb::BLACK,
            alpha: None,
        };
        let (diffuse, conductor) = match self.base {
            LayerBase::Diffuse(d) => (d, mirror),
            LayerBase::Conductor(c) => (black, c),
        };
        let metal = matches!(self.base, LayerBase::Conductor(_));
        LayeredLanes {
            coat: self.coat.lanes(mode),
            base: BaseLanes {
                diffuse: diffuse.lanes(mode),
                conductor: conductor.lanes(mode),
                metal,
                specular: metal && conductor.alpha.is_none(),
            },
            thickness: self.thickness,
            albedo: self.albedo.into(),
            g: HenyeyGreenstein::new(self.g).g,
            max_depth: self.max_depth as f32,
            samples: self.samples.max(1) as f32,
        }
    }

    fn coat_specular(&self) -> bool {
        self.coat.rough().is_none()
    }

    fn scatters(&self) -> bool {
        !self.albedo.is_black()
    }

    fn base_specular(&self) -> bool {
        matches!(self.base, LayerBase::Conductor(c) if c.alpha.is_none())
    }

    /// The unscattered specular reflection's weight towards `wo`: the coating's F plus, over
    /// a smooth conductor, the light refracted in that bounces between the two as many
    /// times as a walk of `max_depth` events allows, (1 - F)² Σ_k (F F_c T²)^k F_c T².
    fn specular_weight(&self, wo: Vec3) -> Rgb {
        let f = fresnel_dielectric(wo.z, self.coat.eta);
        let mut weight = Rgb::splat(f);
        let LayerBase::Conductor(c) = &self.base else {
            return weight;
        };
        let Some(wt) = refract(wo, Vec3::Z, self.coat.eta).filter(|_| c.alpha.is_none()) else {
            return weight;
        };
        let t2 = transmittance(self.thickness, wt.into()).powi(2);
        let inside = fresnel_dielectric(-wt.z, 1.0 / self.coat.eta);
        let once = c.fresnel(-wt.z) * t2;
        let round = once * inside;
        let (mut sum, mut power) = (Rgb::BLACK, Rgb::WHITE);
        // A walk that leaves after k reflections inside ends at event 2k + 1 (none before
        // event 1 can: with fewer than two events no light comes back out).
        let terms = if self.max_depth >= 2 {
            (self.max_depth - 2) / 2 + 1
        } else {
            0
        };
        for _ in 0..terms {
            sum += power;
            power *= round;
        }
        // (In radiance, 1/η² in and η² out cancel; in importance neither applies.)
        weight += once * sum * ((1.0 - f) * (1.0 - inside));
        weight
    }
}

impl BsdfModel for Layered {
    one_lane_methods!();

    fn specular_rays(&self, wo: Vec3, _mode: TransportMode, rays: &mut SpecularRays) {
        if wo.z > 0.0 && self.coat_specular() {
            rays.push(reflect_z(wo), self.specular_weight(wo));
        }
    }

    fn has_smooth(&self) -> bool {
        !self.coat_specular() || !self.base_specular() || self.scatters()
    }

    fn albedo(&self) -> Rgb {
        self.base.albedo()
    }

    fn stochastic(&self) -> bool {
        true
    }
}
