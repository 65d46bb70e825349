//! Image textures: linear RGB pixels bilinearly filtered between pixel centres, continued
//! beyond [0, 1] by a wrap mode per axis, repeated every 1/`scale` texture units.
//!
//! Native format: `{ type = "image", file = "wood.png", scale = 1 }` (docs/scene-format.md);
//! Mitsuba's `bitmap`, pbrt's `imagemap` and glTF's textures map onto it.

use super::TextureModel;
use glam::Vec2;
use penumbra_core::lanes::{Real, V3};
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
        self.bilinear_lanes(uv.x, uv.y).into()
    }

    /// [`TextureImage::bilinear`] per lane of any [`Real`] type: the weights in lanes, the
    /// four pixels of each lane gathered by the lane's own indices. Black where a
    /// coordinate is not finite.
    #[inline(always)]
    pub fn bilinear_lanes<R: Real>(&self, u: R, v: R) -> V3<R> {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = u * R::splat(w as f32) - R::splat(0.5);
        let y = (R::splat(1.0) - v) * R::splat(h as f32) - R::splat(0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // Each lane's four pixels, (left, right) x (top, bottom), black where a wrap gives
        // none, by corner and channel. Cells beyond 2^40 pixels are as far as
        // float coordinates resolve anyway (and keep `i + 1` from overflowing).
        let far = (1i64 << 40) as f32;
        let [r00, g00, b00, r10, g10, b10, r01, g01, b01, r11, g11, b11] = R::map_lanes([x0, y0], |_, [x0, y0]| {
            let (i, j) = (x0.clamp(-far, far) as i64, y0.clamp(-far, far) as i64);
            let column = |i| self.wrap[0].pixel(i, w);
            let row = |j| self.wrap[1].pixel(j, h).map(|j| j * w);
            let (left, right, top, bottom) = (column(i), column(i + 1), row(j), row(j + 1));
            let at = |x: Option<i64>, y: Option<i64>| match (x, y) {
                (Some(x), Some(y)) => self.pixels[(y + x) as usize],
                _ => Rgb::BLACK,
            };
            let [a, b, c, d] = [at(left, top), at(right, top), at(left, bottom), at(right, bottom)];
            [a.r, a.g, a.b, b.r, b.g, b.b, c.r, c.g, c.b, d.r, d.g, d.b]
        });
        let (one_x, one_y) = (R::splat(1.0) - fx, R::splat(1.0) - fy);
        let top = V3::new(r00, g00, b00).scale(one_x) + V3::new(r10, g10, b10).scale(fx);
        let bottom = V3::new(r01, g01, b01).scale(one_x) + V3::new(r11, g11, b11).scale(fx);
        let value = top.scale(one_y) + bottom.scale(fy);
        V3::select(R::and(x.is_finite(), y.is_finite()), value, V3::splat(0.0))
    }
}

/// An image texture: the image, repeated every 1/`scale` units of texture coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    pub image: Arc<TextureImage>,
    pub scale: f32,
}

impl TextureModel for ImageTexture {
    #[inline(always)]
    fn eval_lanes<R: Real>(&self, u: R, v: R) -> V3<R> {
        let scale = R::splat(self.scale);
        self.image.bilinear_lanes(u * scale, v * scale)
    }

    /// The darkest pixel, or black where a wrap mode shows black beyond the image.
    fn min_value(&self) -> Rgb {
        let outside = if self.image.wrap.contains(&Wrap::Black) {
            Rgb::BLACK
        } else {
            Rgb::splat(f32::INFINITY)
        };
        self.image.pixels.iter().fold(outside, |a, &p| a.min(p))
    }

    fn max_value(&self) -> Rgb {
        self.image
            .pixels
            .iter()
            .fold(Rgb::splat(f32::NEG_INFINITY), |a, &p| a.max(p))
    }
}
