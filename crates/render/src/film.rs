//! The film: per-pixel weighted sums of radiance samples in linear float RGB, with sample
//! counts and a count of rejected (NaN or infinite) samples.

use penumbra_core::Rgb;

/// One pixel's accumulated samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pixel {
    /// Sum of filter weight times radiance.
    pub sum: Rgb,
    /// Sum of filter weights.
    pub weight: f32,
    /// Samples taken in this pixel, including rejected ones.
    pub samples: u32,
}

impl Pixel {
    /// Adds a weighted sample, or a weighted share of one taken in a neighbouring pixel
    /// (the pixel's own sample count is kept apart).
    pub fn add(&mut self, radiance: Rgb, weight: f32) {
        self.sum += radiance * weight;
        self.weight += weight;
    }

    /// Adds everything `other` accumulated.
    pub fn merge(&mut self, other: &Pixel) {
        self.sum += other.sum;
        self.weight += other.weight;
        self.samples += other.samples;
    }

    /// The pixel's estimate: the weighted mean of its samples (black without samples).
    pub fn value(&self) -> Rgb {
        if self.weight > 0.0 {
            self.sum / self.weight
        } else {
            Rgb::BLACK
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pixels: Vec<Pixel>,
    /// Samples dropped because their radiance was not finite.
    pub rejected: u64,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: vec![Pixel::default(); width as usize * height as usize],
            rejected: 0,
        }
    }

    pub fn pixel(&self, x: u32, y: u32) -> &Pixel {
        &self.pixels[self.index(x, y)]
    }

    fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    pub fn pixel_mut(&mut self, x: u32, y: u32) -> &mut Pixel {
        let i = self.index(x, y);
        &mut self.pixels[i]
    }

    /// The image: every pixel's estimate, row by row from the top.
    pub fn image(&self) -> Vec<Rgb> {
        self.pixels.iter().map(Pixel::value).collect()
    }

    /// Total samples taken.
    pub fn samples(&self) -> u64 {
        self.pixels.iter().map(|p| p.samples as u64).sum()
    }
}
