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
//! Adding a light: a new file with what the methods of [`Light`] ask of it, a variant and
//! its name in [`Light::NAMES`], and an arm in each match below. Every match here is
//! exhaustive (no catch-all arm), so the compiler names each place a new kind must answer:
//! the integrators ask [`Light`] and never match on kinds themselves. The light test table
//! (`lights/tests_table.rs`) fails until the new kind has a case.

mod area;
mod directional;
pub mod emitter;
#[cfg(test)]
mod emitter_tests;
pub mod environment;
mod point;
mod set;
mod spot;
#[cfg(test)]
mod tests_table;

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
    /// Every kind's name, in the order of the variants.
    pub const NAMES: [&'static str; 5] = ["point", "spot", "directional", "area", "environment"];

    pub fn name(&self) -> &'static str {
        match self {
            Light::Point(_) => Self::NAMES[0],
            Light::Spot(_) => Self::NAMES[1],
            Light::Directional(_) => Self::NAMES[2],
            Light::Area(_) => Self::NAMES[3],
            Light::Environment(_) => Self::NAMES[4],
        }
    }

    /// The solid-angle density with which [`Light::sample_li`] gives direction `wi` at
    /// `p` (0 for delta lights, which no other direction meets, and where `wi` misses).
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, strategy: AreaSampling) -> f32 {
        match self {
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => 0.0,
            Light::Area(l) => l
                .emitter
                .intersect(p, wi)
                .map_or(0.0, |(point, normal)| l.pdf(p, point, normal, strategy)),
            Light::Environment(l) => l.pdf(wi),
        }
    }

    /// Radiance the light sends along `w` from its point `point` (for lights at infinity:
    /// travelling along `w`, whatever the point); black for delta lights, which no ray
    /// meets.
    pub fn emitted(&self, point: Vec3, w: Vec3) -> Rgb {
        match self {
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => Rgb::BLACK,
            Light::Area(l) => l.le(point, l.emitter.normal_at(point), w),
            Light::Environment(l) => l.le(-w),
        }
    }

    /// The front normal of the light's surface at `point`; `None` for lights without one.
    pub fn surface_normal(&self, point: Vec3) -> Option<Vec3> {
        match self {
            Light::Area(l) => Some(l.emitter.normal_at(point)),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Environment(_) => None,
        }
    }

    /// The density with which a light path's ray comes in from infinity along `dir` (the
    /// environment's direction density); 0 for finite lights and delta directions.
    pub fn pdf_from_infinity(&self, dir: Vec3) -> f32 {
        match self {
            Light::Environment(l) => l.pdf(-dir),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Area(_) => 0.0,
        }
    }

    /// Whether a path vertex on this light can be joined to another by a shadow ray: not
    /// for a single direction of travel (directional light).
    pub fn connectible(&self) -> bool {
        match self {
            Light::Directional(_) => false,
            Light::Point(_) | Light::Spot(_) | Light::Area(_) | Light::Environment(_) => true,
        }
    }

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
        match self {
            Light::Directional(_) | Light::Environment(_) => true,
            Light::Point(_) | Light::Spot(_) | Light::Area(_) => false,
        }
    }

    /// Whether the light is a delta distribution (reachable only by light sampling).
    pub fn is_delta(&self) -> bool {
        match self {
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => true,
            Light::Area(_) | Light::Environment(_) => false,
        }
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
