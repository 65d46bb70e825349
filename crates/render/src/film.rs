//! The film: per-pixel weighted sums of radiance samples in linear RGB (and of the AOVs
//! when asked for), the number of samples per pixel, and a count of rejected (NaN or
//! infinite) samples. Tiles accumulate one pass in single precision ([`Pixel`]); the film
//! adds the passes in double precision ([`Film`]).
//!
//! Beside the filtered sums, a splat layer takes what samples add to pixels other than
//! their own (light paths connected to the camera, Veach 1997 section 10.2): each pass
//! traces one light path per pixel sample, and the camera's importance is normalised over
//! the whole film, so a pixel's splats summed over a pass estimate its value, and the
//! image is the filtered mean plus the splat sum over the samples per pixel. The driver
//! adds a pass's splats tile by tile in tile order, so the sums do not depend on threads.

use glam::Vec4;
use penumbra_core::Rgb;
use std::collections::BTreeMap;

/// One pixel of a tile's buffer during a pass (16 bytes, aligned: one SIMD register).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(16))]
pub struct Pixel {
    /// Sum of filter weight times radiance.
    pub sum: Rgb,
    /// Sum of filter weights.
    pub weight: f32,
}

impl Pixel {
    /// Adds a weighted sample, or a weighted share of one taken in a neighbouring pixel
    /// (the pixel's own sample count is kept apart).
    #[inline(always)]
    pub fn add(&mut self, radiance: Rgb, weight: f32) {
        // The four sums in one SIMD add: the same floats as channel by channel.
        let s = Vec4::new(self.sum.r, self.sum.g, self.sum.b, self.weight)
            + Vec4::new(radiance.r, radiance.g, radiance.b, 1.0) * weight;
        (self.sum, self.weight) = (Rgb::new(s.x, s.y, s.z), s.w);
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

/// Channels of the auxiliary outputs (AOVs): albedo (RGB), shading normal (XYZ), depth.
pub const AOV_CHANNELS: usize = 7;
/// The AOV channel names, as EXR layers.
pub const AOV_NAMES: [&str; AOV_CHANNELS] = [
    "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "depth.Z",
];

/// One pixel of the film: weighted sums in double precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilmPixel {
    pub sum: [f64; 3],
    pub weight: f64,
}

impl FilmPixel {
    /// Adds one pass's sums of the pixel.
    #[inline]
    pub fn add(&mut self, p: &Pixel) {
        for (s, v) in self.sum.iter_mut().zip(p.sum.to_array()) {
            *s += v as f64;
        }
        self.weight += p.weight as f64;
    }

    /// The pixel's estimate: the weighted mean of its samples (black without weight).
    pub fn value(&self) -> Rgb {
        if self.weight > 0.0 {
            let [r, g, b] = self.sum.map(|s| (s / self.weight) as f32);
            Rgb::new(r, g, b)
        } else {
            Rgb::BLACK
        }
    }
}

/// Adds one pass's AOV sums of a pixel to the film's.
#[inline]
pub fn add_aov(sums: &mut [f64; AOV_CHANNELS], a: &[f32; AOV_CHANNELS]) {
    for (s, v) in sums.iter_mut().zip(a) {
        *s += *v as f64;
    }
}

/// The accumulated state of a progressive render: every pixel's sums over the passes done
/// so far, one pass per sample index, added in sample order. Because each pass is added
/// whole and in order, a render stopped after any pass and resumed gives exactly the sums
/// of an uninterrupted one.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pixels: Vec<FilmPixel>,
    /// Weighted sums of the AOV channels, [`AOV_CHANNELS`] per pixel, when asked for.
    pub aovs: Option<Vec<[f64; AOV_CHANNELS]>>,
    /// Sample indices done: every pixel has this many samples.
    pub samples_per_pixel: u32,
    /// Samples dropped because their radiance was not finite.
    pub rejected: u64,
    /// Sums of the splats each pixel received (empty until the first splat).
    pub splats: Vec<[f64; 3]>,
    /// What the splat sums are multiplied by in the image (1, except for Metropolis light
    /// transport, whose normalisation is estimated as it renders).
    pub splat_scale: f64,
    /// Images kept apart from the film's own ([`Splat::layer`] > 0; bidirectional path
    /// tracing's strategies when asked for), splat sums per pixel.
    pub layers: BTreeMap<u32, Vec<[f32; 3]>>,
}

/// What a sample adds to some pixel of the film, at film position `film` (pixels), beside
/// its own radiance estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    pub film: glam::Vec2,
    pub value: Rgb,
    /// 0: the image; else a separate image of the film's [`Film::layers`].
    pub layer: u32,
}

impl Film {
    pub fn new(width: u32, height: u32, aovs: bool) -> Self {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            pixels: vec![FilmPixel::default(); n],
            aovs: aovs.then(|| vec![[0.0; AOV_CHANNELS]; n]),
            samples_per_pixel: 0,
            rejected: 0,
            splats: Vec::new(),
            splat_scale: 1.0,
            layers: BTreeMap::new(),
        }
    }

    /// Adds `value` to the splat sum of pixel `index` (row by row from the top) of the
    /// image (`layer` 0) or of a separate layer.
    pub fn add_splat(&mut self, layer: u32, index: usize, value: Rgb) {
        let n = self.pixels.len();
        if layer != 0 {
            let sums = self.layers.entry(layer).or_insert_with(|| vec![[0.0; 3]; n]);
            for (s, v) in sums[index].iter_mut().zip(value.to_array()) {
                *s += v;
            }
            return;
        }
        if self.splats.is_empty() {
            self.splats = vec![[0.0; 3]; n];
        }
        for (s, v) in self.splats[index].iter_mut().zip(value.to_array()) {
            *s += v as f64;
        }
    }

    /// The separate layers' images (splat sums over the samples per pixel), by layer.
    pub fn layer_images(&self) -> Vec<(u32, Vec<Rgb>)> {
        let per_sample = 1.0 / self.samples_per_pixel.max(1) as f32;
        self.layers
            .iter()
            .map(|(&k, sums)| {
                (
                    k,
                    sums.iter().map(|&[r, g, b]| Rgb::new(r, g, b) * per_sample).collect(),
                )
            })
            .collect()
    }

    pub fn pixel(&self, x: u32, y: u32) -> &FilmPixel {
        &self.pixels[self.index(x, y)]
    }

    fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    pub fn pixels(&self) -> &[FilmPixel] {
        &self.pixels
    }

    pub fn pixels_mut(&mut self) -> &mut [FilmPixel] {
        &mut self.pixels
    }

    /// The image: every pixel's estimate (its filtered mean plus its splats per sample),
    /// row by row from the top.
    pub fn image(&self) -> Vec<Rgb> {
        let per_sample = self.splat_scale / self.samples_per_pixel.max(1) as f64;
        self.pixels
            .iter()
            .enumerate()
            .map(|(i, p)| match self.splats.get(i) {
                Some(s) => {
                    let [r, g, b] = s.map(|s| (s * per_sample) as f32);
                    p.value() + Rgb::new(r, g, b)
                }
                None => p.value(),
            })
            .collect()
    }

    /// The AOV images (each channel's weighted mean), one per entry of [`AOV_NAMES`].
    pub fn aov_images(&self) -> Option<Vec<Vec<f32>>> {
        let aovs = self.aovs.as_ref()?;
        Some(
            (0..AOV_CHANNELS)
                .map(|c| {
                    aovs.iter()
                        .zip(&self.pixels)
                        .map(|(a, p)| if p.weight > 0.0 { (a[c] / p.weight) as f32 } else { 0.0 })
                        .collect()
                })
                .collect(),
        )
    }

    /// Total samples taken.
    pub fn samples(&self) -> u64 {
        self.samples_per_pixel as u64 * self.width as u64 * self.height as u64
    }
}
