//! Lambertian reflection: f = ρ / π on the front side, sampled by the cosine-weighted
//! hemisphere (Malley's method), so that the weight f cos θ / pdf is ρ.

use super::{same_hemisphere, BsdfModel, BsdfSample, TransportMode};
use glam::{Vec2, Vec3};
use penumbra_core::{warp, Rgb};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    pub reflectance: Rgb,
}

impl BsdfModel for Diffuse {
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Rgb {
        if wo.z > 0.0 && wi.z > 0.0 {
            self.reflectance * FRAC_1_PI
        } else {
            Rgb::BLACK
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        if wo.z > 0.0 && same_hemisphere(wo, wi) {
            warp::cosine_hemisphere_pdf(wi)
        } else {
            0.0
        }
    }

    fn sample(&self, wo: Vec3, _u: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = warp::cosine_hemisphere(u);
        let pdf = warp::cosine_hemisphere_pdf(wi);
        (pdf > 0.0).then_some(BsdfSample {
            wi,
            weight: self.reflectance,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    fn has_smooth(&self) -> bool {
        !self.reflectance.is_black()
    }

    fn albedo(&self) -> Rgb {
        self.reflectance
    }
}
