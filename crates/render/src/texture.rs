//! Textures: colours that vary over a surface, looked up by texture coordinates.
//!
//! Native format: a colour is `[r, g, b]`, or a table: `{ type = "checker", even = [..],
//! odd = [..], size = 0.125 }` (squares of side `size` in texture units, alternating `even`
//! and `odd`) or `{ type = "image", file = "wood.png", scale = 1 }` (an image repeated every
//! 1/scale texture units, bilinearly filtered; see docs/scene-format.md).

use glam::Vec2;
use penumbra_core::Rgb;
use std::sync::Arc;

/// The pixels of an image texture: linear RGB, row 0 at the top (v = 1).
#[derive(Clone, Debug, PartialEq)]
pub struct TextureImage {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Rgb>,
}

impl TextureImage {
    /// Bilinear interpolation of the four pixels around texture point `uv`, the image
    /// repeated in both directions; pixel centres at ((x + 0.5)/w, 1 - (y + 0.5)/h).
    pub fn bilinear(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = uv.x * w as f32 - 0.5;
        let y = (1.0 - uv.y) * h as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Rgb::BLACK;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| self.pixels[(j.rem_euclid(h) * w + i.rem_euclid(w)) as usize];
        let (i, j) = (x0 as i64, y0 as i64);
        (at(i, j) * (1.0 - fx) + at(i + 1, j) * fx) * (1.0 - fy)
            + (at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx) * fy
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Constant(Rgb),
    Checker {
        even: Rgb,
        odd: Rgb,
        size: f32,
    },
    /// An image, repeated every 1/`scale` units of texture coordinates.
    Image {
        image: Arc<TextureImage>,
        scale: f32,
    },
}

impl Texture {
    pub fn eval(&self, uv: Vec2) -> Rgb {
        match *self {
            Texture::Image { ref image, scale } => image.bilinear(uv * scale),
            Texture::Constant(c) => c,
            Texture::Checker { even, odd, size } => {
                let cell = (uv / size).floor();
                if (cell.x + cell.y).rem_euclid(2.0) < 1.0 {
                    even
                } else {
                    odd
                }
            }
        }
    }

    /// The smallest value the texture takes, per channel.
    pub fn min_value(&self) -> Rgb {
        match *self {
            Texture::Constant(c) => c,
            Texture::Image { ref image, .. } => image.pixels.iter().fold(Rgb::splat(f32::INFINITY), |a, &p| a.min(p)),
            Texture::Checker { even, odd, .. } => even.min(odd),
        }
    }

    /// The largest value the texture takes, per channel.
    pub fn max_value(&self) -> Rgb {
        match *self {
            Texture::Constant(c) => c,
            Texture::Image { ref image, .. } => image
                .pixels
                .iter()
                .fold(Rgb::splat(f32::NEG_INFINITY), |a, &p| a.max(p)),
            Texture::Checker { even, odd, .. } => even.max(odd),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_textures_interpolate_between_pixel_centres_and_repeat() {
        // 2 x 2: top row black, white; bottom row red, blue.
        let image = TextureImage {
            width: 2,
            height: 2,
            pixels: vec![Rgb::BLACK, Rgb::WHITE, Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 0.0, 1.0)],
        };
        // Pixel centres: top-left at uv (0.25, 0.75), bottom-right at (0.75, 0.25).
        assert_eq!(image.bilinear(Vec2::new(0.25, 0.75)), Rgb::BLACK);
        assert_eq!(image.bilinear(Vec2::new(0.75, 0.25)), Rgb::new(0.0, 0.0, 1.0));
        // Halfway between the top two: grey; the centre: the mean of all four.
        assert_eq!(image.bilinear(Vec2::new(0.5, 0.75)), Rgb::splat(0.5));
        let c = image.bilinear(Vec2::new(0.5, 0.5));
        assert!(
            (c.r - 0.5).abs() < 1e-6 && (c.g - 0.25).abs() < 1e-6 && (c.b - 0.5).abs() < 1e-6,
            "{c:?}"
        );
        // Repeats: u = 0 lies between the last and the first column.
        assert_eq!(image.bilinear(Vec2::new(0.0, 0.75)), Rgb::splat(0.5));
        assert_eq!(
            image.bilinear(Vec2::new(1.25, -0.25)),
            image.bilinear(Vec2::new(0.25, 0.75))
        );
        let t = Texture::Image {
            image: Arc::new(image),
            scale: 2.0,
        };
        assert_eq!(t.eval(Vec2::new(0.125, 0.375)), Rgb::BLACK);
        assert_eq!(t.max_value(), Rgb::WHITE);
        assert_eq!(t.min_value(), Rgb::BLACK);
    }

    #[test]
    fn checker_alternates() {
        let t = Texture::Checker {
            even: Rgb::WHITE,
            odd: Rgb::BLACK,
            size: 1.0,
        };
        assert_eq!(t.eval(Vec2::new(0.5, 0.5)), Rgb::WHITE);
        assert_eq!(t.eval(Vec2::new(1.5, 0.5)), Rgb::BLACK);
        assert_eq!(t.eval(Vec2::new(-0.5, 0.5)), Rgb::BLACK);
        assert_eq!(t.eval(Vec2::new(-0.5, -0.5)), Rgb::WHITE);
    }
}
