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
            wrap: Default::default(),
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

    /// Beyond [0, 1] each wrap continues the image its way (a 2 x 1 image: pixel centres at
    /// u = 0.25 and 0.75).
    #[test]
    fn wraps_continue_the_image() {
        let (a, b) = (Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 0.0, 1.0));
        let image = |wrap: Wrap| TextureImage {
            width: 2,
            height: 1,
            pixels: vec![a, b],
            wrap: [wrap, Wrap::Repeat],
        };
        let at = |wrap: Wrap, u: f32| image(wrap).bilinear(Vec2::new(u, 0.5));
        assert_eq!(at(Wrap::Repeat, 1.25), a);
        assert_eq!(at(Wrap::Mirror, 1.25), b);
        assert_eq!(at(Wrap::Mirror, 1.75), a);
        assert_eq!(at(Wrap::Mirror, -0.25), a);
        assert_eq!(at(Wrap::Clamp, 1.75), b);
        assert_eq!(at(Wrap::Clamp, -3.0), a);
        assert_eq!(at(Wrap::Black, 1.75), Rgb::BLACK);
        assert_eq!(at(Wrap::Black, 1.0), b * 0.5);
        // Inside, every wrap is the same image.
        for wrap in [Wrap::Repeat, Wrap::Mirror, Wrap::Clamp, Wrap::Black] {
            assert_eq!(at(wrap, 0.5), (a + b) * 0.5);
        }
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
