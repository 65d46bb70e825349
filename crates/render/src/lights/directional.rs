//! A directional (distant) light: parallel light travelling along `direction`, with
//! irradiance `irradiance` on a surface facing it.
//!
//! Native format: `type = "directional"`, `direction` (the way the light travels,
//! default `[0, -1, 0]`), `irradiance` (colour, default `[1, 1, 1]`).

use super::lanes::{LaneLightSample, LightGather, LightKernel};
use super::{
    delta_light_answers, disk_origin, disk_pdf, AreaSampling, EmissionSample, LightModel, LightSample, SceneSphere,
};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{Ray, Rgb};

#[derive(Clone, Debug, PartialEq)]
pub struct Directional {
    /// Unit direction of travel.
    pub direction: Vec3,
    pub irradiance: Rgb,
}

impl Default for Directional {
    /// The native format's defaults: straight down, irradiance 1.
    fn default() -> Self {
        Directional {
            direction: -Vec3::Y,
            irradiance: Rgb::WHITE,
        }
    }
}

/// A directional light in lanes of any [`Real`] type.
#[derive(Clone, Copy, Debug)]
pub struct DirectionalLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub direction: V3<R>,
    pub irradiance: S,
}

impl<R: Real, S: Spectrum<R>> DirectionalLanes<R, S> {
    /// The same light carrying the payload `T`, its colour converted by `to` (as a
    /// spectral renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(S) -> T) -> DirectionalLanes<R, T> {
        DirectionalLanes {
            direction: self.direction,
            irradiance: to(self.irradiance),
        }
    }
}

impl<R: Real, S: Spectrum<R>> LightKernel<R, S> for DirectionalLanes<R, S> {
    /// The same direction and irradiance wherever the point (none where it is black).
    #[inline(always)]
    fn sample_li(&self, _p: V3<R>, _u: (R, R)) -> LaneLightSample<R, S> {
        LaneLightSample {
            wi: -self.direction,
            li: self.irradiance,
            dist: R::splat(f32::INFINITY),
            pdf: R::splat(1.0),
            ok: R::not(self.irradiance.is_black()),
        }
    }
}

impl LightGather for DirectionalLanes<f32> {
    type Lanes<L: Lane8> = DirectionalLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> DirectionalLanes<L> {
        DirectionalLanes {
            direction: V3::gather(one, |l| l.direction),
            irradiance: V3::gather(one, |l| l.irradiance),
        }
    }
}

impl Directional {
    /// The one-lane instance of the arithmetic.
    #[inline(always)]
    pub fn lanes(&self) -> DirectionalLanes<f32> {
        DirectionalLanes {
            direction: self.direction.into(),
            irradiance: self.irradiance.into(),
        }
    }

    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        self.lanes().sample_li(p.into(), (0.0, 0.0)).one(true)
    }

    /// A ray along the light's direction from a point of the disk that covers the scene.
    pub fn sample_le(&self, u: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
        Some(EmissionSample {
            ray: Ray::new(disk_origin(sphere, self.direction, u), self.direction),
            normal: self.direction,
            le: self.irradiance,
            pdf_pos: disk_pdf(sphere),
            pdf_dir: 1.0,
        })
    }

    pub fn power(&self, scene_radius: f32) -> f32 {
        std::f32::consts::PI * scene_radius * scene_radius * self.irradiance.luminance()
    }
}

impl LightModel for Directional {
    delta_light_answers!();

    fn sample_li(&self, p: Vec3, _u: Vec2, _strategy: AreaSampling) -> Option<LightSample> {
        Directional::sample_li(self, p)
    }
    /// A single direction of travel: no shadow ray joins another vertex to it.
    fn connectible(&self) -> bool {
        false
    }
    fn sample_le(&self, u_pos: Vec2, _u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
        Directional::sample_le(self, u_pos, sphere)
    }
    fn pdf_le(&self, _dir: Vec3, _normal: Vec3, sphere: SceneSphere) -> (f32, f32) {
        (disk_pdf(sphere), 0.0)
    }
    fn is_infinite(&self) -> bool {
        true
    }
    fn power(&self, scene_radius: f32) -> f32 {
        Directional::power(self, scene_radius)
    }
}
