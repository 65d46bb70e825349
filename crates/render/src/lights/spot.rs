//! A spot light: a point light restricted to a cone, with a smooth falloff from the inner
//! cone angle to the outer one (pbrt-v4's smoothstep falloff).
//!
//! Native format: `type = "spot"`, `position` (required), `target` (default
//! `position + [0, -1, 0]`), `intensity` (colour, default `[1, 1, 1]`), `cone_angle`
//! (degrees, half-angle of the lit cone, default 30), `falloff_start` (degrees, from 0 to
//! `cone_angle`, default the smaller of 25 and `cone_angle`).

use super::lanes::{delta_sample_lanes, LaneLightSample, LightGather, LightKernel};
use super::{delta_light_answers, AreaSampling, EmissionSample, LightModel, LightSample, SceneSphere};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{warp, Frame, Ray, Rgb};

#[derive(Clone, Debug, PartialEq)]
pub struct Spot {
    pub position: Vec3,
    /// Unit axis of the cone.
    pub direction: Vec3,
    pub intensity: Rgb,
    pub cos_total: f32,
    pub cos_falloff_start: f32,
}

impl Default for Spot {
    /// The native format's defaults: pointing down, a 30-degree cone whose falloff starts
    /// at 25 degrees.
    fn default() -> Self {
        Spot::new(Vec3::ZERO, -Vec3::Y, Rgb::WHITE, 30.0, 25.0)
    }
}

impl Spot {
    pub fn new(position: Vec3, direction: Vec3, intensity: Rgb, cone_angle: f32, falloff_start: f32) -> Self {
        Spot {
            position,
            direction: direction.normalize(),
            intensity,
            cos_total: cone_angle.to_radians().cos(),
            cos_falloff_start: falloff_start.min(cone_angle).to_radians().cos(),
        }
    }

    /// The fraction of `intensity` emitted at angle acos(`cos_theta`) from the axis.
    pub fn falloff(&self, cos_theta: f32) -> f32 {
        self.lanes().falloff(cos_theta)
    }

    /// The one-lane instance of the arithmetic.
    #[inline(always)]
    pub fn lanes(&self) -> SpotLanes<f32> {
        SpotLanes {
            position: self.position.into(),
            direction: self.direction.into(),
            intensity: self.intensity.into(),
            cos_total: self.cos_total,
            cos_falloff_start: self.cos_falloff_start,
        }
    }

    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        self.lanes().sample_li(p.into(), (0.0, 0.0)).one(true)
    }

    /// A ray in a direction uniform over the lit cone, carrying the falloff's intensity.
    pub fn sample_le(&self, u: Vec2) -> Option<EmissionSample> {
        let local = warp::uniform_cone(u, self.cos_total);
        let dir = Frame::from_normal(self.direction).to_world(local);
        Some(EmissionSample {
            ray: Ray::new(self.position, dir),
            normal: Vec3::ZERO,
            le: self.intensity * self.falloff(local.z),
            pdf_pos: 1.0,
            pdf_dir: warp::uniform_cone_pdf(local, self.cos_total),
        })
    }

    /// Density of [`Spot::sample_le`]'s direction `dir`.
    pub fn pdf_dir(&self, dir: Vec3) -> f32 {
        let cos = dir.dot(self.direction);
        if cos >= self.cos_total {
            warp::uniform_cone_pdf(Vec3::Z, self.cos_total)
        } else {
            0.0
        }
    }

    pub fn power(&self) -> f32 {
        // pbrt-v4: 2 pi (1 - (cos_start + cos_total) / 2) approximates the falloff's solid angle.
        self.intensity.luminance()
            * 2.0
            * std::f32::consts::PI
            * (1.0 - 0.5 * (self.cos_falloff_start + self.cos_total))
    }
}

/// A spot light in lanes of any [`Real`] type.
#[derive(Clone, Copy, Debug)]
pub struct SpotLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub position: V3<R>,
    pub direction: V3<R>,
    pub intensity: S,
    pub cos_total: R,
    pub cos_falloff_start: R,
}

impl<R: Real, S: Spectrum<R>> SpotLanes<R, S> {
    /// The same light carrying the payload `T`, its colour converted by `to` (as a
    /// spectral renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(S) -> T) -> SpotLanes<R, T> {
        SpotLanes {
            position: self.position,
            direction: self.direction,
            intensity: to(self.intensity),
            cos_total: self.cos_total,
            cos_falloff_start: self.cos_falloff_start,
        }
    }

    /// The fraction of the intensity emitted at angle acos(`cos_theta`) from the axis:
    /// pbrt-v4's smoothstep between the cone's edge and the falloff's start, or a hard
    /// edge where the falloff starts at the edge.
    #[inline(always)]
    pub fn falloff(&self, cos_theta: R) -> R {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let hard = R::select(cos_theta.cmp_ge(self.cos_total), one, zero);
        let x = (cos_theta - self.cos_total) / (self.cos_falloff_start - self.cos_total);
        // `f32::clamp(0, 1)`: NaN stays NaN.
        let x = R::select(x.cmp_lt(zero), zero, x);
        let x = R::select(x.cmp_gt(one), one, x);
        let smooth = x * x * (R::splat(3.0) - R::splat(2.0) * x);
        R::select(self.cos_falloff_start.cmp_le(self.cos_total), hard, smooth)
    }
}

impl<R: Real, S: Spectrum<R>> LightKernel<R, S> for SpotLanes<R, S> {
    #[inline(always)]
    fn sample_li(&self, p: V3<R>, _u: (R, R)) -> LaneLightSample<R, S> {
        let mut s = delta_sample_lanes(p, self.position, self.intensity);
        let f = self.falloff((-s.wi).dot(self.direction));
        s.li = s.li.scale(f);
        s.ok = R::and(s.ok, f.cmp_gt(R::splat(0.0)));
        s
    }
}

impl LightGather for SpotLanes<f32> {
    type Lanes<L: Lane8> = SpotLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> SpotLanes<L> {
        SpotLanes {
            position: V3::gather(one, |l| l.position),
            direction: V3::gather(one, |l| l.direction),
            intensity: V3::gather(one, |l| l.intensity),
            cos_total: L::from_array(one.map(|l| l.cos_total)),
            cos_falloff_start: L::from_array(one.map(|l| l.cos_falloff_start)),
        }
    }
}

impl LightModel for Spot {
    delta_light_answers!();

    fn sample_li(&self, p: Vec3, _u: Vec2, _strategy: AreaSampling) -> Option<LightSample> {
        Spot::sample_li(self, p)
    }
    fn connectible(&self) -> bool {
        true
    }
    fn sample_le(&self, _u_pos: Vec2, u_dir: Vec2, _sphere: SceneSphere) -> Option<EmissionSample> {
        Spot::sample_le(self, u_dir)
    }
    fn pdf_le(&self, dir: Vec3, _normal: Vec3, _sphere: SceneSphere) -> (f32, f32) {
        (0.0, self.pdf_dir(dir))
    }
    fn is_infinite(&self) -> bool {
        false
    }
    fn power(&self, _scene_radius: f32) -> f32 {
        Spot::power(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_and_falloff() {
        let s = Spot::new(Vec3::ZERO, Vec3::NEG_Y, Rgb::WHITE, 30.0, 20.0);
        assert_eq!(s.sample_li(Vec3::new(0.0, -2.0, 0.0)).unwrap().li, Rgb::splat(0.25));
        let at = |deg: f32| Vec3::new(deg.to_radians().tan(), -1.0, 0.0);
        assert!(s.sample_li(at(31.0)).is_none());
        let mid = s.sample_li(at(25.0)).unwrap().li.r * at(25.0).length_squared();
        assert!(mid > 0.0 && mid < 1.0);
        assert!((s.sample_li(at(19.0)).unwrap().li.r * at(19.0).length_squared() - 1.0).abs() < 1e-5);
    }
}
