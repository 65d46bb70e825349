//! Textures: colours that vary over a surface, looked up by texture coordinates.
//!
//! Native format: a colour is `[r, g, b]` or a table `{ type = "checker", even = [..],
//! odd = [..], size = 0.125 }`: squares of side `size` in texture units (scene units on
//! planes), alternating `even` and `odd`.

use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Constant(Rgb),
    Checker { even: Rgb, odd: Rgb, size: f32 },
}

impl Texture {
    pub fn eval(&self, uv: Vec2) -> Rgb {
        match *self {
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
            Texture::Checker { even, odd, .. } => Rgb::new(even.r.min(odd.r), even.g.min(odd.g), even.b.min(odd.b)),
        }
    }

    /// The largest value the texture takes, per channel.
    pub fn max_value(&self) -> Rgb {
        match *self {
            Texture::Constant(c) => c,
            Texture::Checker { even, odd, .. } => Rgb::new(even.r.max(odd.r), even.g.max(odd.g), even.b.max(odd.b)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
