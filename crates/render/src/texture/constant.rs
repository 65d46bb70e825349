//! A constant colour: the texture of every plain `[r, g, b]` in a scene.

use super::TextureModel;
use glam::Vec2;
use penumbra_core::Rgb;

impl TextureModel for Rgb {
    fn eval(&self, _uv: Vec2) -> Rgb {
        *self
    }

    fn min_value(&self) -> Rgb {
        *self
    }

    fn max_value(&self) -> Rgb {
        *self
    }
}
