//! An isotropic point light: radiant intensity `intensity` (W/sr per channel) from
//! `position`; irradiance falls off as 1/r^2.
//!
//! Native format: `type = "point"`, `position` (required), `intensity` (colour, default
//! `[1, 1, 1]`).

use super::{delta_sample, LightSample};
use glam::Vec3;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub position: Vec3,
    pub intensity: Rgb,
}

impl Point {
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        delta_sample(p, self.position, self.intensity)
    }

    pub fn power(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.intensity.luminance()
    }
}
