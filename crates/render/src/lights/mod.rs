//! Lights. Point-like lights (point, spot, directional) are delta distributions: a shading
//! point receives light from exactly one direction, tested by one shadow ray. Area lights
//! ([`AreaLight`]) are emitting surfaces, sampled by area or by solid angle; the
//! [`Environment`] surrounds the scene at infinity.
//!
//! Light paths (bidirectional path tracing, photons) start on lights: `sample_le` draws an
//! emitted ray (a point and a direction, each with its density) and `pdf_le` gives those
//! densities for a ray found another way (pbrt-v4 section 12.7's `SampleLe`/`PDF_Le`).
//! Lights at infinity (directional, environment) emit from a disk of the scene's bounding
//! sphere's radius facing the direction, so that the rays cover the whole scene.
//!
//! Adding a light: a new file with `sample_li`, `sample_le`, `pdf_le` and `power`, a variant
//! in [`Light`] and an arm in each match.

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
use penumbra_core::{warp, Frame, Ray, Rgb};
use std::f32::consts::PI;

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

/// A ray of light leaving a light, for light paths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionSample {
    /// From the point of emission, in the unit direction light travels.
    pub ray: Ray,
    /// The light's unit normal at the point (the direction of travel for lights at
    /// infinity; zero for point lights).
    pub normal: Vec3,
    /// Emitted radiance (for point lights: intensity; for directional lights: irradiance).
    pub le: Rgb,
    /// Density of the point per unit area (1 for a point light's one position).
    pub pdf_pos: f32,
    /// Density of the direction per unit solid angle (1 for a directional light's one
    /// direction).
    pub pdf_dir: f32,
}

impl EmissionSample {
    /// The light path's starting throughput for a light picked with probability `pick`:
    /// Le |cos θ| / (pick pdf_pos pdf_dir) (cos θ between the normal and the ray; 1 for
    /// point lights).
    pub fn throughput(&self, pick: f32) -> Rgb {
        let cos = if self.normal == Vec3::ZERO {
            1.0
        } else {
            self.normal.dot(self.ray.dir).abs()
        };
        self.le * (cos / (pick * self.pdf_pos * self.pdf_dir))
    }
}

/// The bounding sphere (centre, radius) of a scene's finite geometry: where lights at
/// infinity aim their rays.
pub type SceneSphere = (Vec3, f32);

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

    /// An emitted ray drawn from `u_pos` (the point) and `u_dir` (the direction).
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
        let s = match self {
            Light::Point(l) => l.sample_le(u_dir),
            Light::Spot(l) => l.sample_le(u_dir),
            Light::Directional(l) => l.sample_le(u_pos, sphere),
            Light::Area(l) => l.sample_le(u_pos, u_dir),
            Light::Environment(l) => l.sample_le(u_pos, u_dir, sphere),
        }?;
        let ok = s.pdf_pos > 0.0 && s.pdf_dir > 0.0 && s.pdf_pos.is_finite() && s.pdf_dir.is_finite();
        (ok && !s.le.is_black() && s.le.is_finite()).then_some(s)
    }

    /// The densities `(pdf_pos, pdf_dir)` with which [`Light::sample_le`] draws the ray
    /// leaving the light along `dir` from a point with unit normal `normal`: zero for what
    /// it cannot draw (a delta's position or direction).
    pub fn pdf_le(&self, dir: Vec3, normal: Vec3, sphere: SceneSphere) -> (f32, f32) {
        match self {
            Light::Point(_) => (0.0, warp::UNIFORM_SPHERE_PDF),
            Light::Spot(l) => (0.0, l.pdf_dir(dir)),
            Light::Directional(_) => (disk_pdf(sphere), 0.0),
            Light::Area(l) => l.pdf_le(dir, normal),
            Light::Environment(l) => (disk_pdf(sphere), l.pdf(-dir)),
        }
    }

    /// Whether the light lies at infinity (directional, environment).
    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::Directional(_) | Light::Environment(_))
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

/// The origin of a ray travelling along the unit `dir` from a point uniform over the disk
/// of the scene sphere's radius that faces `dir` and touches the sphere on the side the
/// light comes from.
pub(crate) fn disk_origin((center, radius): SceneSphere, dir: Vec3, u: Vec2) -> Vec3 {
    let d = warp::uniform_disk(u) * radius;
    let frame = Frame::from_normal(dir);
    center - dir * radius + frame.s * d.x + frame.t * d.y
}

/// Density per unit area of [`disk_origin`].
pub(crate) fn disk_pdf((_, radius): SceneSphere) -> f32 {
    1.0 / (PI * radius * radius)
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
