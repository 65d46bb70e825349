//! Linear RGB radiance and reflectance values.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

/// A linear (not gamma-encoded) RGB triple in the sRGB/Rec.709 primaries.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgb {
    pub r: f32,
    pub g: f32,
    pub b: f32,
}

impl Rgb {
    pub const BLACK: Rgb = Rgb::splat(0.0);
    pub const WHITE: Rgb = Rgb::splat(1.0);

    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Rgb { r, g, b }
    }

    pub const fn splat(v: f32) -> Self {
        Rgb { r: v, g: v, b: v }
    }

    pub fn max_component(self) -> f32 {
        self.r.max(self.g).max(self.b)
    }

    /// Luminance Y of linear Rec.709 RGB.
    /// The smaller of each channel.
    pub fn min(self, o: Rgb) -> Rgb {
        Rgb::new(self.r.min(o.r), self.g.min(o.g), self.b.min(o.b))
    }

    /// The larger of each channel.
    pub fn max(self, o: Rgb) -> Rgb {
        Rgb::new(self.r.max(o.r), self.g.max(o.g), self.b.max(o.b))
    }

    /// The mean of the three channels.
    pub fn mean(self) -> f32 {
        (self.r + self.g + self.b) / 3.0
    }

    pub fn luminance(self) -> f32 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }

    pub fn is_black(self) -> bool {
        self.r == 0.0 && self.g == 0.0 && self.b == 0.0
    }

    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    pub fn to_array(self) -> [f32; 3] {
        [self.r, self.g, self.b]
    }

    pub fn map(self, f: impl Fn(f32) -> f32) -> Rgb {
        Rgb::new(f(self.r), f(self.g), f(self.b))
    }
}

impl From<[f32; 3]> for Rgb {
    fn from(v: [f32; 3]) -> Self {
        Rgb::new(v[0], v[1], v[2])
    }
}

impl Add for Rgb {
    type Output = Rgb;
    fn add(self, o: Rgb) -> Rgb {
        Rgb::new(self.r + o.r, self.g + o.g, self.b + o.b)
    }
}

impl AddAssign for Rgb {
    fn add_assign(&mut self, o: Rgb) {
        *self = *self + o;
    }
}

impl Sub for Rgb {
    type Output = Rgb;
    fn sub(self, o: Rgb) -> Rgb {
        Rgb::new(self.r - o.r, self.g - o.g, self.b - o.b)
    }
}

impl Mul for Rgb {
    type Output = Rgb;
    fn mul(self, o: Rgb) -> Rgb {
        Rgb::new(self.r * o.r, self.g * o.g, self.b * o.b)
    }
}

impl MulAssign for Rgb {
    fn mul_assign(&mut self, o: Rgb) {
        *self = *self * o;
    }
}

impl Mul<f32> for Rgb {
    type Output = Rgb;
    fn mul(self, s: f32) -> Rgb {
        Rgb::new(self.r * s, self.g * s, self.b * s)
    }
}

impl Mul<Rgb> for f32 {
    type Output = Rgb;
    fn mul(self, c: Rgb) -> Rgb {
        c * self
    }
}

impl Div<f32> for Rgb {
    type Output = Rgb;
    fn div(self, s: f32) -> Rgb {
        self * (1.0 / s)
    }
}
