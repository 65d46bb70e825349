//! Checkerboards: squares of side `size` in texture units, alternating `even` and `odd`.
//!
//! Native format: `{ type = "checker", even = [..], odd = [..], size = 0.125 }`; Mitsuba's
//! `checkerboard` and pbrt's `checkerboard` map onto it.

use super::TextureModel;
use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checker {
    pub even: Rgb,
    pub odd: Rgb,
    pub size: f32,
}

impl Default for Checker {
    /// Mitsuba's defaults: 0.4 and 0.2 grey, two squares per unit.
    fn default() -> Self {
        Checker {
            even: Rgb::splat(0.4),
            odd: Rgb::splat(0.2),
            size: 0.5,
        }
    }
}

impl TextureModel for Checker {
    fn eval(&self, uv: Vec2) -> Rgb {
        let cell = (uv / self.size).floor();
        if (cell.x + cell.y).rem_euclid(2.0) < 1.0 {
            self.even
        } else {
            self.odd
        }
    }

    fn min_value(&self) -> Rgb {
        self.even.min(self.odd)
    }

    fn max_value(&self) -> Rgb {
        self.even.max(self.odd)
    }
}
