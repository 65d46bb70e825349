//! Textures: colours that vary over a surface, looked up by texture coordinates.
//!
//! Native format: a colour is `[r, g, b]`, or a table naming a kind (see each kind's file
//! and docs/scene-format.md). Adding a texture: a file in `texture/` whose type implements
//! [`TextureModel`], and one line in the `texture_kinds!` registry below.

mod checker;
mod constant;
mod image;

pub use checker::Checker;
pub use image::{ImageTexture, TextureImage, Wrap};

use glam::Vec2;
use penumbra_core::lanes::{Real, V3};
use penumbra_core::Rgb;

/// What every texture answers. A kind writes its lookup once, over the lane type
/// ([`TextureModel::eval_lanes`]); the scalar [`TextureModel::eval`] is its one-lane
/// instance.
pub trait TextureModel {
    /// The colour at texture coordinates (`u`, `v`), per lane of any [`Real`] type.
    fn eval_lanes<R: Real>(&self, u: R, v: R) -> V3<R>;
    /// The colour at texture coordinates `uv`.
    #[inline]
    fn eval(&self, uv: Vec2) -> Rgb {
        self.eval_lanes(uv.x, uv.y).into()
    }
    /// The smallest value the texture takes, per channel.
    fn min_value(&self) -> Rgb;
    /// The largest value the texture takes, per channel.
    fn max_value(&self) -> Rgb;
}

/// The registry of texture kinds: one line per kind (variant, type, name) generates
/// [`Texture`], its static dispatch and [`Texture::NAMES`].
macro_rules! texture_kinds {
    ($($variant:ident($ty:ty) = $name:literal),* $(,)?) => {
        /// The textures this renderer knows.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Texture {
            $($variant($ty)),*
        }

        impl Texture {
            /// Every kind's name, in registry order.
            pub const NAMES: &'static [&'static str] = &[$($name),*];

            pub fn name(&self) -> &'static str {
                match self {
                    $(Texture::$variant(_) => $name),*
                }
            }

            /// [`TextureModel::eval`].
            #[inline]
            pub fn eval(&self, uv: Vec2) -> Rgb {
                match self {
                    $(Texture::$variant(t) => t.eval(uv)),*
                }
            }

            /// [`TextureModel::eval_lanes`].
            #[inline(always)]
            pub fn eval_lanes<R: Real>(&self, u: R, v: R) -> V3<R> {
                match self {
                    $(Texture::$variant(t) => t.eval_lanes(u, v)),*
                }
            }

            /// [`TextureModel::min_value`].
            pub fn min_value(&self) -> Rgb {
                match self {
                    $(Texture::$variant(t) => t.min_value()),*
                }
            }

            /// [`TextureModel::max_value`].
            pub fn max_value(&self) -> Rgb {
                match self {
                    $(Texture::$variant(t) => t.max_value()),*
                }
            }
        }
    };
}

texture_kinds! {
    Constant(Rgb) = "constant",
    Checker(Checker) = "checker",
    Image(ImageTexture) = "image",
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

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
        let t = Texture::Image(ImageTexture {
            image: Arc::new(image),
            scale: 2.0,
        });
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
        let t = Texture::Checker(Checker {
            even: Rgb::WHITE,
            odd: Rgb::BLACK,
            size: 1.0,
        });
        assert_eq!(t.eval(Vec2::new(0.5, 0.5)), Rgb::WHITE);
        assert_eq!(t.eval(Vec2::new(1.5, 0.5)), Rgb::BLACK);
        assert_eq!(t.eval(Vec2::new(-0.5, 0.5)), Rgb::BLACK);
        assert_eq!(t.eval(Vec2::new(-0.5, -0.5)), Rgb::WHITE);
    }

    /// A case of every registered kind (images with every wrap mode).
    fn cases() -> Vec<Texture> {
        let image = |wrap| TextureImage {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| Rgb::new(i as f32, 5.0 - i as f32, 0.5)).collect(),
            wrap,
        };
        let mut cases = vec![
            Texture::Constant(Rgb::new(0.1, 0.2, 0.3)),
            Texture::Checker(Checker::default()),
            Texture::Checker(Checker {
                size: 0.3,
                ..Checker::default()
            }),
        ];
        for wrap in [
            [Wrap::Mirror, Wrap::Clamp],
            [Wrap::Repeat, Wrap::Black],
            [Wrap::Black, Wrap::Mirror],
        ] {
            cases.push(Texture::Image(ImageTexture {
                image: Arc::new(image(wrap)),
                scale: 1.5,
            }));
        }
        cases
    }

    /// Eight lanes give, lane by lane, the bits of the one-lane lookup (which the exact
    /// values of the tests above pin down), at random points, cell edges, huge, infinite
    /// and NaN coordinates.
    #[test]
    fn lanes_give_each_lane_the_scalar_bits() {
        use penumbra_core::lanes::{Lane8, F8};
        let special = [0.0, -0.0, 0.5, -0.5, 1.0, 1e30, -1e30, f32::INFINITY, f32::NAN, 2.5e7];
        let mut rng = penumbra_core::Pcg32::new(5, 2);
        let mut coordinate = |k: u32| {
            if rng.next_u32().is_multiple_of(4) {
                special[(rng.next_u32() as usize + k as usize) % special.len()]
            } else {
                rng.next_f32() * 8.0 - 4.0
            }
        };
        for t in &cases() {
            for round in 0..2_000 {
                let u: [f32; 8] = std::array::from_fn(|k| coordinate(round + k as u32));
                let v: [f32; 8] = std::array::from_fn(|k| coordinate(round + 3 * k as u32));
                let lanes = t.eval_lanes(F8::from_array(u), F8::from_array(v)).to_lanes();
                for k in 0..8 {
                    let one = t.eval(Vec2::new(u[k], v[k]));
                    let bits = |c: [f32; 3]| c.map(f32::to_bits);
                    assert_eq!(
                        bits(lanes[k].to_array()),
                        bits([one.r, one.g, one.b]),
                        "{} at ({}, {})",
                        t.name(),
                        u[k],
                        v[k]
                    );
                }
            }
        }
    }

    /// Every registered kind has a case here, and each case's values lie within its
    /// `min_value` and `max_value` at 10,000 random points (wrapping beyond [0, 1] too).
    #[test]
    fn every_kind_stays_within_its_bounds() {
        let cases = cases();
        for name in Texture::NAMES {
            assert!(
                cases.iter().any(|t| t.name() == *name),
                "no case for texture kind {name}"
            );
        }
        let mut rng = penumbra_core::Pcg32::new(9, 4);
        for t in &cases {
            let (lo, hi) = (t.min_value(), t.max_value());
            for _ in 0..10_000 {
                let uv = Vec2::new(rng.next_f32(), rng.next_f32()) * 6.0 - Vec2::splat(3.0);
                let v = t.eval(uv);
                let inside = |v: f32, lo: f32, hi: f32| lo - 1e-6 <= v && v <= hi + 1e-6;
                assert!(
                    inside(v.r, lo.r, hi.r) && inside(v.g, lo.g, hi.g) && inside(v.b, lo.b, hi.b),
                    "{}: {v:?} outside {lo:?}..{hi:?} at {uv}",
                    t.name()
                );
            }
        }
    }
}
