//! An isotropic point light: radiant intensity `intensity` (W/sr per channel) from
//! `position`; irradiance falls off as 1/r^2.
//!
//! Native format: `type = "point"`, `position` (required), `intensity` (colour, default
//! `[1, 1, 1]`).

use super::lanes::{delta_sample_lanes, LaneLightSample, LightGather, LightKernel};
use super::{delta_light_answers, AreaSampling, EmissionSample, LightModel, LightSample, SceneSphere};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{warp, Ray, Rgb};

#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub position: Vec3,
    pub intensity: Rgb,
}

impl Default for Point {
    /// The native format's defaults (at the origin, since `position` is required there).
    fn default() -> Self {
        Point {
            position: Vec3::ZERO,
            intensity: Rgb::WHITE,
        }
    }
}

/// A point light in lanes of any [`Real`] type.
#[derive(Clone, Copy, Debug)]
pub struct PointLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub position: V3<R>,
    pub intensity: S,
}

impl<R: Real, S: Spectrum<R>> PointLanes<R, S> {
    /// The same light carrying the payload `T`, its colour converted by `to` (as a
    /// spectral renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(S) -> T) -> PointLanes<R, T> {
        PointLanes {
            position: self.position,
            intensity: to(self.intensity),
        }
    }
}

impl<R: Real, S: Spectrum<R>> LightKernel<R, S> for PointLanes<R, S> {
    #[inline(always)]
    fn sample_li(&self, p: V3<R>, _u: (R, R)) -> LaneLightSample<R, S> {
        delta_sample_lanes(p, self.position, self.intensity)
    }
}

impl LightGather for PointLanes<f32> {
    type Lanes<L: Lane8> = PointLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> PointLanes<L> {
        PointLanes {
            position: V3::gather(one, |l| l.position),
            intensity: V3::gather(one, |l| l.intensity),
        }
    }
}

impl Point {
    /// The one-lane instance of the arithmetic.
    #[inline(always)]
    pub fn lanes(&self) -> PointLanes<f32> {
        PointLanes {
            position: self.position.into(),
            intensity: self.intensity.into(),
        }
    }

    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        self.lanes().sample_li(p.into(), (0.0, 0.0)).one(true)
    }

    /// A ray in a direction uniform over the sphere.
    pub fn sample_le(&self, u: Vec2) -> Option<EmissionSample> {
        Some(EmissionSample {
            ray: Ray::new(self.position, warp::uniform_sphere(u)),
            normal: Vec3::ZERO,
            le: self.intensity,
            pdf_pos: 1.0,
            pdf_dir: warp::UNIFORM_SPHERE_PDF,
        })
    }

    pub fn power(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.intensity.luminance()
    }
}

impl LightModel for Point {
    delta_light_answers!();

    fn sample_li(&self, p: Vec3, _u: Vec2, _strategy: AreaSampling) -> Option<LightSample> {
        Point::sample_li(self, p)
    }
    fn connectible(&self) -> bool {
        true
    }
    fn sample_le(&self, _u_pos: Vec2, u_dir: Vec2, _sphere: SceneSphere) -> Option<EmissionSample> {
        Point::sample_le(self, u_dir)
    }
    fn pdf_le(&self, _dir: Vec3, _normal: Vec3, _sphere: SceneSphere) -> (f32, f32) {
        (0.0, warp::UNIFORM_SPHERE_PDF)
    }
    fn is_infinite(&self) -> bool {
        false
    }
    fn power(&self, _scene_radius: f32) -> f32 {
        Point::power(self)
    }
}
