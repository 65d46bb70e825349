//! A constant colour: the texture of every plain `[r, g, b]` in a scene.

use super::TextureModel;
use penumbra_core::lanes::{Real, V3};
use penumbra_core::Rgb;

impl TextureModel for Rgb {
    #[inline(always)]
    fn eval_lanes<R: Real>(&self, _u: R, _v: R) -> V3<R> {
        V3::splat_rgb(*self)
    }

    fn min_value(&self) -> Rgb {
        *self
    }

    fn max_value(&self) -> Rgb {
        *self
    }
}
