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
//! Adding a light: a new file whose type implements [`LightModel`] (every method, none
//! with a default, so the compiler names each question a new kind must answer), and one
//! line in the `light_kinds!` registry. The integrators ask [`Light`] and never match on
//! kinds themselves. The light test table (`lights/tests_table.rs`) fails until the new
//! kind has a case.

mod area;
mod area_lanes;
mod directional;
pub mod emitter;
#[cfg(test)]
mod emitter_tests;
pub mod environment;
pub mod lanes;
#[cfg(test)]
mod lanes_tests;
mod point;
mod set;
mod spot;
#[cfg(test)]
mod tests_table;

pub use area::{emits_towards, towards_point_lanes, AreaLight, AreaSampling, EmissionTexture};
pub use area_lanes::TriangleByArea;
pub use directional::{Directional, DirectionalLanes};
pub use environment::{Environment, EnvironmentLanes};
pub use lanes::{LaneLightSample, LightGather, LightKernel};
pub use point::{Point, PointLanes};
pub use set::{LightSelection, LightSet, LightSetBuilder};
pub use spot::{Spot, SpotLanes};

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

/// What every light answers; each kind's file implements it. No method has a default: a
/// new kind must answer each question (the integrators ask [`Light`], never match on
/// kinds, so nothing falls back silently to another kind's answer).
pub trait LightModel {
    /// Light arriving at `p`; `u` and `strategy` choose the point on area lights.
    fn sample_li(&self, p: Vec3, u: Vec2, strategy: AreaSampling) -> Option<LightSample>;
    /// The solid-angle density with which `sample_li` gives direction `wi` at `p` (0 for
    /// delta lights, which no other direction meets, and where `wi` misses).
    fn pdf_li(&self, p: Vec3, wi: Vec3, strategy: AreaSampling) -> f32;
    /// Radiance the light sends along `w` from its point `point` (for lights at infinity:
    /// travelling along `w`, whatever the point); black for delta lights, which no ray
    /// meets.
    fn emitted(&self, point: Vec3, w: Vec3) -> Rgb;
    /// The front normal of the light's surface at `point`; `None` for lights without one.
    fn surface_normal(&self, point: Vec3) -> Option<Vec3>;
    /// The density with which a light path's ray comes in from infinity along `dir` (the
    /// environment's direction density); 0 for finite lights and delta directions.
    fn pdf_from_infinity(&self, dir: Vec3) -> f32;
    /// Whether a path vertex on this light can be joined to another by a shadow ray: not
    /// for a single direction of travel (directional light).
    fn connectible(&self) -> bool;
    /// An emitted ray drawn from `u_pos` (the point) and `u_dir` (the direction).
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample>;
    /// The densities `(pdf_pos, pdf_dir)` with which `sample_le` draws the ray leaving the
    /// light along `dir` from a point with unit normal `normal`: zero for what it cannot
    /// draw (a delta's position or direction).
    fn pdf_le(&self, dir: Vec3, normal: Vec3, sphere: SceneSphere) -> (f32, f32);
    /// Whether the light lies at infinity (directional, environment).
    fn is_infinite(&self) -> bool;
    /// Whether the light is a delta distribution (reachable only by light sampling).
    fn is_delta(&self) -> bool;
    /// Total emitted power (a luminance), for choosing among lights.
    fn power(&self, scene_radius: f32) -> f32;
}

/// The [`LightModel`] answers every delta light (point, spot, directional) shares: no ray
/// meets it, so it has no density for a direction met, emits nothing along one, has no
/// surface and no direction density from infinity. A kind opts in by calling this in its
/// implementation.
macro_rules! delta_light_answers {
    () => {
        fn pdf_li(&self, _p: Vec3, _wi: Vec3, _strategy: AreaSampling) -> f32 {
            0.0
        }
        fn emitted(&self, _point: Vec3, _w: Vec3) -> Rgb {
            Rgb::BLACK
        }
        fn surface_normal(&self, _point: Vec3) -> Option<Vec3> {
            None
        }
        fn pdf_from_infinity(&self, _dir: Vec3) -> f32 {
            0.0
        }
        fn is_delta(&self) -> bool {
            true
        }
    };
}
use delta_light_answers;

/// The registry of light kinds: one line per kind (variant, type, name) generates
/// [`Light`], its static dispatch of [`LightModel`] and [`Light::NAMES`], which the light
/// test table checks it covers. Adding a light: its file, implementing [`LightModel`],
/// and one line here.
macro_rules! light_kinds {
    ($($variant:ident($ty:ty) = $name:literal),* $(,)?) => {
        /// The lights this renderer knows.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Light {
            $($variant($ty)),*
        }

        impl Light {
            /// Every kind's name, in registry order.
            pub const NAMES: &'static [&'static str] = &[$($name),*];

            pub fn name(&self) -> &'static str {
                match self {
                    $(Light::$variant(_) => $name),*
                }
            }

            /// [`LightModel::sample_li`], statically dispatched.
            #[inline]
            pub fn sample_li(&self, p: Vec3, u: Vec2, strategy: AreaSampling) -> Option<LightSample> {
                match self {
                    $(Light::$variant(l) => LightModel::sample_li(l, p, u, strategy)),*
                }
            }

            /// [`LightModel::pdf_li`], statically dispatched.
            #[inline]
            pub fn pdf_li(&self, p: Vec3, wi: Vec3, strategy: AreaSampling) -> f32 {
                match self {
                    $(Light::$variant(l) => LightModel::pdf_li(l, p, wi, strategy)),*
                }
            }

            /// [`LightModel::emitted`], statically dispatched.
            #[inline]
            pub fn emitted(&self, point: Vec3, w: Vec3) -> Rgb {
                match self {
                    $(Light::$variant(l) => LightModel::emitted(l, point, w)),*
                }
            }

            /// [`LightModel::surface_normal`], statically dispatched.
            #[inline]
            pub fn surface_normal(&self, point: Vec3) -> Option<Vec3> {
                match self {
                    $(Light::$variant(l) => LightModel::surface_normal(l, point)),*
                }
            }

            /// [`LightModel::pdf_from_infinity`], statically dispatched.
            #[inline]
            pub fn pdf_from_infinity(&self, dir: Vec3) -> f32 {
                match self {
                    $(Light::$variant(l) => LightModel::pdf_from_infinity(l, dir)),*
                }
            }

            /// [`LightModel::connectible`], statically dispatched.
            #[inline]
            pub fn connectible(&self) -> bool {
                match self {
                    $(Light::$variant(l) => LightModel::connectible(l)),*
                }
            }

            /// [`LightModel::pdf_le`], statically dispatched.
            #[inline]
            pub fn pdf_le(&self, dir: Vec3, normal: Vec3, sphere: SceneSphere) -> (f32, f32) {
                match self {
                    $(Light::$variant(l) => LightModel::pdf_le(l, dir, normal, sphere)),*
                }
            }

            /// [`LightModel::is_infinite`], statically dispatched.
            #[inline]
            pub fn is_infinite(&self) -> bool {
                match self {
                    $(Light::$variant(l) => LightModel::is_infinite(l)),*
                }
            }

            /// [`LightModel::is_delta`], statically dispatched.
            #[inline]
            pub fn is_delta(&self) -> bool {
                match self {
                    $(Light::$variant(l) => LightModel::is_delta(l)),*
                }
            }

            /// [`LightModel::power`], statically dispatched.
            #[inline]
            pub fn power(&self, scene_radius: f32) -> f32 {
                match self {
                    $(Light::$variant(l) => LightModel::power(l, scene_radius)),*
                }
            }

            /// [`LightModel::sample_le`] as the kind answers it.
            #[inline]
            fn emission(&self, u_pos: Vec2, u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
                match self {
                    $(Light::$variant(l) => LightModel::sample_le(l, u_pos, u_dir, sphere)),*
                }
            }
        }
    };
}

light_kinds! {
    Point(Point) = "point",
    Spot(Spot) = "spot",
    Directional(Directional) = "directional",
    Area(AreaLight) = "area",
    Environment(Environment) = "environment",
}

impl Light {
    /// [`LightModel::sample_le`], with samples of no density or no light dropped.
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
        let s = self.emission(u_pos, u_dir, sphere)?;
        let ok = s.pdf_pos > 0.0 && s.pdf_dir > 0.0 && s.pdf_pos.is_finite() && s.pdf_dir.is_finite();
        (ok && !s.le.is_black() && s.le.is_finite()).then_some(s)
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
