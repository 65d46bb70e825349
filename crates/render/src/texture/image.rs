//! Image textures: linear RGB pixels bilinearly filtered between pixel centres, continued
//! beyond [0, 1] by a wrap mode per axis, repeated every 1/`scale` texture units.
//!
//! Native format: `{ type = "image", file = "wood.png", scale = 1 }` (docs/scene-format.md);
//! Mitsuba's `bitmap`, pbrt's `imagemap` and glTF's textures map onto it.

use super::TextureModel;
use glam::Vec2;
use penumbra_core::Rgb;
use std::sync::Arc;

/// The pixels of an image texture: linear RGB, row 0 at the top (v = 1).
#[derive(Clone, Debug, PartialEq)]
pub struct TextureImage {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Rgb>,
    /// What lies beyond the image along u and along v.
    pub wrap: [Wrap; 2],
}

/// What an image texture shows outside [0, 1] along one axis (glTF's wrap modes, Mitsuba's
/// `wrap_mode`, pbrt's `wrap`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image again.
    #[default]
    Repeat,
    /// The image mirrored, then again, and so on.
    Mirror,
    /// The edge pixels, stretched.
    Clamp,
    /// Black.
    Black,
}

impl Wrap {
    /// The pixel that `i` (any integer) stands for in a row of `n`; `None`: black.
    fn pixel(self, i: i64, n: i64) -> Option<i64> {
        match self {
            Wrap::Repeat => Some(i.rem_euclid(n)),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                Some(if m >= n { 2 * n - 1 - m } else { m })
            }
            Wrap::Clamp => Some(i.clamp(0, n - 1)),
            Wrap::Black => (0..n).contains(&i).then_some(i),
        }
    }
}

impl TextureImage {
    /// Bilinear interpolation of the four pixels around texture point `uv`, the image
    /// continued by its [`Wrap`]s; pixel centres at ((x + 0.5)/w, 1 - (y + 0.5)/h).
    pub fn bilinear(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = uv.x * w as f32 - 0.5;
        let y = (1.0 - uv.y) * h as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Rgb::BLACK;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| match (self.wrap[0].pixel(i, w), self.wrap[1].pixel(j, h)) {
            (Some(i), Some(j)) => self.pixels[(j * w + i) as usize],
            _ => Rgb::BLACK,
        };
        let (i, j) = (x0 as i64, y0 as i64);
        (at(i, j) * (1.0 - fx) + at(i + 1, j) * fx) * (1.0 - fy)
            + (at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx) * fy
    }
}

/// An image texture: the image, repeated every 1/`scale` units of texture coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    pub image: Arc<TextureImage>,
    pub scale: f32,
}

impl TextureModel for ImageTexture {
    fn eval(&self, uv: Vec2) -> Rgb {
        self.image.bilinear(uv * self.scale)
    }

    fn min_value(&self) -> Rgb {
        self.image
            .pixels
            .iter()
            .fold(Rgb::splat(f32::INFINITY), |a, &p| a.min(p))
    }

    fn max_value(&self) -> Rgb {
        self.image
            .pixels
            .iter()
            .fold(Rgb::splat(f32::NEG_INFINITY), |a, &p| a.max(p))
    }
}
