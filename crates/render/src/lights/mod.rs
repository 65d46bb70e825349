//! Lights. Point-like lights (point, spot, directional) are delta distributions: a shading
//! point receives light from exactly one direction, tested by one shadow ray. Area lights
//! ([`AreaLight`]) are emitting surfaces, sampled by area or by solid angle; the
//! [`Environment`] surrounds the scene at infinity.
//!
//! Adding a light: a new file with `sample_li` and `power`, a variant in [`Light`] and an
//! arm in each match.

mod area;
mod directional;
pub mod emitter;
#[cfg(test)]
mod emitter_tests;
pub mod environment;
mod point;
mod set;
mod spot;

pub use area::{AreaLight, AreaSampling, EmissionTexture};
pub use directional::Directional;
pub use environment::Environment;
pub use point::Point;
pub use set::{LightSelection, LightSet, LightSetBuilder};
pub use spot::Spot;

use glam::{Vec2, Vec3};
use penumbra_core::Rgb;

/// Incident light from one light at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Incident radiance (for delta lights: irradiance at normal incidence).
    pub li: Rgb,
    /// Distance to the light (infinite for directional lights).
    pub dist: f32,
    /// Solid-angle density of `wi`; 1 for delta lights.
    pub pdf: f32,
    pub delta: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    Point(Point),
    Spot(Spot),
    Directional(Directional),
    Area(AreaLight),
    Environment(Environment),
}

impl Light {
    /// Light arriving at `p`; `u` and `strategy` choose the point on area lights.
    pub fn sample_li(&self, p: Vec3, u: Vec2, strategy: AreaSampling) -> Option<LightSample> {
        match self {
            Light::Point(l) => l.sample_li(p),
            Light::Spot(l) => l.sample_li(p),
            Light::Directional(l) => l.sample_li(p),
            Light::Area(l) => l.sample_li(p, u, strategy),
            Light::Environment(l) => l.sample_li(u),
        }
    }

    /// Whether the light is a delta distribution (reachable only by light sampling).
    pub fn is_delta(&self) -> bool {
        !matches!(self, Light::Area(_) | Light::Environment(_))
    }

    /// Total emitted power (a luminance), for choosing among lights.
    pub fn power(&self, scene_radius: f32) -> f32 {
        match self {
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Directional(l) => l.power(scene_radius),
            Light::Area(l) => l.power(),
            Light::Environment(l) => l.power(scene_radius),
        }
    }
}

/// Light from a point source of `intensity` at `position`, seen from `p`: inverse-square falloff.
pub(crate) fn delta_sample(p: Vec3, position: Vec3, intensity: Rgb) -> Option<LightSample> {
    let to_light = position - p;
    let dist2 = to_light.length_squared();
    if dist2 == 0.0 || intensity.is_black() {
        return None;
    }
    let dist = dist2.sqrt();
    Some(LightSample {
        wi: to_light / dist,
        li: intensity / dist2,
        dist,
        pdf: 1.0,
        delta: true,
    })
}
