//! Samplers: the random numbers of one pixel sample, handed out one dimension at a time.
//!
//! Every value is a pure function of (seed, pixel, sample index, dimension), so an image is
//! identical for any thread count or tile order. Parameters (`[render]` in the native format):
//! `sampler = "independent" | "stratified"` (default `stratified`).
//!
//! Adding a sampler: a new file here with a `fn sample_1d/sample_2d(&Key) -> ...` pair, one
//! variant in [`SamplerKind`] and one arm in each match below.

mod independent;
mod stratified;

use crate::hash::hash_words;
use glam::{UVec2, Vec2};

/// The sampling strategies a scene can choose.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Uniform random numbers, independent in every dimension.
    Independent,
    /// Stratified over the pixel's samples in every dimension: correlated multi-jittered
    /// patterns in 2D, jittered permuted strata in 1D (Kensler 2013).
    #[default]
    Stratified,
}

impl SamplerKind {
    pub const NAMES: [&'static str; 2] = ["independent", "stratified"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "independent" => Some(SamplerKind::Independent),
            "stratified" => Some(SamplerKind::Stratified),
            _ => None,
        }
    }
}

/// Identifies one dimension of one pixel sample: everything a value may depend on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Key {
    /// Hash of (seed, pixel, dimension): the same for every sample of the pixel.
    pub pattern: u64,
    /// The sample's index within the pixel.
    pub index: u32,
    /// Samples per pixel: the number of strata.
    pub count: u32,
}

/// The sampler state for one pixel: cheap to create, one per pixel sample.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    kind: SamplerKind,
    seed: u64,
    pixel: UVec2,
    spp: u32,
    index: u32,
    dimension: u32,
}

impl PixelSampler {
    pub fn new(kind: SamplerKind, seed: u64, spp: u32) -> Self {
        PixelSampler {
            kind,
            seed,
            pixel: UVec2::ZERO,
            spp: spp.max(1),
            index: 0,
            dimension: 0,
        }
    }

    /// Starts sample `index` of `pixel`; dimensions restart from zero.
    pub fn start(&mut self, pixel: UVec2, index: u32) {
        self.pixel = pixel;
        self.index = index;
        self.dimension = 0;
    }

    fn next_key(&mut self) -> Key {
        let d = self.dimension;
        self.dimension += 1;
        let pattern = hash_words(&[self.seed, self.pixel.x as u64, self.pixel.y as u64, d as u64]);
        Key {
            pattern,
            index: self.index,
            count: self.spp,
        }
    }

    pub fn next_1d(&mut self) -> f32 {
        let key = self.next_key();
        match self.kind {
            SamplerKind::Independent => independent::sample_1d(&key),
            SamplerKind::Stratified => stratified::sample_1d(&key),
        }
    }

    pub fn next_2d(&mut self) -> Vec2 {
        let key = self.next_key();
        match self.kind {
            SamplerKind::Independent => independent::sample_2d(&key),
            SamplerKind::Stratified => stratified::sample_2d(&key),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(kind: SamplerKind, spp: u32, pixel: UVec2) -> Vec<(f32, Vec2)> {
        let mut s = PixelSampler::new(kind, 42, spp);
        (0..spp)
            .map(|i| {
                s.start(pixel, i);
                let a = s.next_2d();
                (s.next_1d(), a)
            })
            .collect()
    }

    #[test]
    fn pure_function_of_pixel_and_index() {
        for kind in [SamplerKind::Independent, SamplerKind::Stratified] {
            let a = samples(kind, 16, UVec2::new(3, 4));
            assert_eq!(a, samples(kind, 16, UVec2::new(3, 4)));
            assert_ne!(a, samples(kind, 16, UVec2::new(4, 3)));
            // Out-of-order evaluation gives the same values.
            let mut s = PixelSampler::new(kind, 42, 16);
            s.start(UVec2::new(3, 4), 5);
            assert_eq!(s.next_2d(), a[5].1);
            for (x, p) in &a {
                assert!((0.0..1.0).contains(x) && (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            }
        }
    }

    #[test]
    fn stratified_fills_every_stratum() {
        for spp in [1, 2, 7, 16, 25, 30] {
            let s = samples(SamplerKind::Stratified, spp, UVec2::new(9, 1));
            // 1D: one sample in each of the spp strata.
            let mut strata: Vec<u32> = s.iter().map(|(x, _)| (x * spp as f32) as u32).collect();
            strata.sort();
            assert_eq!(strata, (0..spp).collect::<Vec<_>>(), "spp {spp}");
            // 2D, x: Kensler's pattern is an m x n jittered grid (m = floor(sqrt(spp)),
            // n = ceil(spp / m)) whose x values also fall in distinct strata of width 1/(mn).
            let m = (spp as f32).sqrt() as u32;
            let n = spp.div_ceil(m);
            let mut columns: Vec<u32> = s.iter().map(|(_, p)| (p.x * (m * n) as f32) as u32).collect();
            columns.sort();
            columns.dedup();
            assert_eq!(columns.len(), spp as usize, "x strata, spp {spp}");
            // 2D, y: each row of the N-rooks pattern holds one sample.
            let mut rows: Vec<u32> = s.iter().map(|(_, p)| (p.y * spp as f32) as u32).collect();
            rows.sort();
            assert_eq!(rows, (0..spp).collect::<Vec<_>>(), "spp {spp}");
        }
    }
}
