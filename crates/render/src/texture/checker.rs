//! Checkerboards: squares of side `size` in texture units, alternating `even` and `odd`.
//!
//! Native format: `{ type = "checker", even = [..], odd = [..], size = 0.125 }`; Mitsuba's
//! `checkerboard` and pbrt's `checkerboard` map onto it.

use super::TextureModel;
use penumbra_core::lanes::{Real, V3};
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
    /// The square's parity: the sum of the cell indices, less twice its half's floor, is
    /// 0 or 1 (exactly, since the indices are integers; an infinite or NaN coordinate
    /// gives NaN, the odd colour).
    #[inline(always)]
    fn eval_lanes<R: Real>(&self, u: R, v: R) -> V3<R> {
        let size = R::splat(self.size);
        let sum = (u / size).floor() + (v / size).floor();
        let parity = sum - R::splat(2.0) * (sum * R::splat(0.5)).floor();
        V3::select(
            parity.cmp_lt(R::splat(1.0)),
            V3::splat_rgb(self.even),
            V3::splat_rgb(self.odd),
        )
    }

    fn min_value(&self) -> Rgb {
        self.even.min(self.odd)
    }

    fn max_value(&self) -> Rgb {
        self.even.max(self.odd)
    }
}
