//! Samplers: the random numbers of one pixel sample, handed out one dimension at a time.
//!
//! Every value is a pure function of (seed, pixel, sample index, dimension), so an image is
//! identical for any thread count or tile order. Parameters (`[render]` in the native format):
//! `sampler = "independent" | "stratified" | "halton" | "sobol"` (default `sobol`: its every
//! prefix is well spread, so a render stopped early by `--time` or Ctrl-C is as good as its
//! sample count allows, and it is the cheapest of the low-discrepancy samplers).
//!
//! Adding a sampler: a new file here with a `fn sample_1d/sample_2d(&Key) -> ...` pair, one
//! variant in [`SamplerKind`] and one arm in each match below.

mod halton;
mod independent;
mod sobol;
mod sobol_lanes;
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
    Stratified,
    /// Halton points in bases 2 and 3, Owen-scrambled, index permuted per dimension pair.
    Halton,
    /// Sobol points, Owen-scrambled and shuffled by hashing (Burley 2020).
    #[default]
    Sobol,
}

impl SamplerKind {
    pub const NAMES: [&'static str; 4] = ["independent", "stratified", "halton", "sobol"];
    pub const ALL: [SamplerKind; 4] = [
        SamplerKind::Independent,
        SamplerKind::Stratified,
        SamplerKind::Halton,
        SamplerKind::Sobol,
    ];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "independent" => Some(SamplerKind::Independent),
            "stratified" => Some(SamplerKind::Stratified),
            "halton" => Some(SamplerKind::Halton),
            "sobol" => Some(SamplerKind::Sobol),
            _ => None,
        }
    }
}

/// The largest float below 1: samplers clamp to it so that values stay in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Identifies one dimension of one pixel sample: everything a value may depend on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Key {
    /// Hash of (seed, pixel, dimension): the same for every sample of the pixel.
    pub pattern: u64,
    /// The sample's index within the pixel.
    pub index: u32,
    /// `index.reverse_bits()`, worked out once per sample rather than once per dimension.
    pub index_reversed: u32,
    /// Samples per pixel: the number of strata.
    pub count: u32,
    /// The 2D stratified pattern's columns and rows for `count` samples.
    pub grid: [u32; 2],
}

impl Key {
    /// The `k`-th independent hash of the pattern: a seed for one scramble or permutation.
    pub fn seed(&self, k: u64) -> u64 {
        seed_of(self.pattern, k)
    }
}

/// [`Key::seed`] of a key's pattern.
#[inline]
pub(crate) fn seed_of(pattern: u64, k: u64) -> u64 {
    crate::hash::mix64(pattern ^ k.wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The hash of dimension `d` of the pixel hashed `pixel_hash`: SplitMix64's sequence
/// seeded with the pixel's hash (Steele et al. 2014), one mix per dimension.
#[inline(always)]
pub(crate) fn dimension_pattern(pixel_hash: u64, d: u32) -> u64 {
    crate::hash::mix64(pixel_hash.wrapping_add((d as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15)))
}

/// The sampler state for one pixel: cheap to create, one per pixel sample.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    kind: SamplerKind,
    seed: u64,
    spp: u32,
    grid: [u32; 2],
    index: u32,
    /// The independent sampler's key of this sample: the pixel's hash xor `mix64(index)`.
    key: u64,
    index_reversed: u32,
    dimension: u32,
    /// Hash of the seed and pixel, the start of the pixel's sequence of dimension hashes.
    pixel_hash: u64,
}

impl PixelSampler {
    pub fn new(kind: SamplerKind, seed: u64, spp: u32) -> Self {
        PixelSampler {
            kind,
            seed,
            spp: spp.max(1),
            grid: stratified::grid(spp.max(1)),
            index: 0,
            key: crate::hash::mix64(0),
            index_reversed: 0,
            dimension: 0,
            pixel_hash: 0,
        }
    }

    /// Starts sample `index` of `pixel`; dimensions restart from zero.
    pub fn start(&mut self, pixel: UVec2, index: u32) {
        self.index = index;
        self.index_reversed = index.reverse_bits();
        self.dimension = 0;
        self.pixel_hash = hash_words(&[self.seed, pixel.x as u64, pixel.y as u64]);
        self.key = self.pixel_hash ^ crate::hash::mix64(index as u64);
    }

    /// The hash of dimension `d` of this pixel ([`dimension_pattern`]).
    #[inline(always)]
    fn pattern(&self, d: u32) -> u64 {
        dimension_pattern(self.pixel_hash, d)
    }

    /// The next dimension's number, the sampler moved past it.
    #[inline]
    fn next_dimension(&mut self) -> u32 {
        let d = self.dimension;
        self.dimension += 1;
        d
    }

    #[inline]
    fn next_key(&mut self) -> Key {
        let d = self.next_dimension();
        Key {
            pattern: self.pattern(d),
            index: self.index,
            index_reversed: self.index_reversed,
            count: self.spp,
            grid: self.grid,
        }
    }

    /// The next 1D value of each sampler `samplers[lanes[k]]` (no index twice, at most
    /// eight), lane `k` of the result; lanes past `lanes.len()` repeat the last. Each
    /// value is what [`PixelSampler::next_1d`] would return; Sobol samplers compute the
    /// eight together in SIMD lanes.
    pub fn next_1d_lanes(samplers: &mut [PixelSampler], lanes: &[usize]) -> [f32; 8] {
        Self::draws_lanes(samplers, lanes, [(0, false)], 1)[0].0
    }

    /// [`PixelSampler::next_1d_lanes`] for [`PixelSampler::next_2d`]: the x and the y of
    /// each lane's point.
    pub fn next_2d_lanes(samplers: &mut [PixelSampler], lanes: &[usize]) -> ([f32; 8], [f32; 8]) {
        Self::draws_lanes(samplers, lanes, [(0, true)], 1)[0]
    }

    /// Several of the next dimensions of each sampler `samplers[lanes[k]]` at once (as
    /// [`PixelSampler::next_1d_lanes`]): `plan[m] = (offset, two)` draws the dimension
    /// `offset` past each sampler's current one, in 2D when `two`, into `result[m]`; then
    /// each sampler moves on by `advance` dimensions. The values are what drawing them one
    /// by one (and skipping the others) would give; the samplers' state is read and written
    /// once for all of them.
    pub fn draws_lanes<const M: usize>(
        samplers: &mut [PixelSampler],
        lanes: &[usize],
        plan: [(u32, bool); M],
        advance: u32,
    ) -> [([f32; 8], [f32; 8]); M] {
        let n = lanes.len();
        assert!((1..=8).contains(&n), "{n} lanes");
        debug_assert!(plan.iter().all(|&(offset, _)| offset < advance));
        let mut out = [([0.0; 8], [0.0; 8]); M];
        if samplers[lanes[0]].kind == SamplerKind::Sobol {
            let mut patterns = [[0; 8]; M];
            let mut index_reversed = [0; 8];
            for (k, &i) in lanes.iter().enumerate() {
                let s = &mut samplers[i];
                for (m, &(offset, _)) in plan.iter().enumerate() {
                    patterns[m][k] = s.pattern(s.dimension + offset);
                }
                index_reversed[k] = s.index_reversed;
                s.dimension += advance;
            }
            for k in n..8 {
                index_reversed[k] = index_reversed[n - 1];
                patterns.iter_mut().for_each(|p| p[k] = p[n - 1]);
            }
            for (m, &(_, two)) in plan.iter().enumerate() {
                out[m] = sobol_lanes::sample_lanes(&patterns[m], &index_reversed, two);
            }
            return out;
        }
        if samplers[lanes[0]].kind == SamplerKind::Independent {
            // Each lane's key and dimension, then every draw of the plan for the eight
            // at once.
            let mut keys = independent::LaneKeys {
                key: [0; 8],
                dims: [0; 8],
            };
            for k in 0..8 {
                let s = &samplers[lanes[k.min(n - 1)]];
                (keys.key[k], keys.dims[k]) = (s.key, s.dimension);
            }
            for &i in lanes {
                samplers[i].dimension += advance;
            }
            for (m, &(offset, two)) in plan.iter().enumerate() {
                out[m] = independent::sample_lanes(&keys, offset, two);
            }
            return out;
        }
        for (k, &i) in lanes.iter().enumerate() {
            let s = &mut samplers[i];
            let base = s.dimension;
            for (m, &(offset, two)) in plan.iter().enumerate() {
                s.dimension = base + offset;
                if two {
                    let p = s.next_2d();
                    (out[m].0[k], out[m].1[k]) = (p.x, p.y);
                } else {
                    out[m].0[k] = s.next_1d();
                }
            }
            s.dimension = base + advance;
        }
        for o in &mut out {
            for k in n..8 {
                (o.0[k], o.1[k]) = (o.0[n - 1], o.1[n - 1]);
            }
        }
        out
    }

    /// Passes over the next `n` dimensions without computing them: what drawing and
    /// ignoring them would leave (every dimension is a pure function of its number).
    #[inline]
    pub fn skip(&mut self, n: u32) {
        self.dimension += n;
    }

    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        match self.kind {
            SamplerKind::Independent => independent::sample_1d(self.key, self.next_dimension()),
            SamplerKind::Stratified => stratified::sample_1d(&self.next_key()),
            SamplerKind::Halton => halton::sample_1d(&self.next_key()),
            SamplerKind::Sobol => sobol::sample_1d(&self.next_key()),
        }
    }

    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        match self.kind {
            SamplerKind::Independent => independent::sample_2d(self.key, self.next_dimension()),
            SamplerKind::Stratified => stratified::sample_2d(&self.next_key()),
            SamplerKind::Halton => halton::sample_2d(&self.next_key()),
            SamplerKind::Sobol => sobol::sample_2d(&self.next_key()),
        }
    }
}

/// A source of the uniform numbers a path consumes, one dimension after another: a pixel's
/// sampler, or the primary sample space of a Markov chain (Metropolis light transport),
/// which keeps separate streams for the parts of a path so that a change of one part's
/// length does not shift the numbers of the others.
pub trait Draws {
    fn next_1d(&mut self) -> f32;
    fn next_2d(&mut self) -> Vec2;
    /// Continue from stream `k` (0: camera subpath, 1: light subpath, 2: connections);
    /// ignored by pixel samplers.
    fn start_stream(&mut self, _k: usize) {}
}

impl Draws for PixelSampler {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        PixelSampler::next_1d(self)
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        PixelSampler::next_2d(self)
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

    /// Drawing for up to eight samplers at once gives each what drawing alone would, in
    /// every sampler kind, for any lane count, and leaves each at the same dimension.
    #[test]
    fn lanes_draw_what_each_sampler_draws_alone() {
        for kind in SamplerKind::ALL {
            for n in [1usize, 3, 8] {
                let start = |s: &mut Vec<PixelSampler>| {
                    for (k, s) in s.iter_mut().enumerate() {
                        s.start(UVec2::new(7 * k as u32, 3), 5 + k as u32);
                        s.skip(k as u32 % 3);
                    }
                };
                let mut together = vec![PixelSampler::new(kind, 9, 64); 10];
                let mut alone = together.clone();
                start(&mut together);
                start(&mut alone);
                let lanes: Vec<usize> = (0..n).map(|k| 9 - k).collect();
                for _ in 0..6 {
                    let one = PixelSampler::next_1d_lanes(&mut together, &lanes);
                    let two = PixelSampler::next_2d_lanes(&mut together, &lanes);
                    for (k, &i) in lanes.iter().enumerate() {
                        assert_eq!(one[k].to_bits(), alone[i].next_1d().to_bits(), "{kind:?} lane {k}");
                        let p = alone[i].next_2d();
                        assert_eq!([two.0[k], two.1[k]], [p.x, p.y], "{kind:?} lane {k}");
                    }
                    assert_eq!(one[7], one[n - 1], "{kind:?}: padding repeats the last lane");
                }
                // Several dimensions at once, some passed over.
                let [a, b, c] = PixelSampler::draws_lanes(&mut together, &lanes, [(0, false), (1, true), (3, true)], 5);
                for (k, &i) in lanes.iter().enumerate() {
                    let s = &mut alone[i];
                    assert_eq!(a.0[k].to_bits(), s.next_1d().to_bits(), "{kind:?} lane {k}");
                    let p = s.next_2d();
                    assert_eq!([b.0[k], b.1[k]], [p.x, p.y], "{kind:?} lane {k}");
                    s.skip(1);
                    let p = s.next_2d();
                    assert_eq!([c.0[k], c.1[k]], [p.x, p.y], "{kind:?} lane {k}");
                    s.skip(1);
                }
                assert_eq!(c.1[7], c.1[n - 1], "{kind:?}: padding repeats the last lane");
                for i in 0..10 {
                    assert_eq!(together[i].next_1d(), alone[i].next_1d(), "{kind:?} sampler {i}");
                }
            }
        }
    }

    #[test]
    fn pure_function_of_pixel_and_index() {
        for kind in SamplerKind::ALL {
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

    /// Whether every elementary interval of area 1/n (2^a x 2^b cells with a + b = log2 n)
    /// holds exactly one of the n points: the (0, m, 2)-net property.
    fn is_binary_net(points: &[Vec2]) -> bool {
        let m = points.len().trailing_zeros();
        (0..=m).all(|a| {
            let (nx, ny) = (1u32 << a, 1u32 << (m - a));
            let mut seen = vec![false; points.len()];
            points.iter().all(|p| {
                let cell = ((p.y * ny as f32) as u32 * nx + (p.x * nx as f32) as u32) as usize;
                !std::mem::replace(&mut seen[cell], true)
            })
        })
    }

    #[test]
    fn sobol_points_are_scrambled_nets_in_every_dimension_pair() {
        for spp in [1u32, 4, 16, 64, 256] {
            for pixel in [UVec2::new(0, 0), UVec2::new(17, 3)] {
                let mut s = PixelSampler::new(SamplerKind::Sobol, 7, spp);
                let mut dims: Vec<Vec<Vec2>> = vec![Vec::new(); 3];
                let mut one_d = Vec::new();
                for i in 0..spp {
                    s.start(pixel, i);
                    for d in &mut dims {
                        d.push(s.next_2d());
                    }
                    one_d.push(s.next_1d());
                }
                for d in &dims {
                    assert!(is_binary_net(d), "spp {spp}: {d:?}");
                }
                // 1D: one point in each of the spp strata.
                let mut strata: Vec<u32> = one_d.iter().map(|x| (x * spp as f32) as u32).collect();
                strata.sort();
                assert_eq!(strata, (0..spp).collect::<Vec<_>>());
                // Different dimension pairs are scrambled differently.
                if spp > 1 {
                    assert_ne!(dims[0], dims[1]);
                }
            }
        }
    }

    #[test]
    fn halton_points_fill_base_two_and_three_strata() {
        // 6^k points of the Halton sequence put one point in each of 2^a x 3^b cells for
        // 2^a and 3^b dividing the count; with scrambling and an index permutation within
        // the pixel, the set of points is still a scrambled (0, 2)-net in bases (2, 3).
        for spp in [6u32, 36, 72] {
            let mut s = PixelSampler::new(SamplerKind::Halton, 3, spp);
            let points: Vec<Vec2> = (0..spp)
                .map(|i| {
                    s.start(UVec2::new(5, 8), i);
                    s.next_2d()
                })
                .collect();
            let (twos, threes) = ((spp & spp.wrapping_neg()).trailing_zeros(), {
                let (mut n, mut k) = (spp, 0);
                while n % 3 == 0 {
                    n /= 3;
                    k += 1;
                }
                k
            });
            let (nx, ny) = (1u32 << twos, 3u32.pow(threes));
            let mut cells: Vec<u32> = points
                .iter()
                .map(|p| (p.y * ny as f32) as u32 * nx + (p.x * nx as f32) as u32)
                .collect();
            cells.sort();
            cells.dedup();
            assert_eq!(cells.len() as u32, nx * ny, "spp {spp}: {points:?}");
        }
    }

    #[test]
    fn every_sampler_is_uniform_over_pixels_and_dimensions() {
        use penumbra_testkit::{chi2_test, Grid2};
        for kind in SamplerKind::ALL {
            let mut s = PixelSampler::new(kind, 11, 16);
            let mut values = (0..4096u32)
                .flat_map(|p| (0..16).map(move |i| (p, i)))
                .flat_map(|(p, i)| {
                    s.start(UVec2::new(p % 64, p / 64), i);
                    [s.next_2d(), s.next_2d()]
                });
            let grid = Grid2 {
                min: [0.0, 0.0],
                max: [1.0, 1.0],
                bins: [16, 16],
            };
            let points: Vec<Vec2> = values.by_ref().collect();
            let mut it = points.iter();
            let r = chi2_test(
                grid,
                points.len(),
                || it.next().map(|p| [p.x as f64, p.y as f64]),
                |_| 1.0,
            );
            // Stratified samplers fit better than chance would; only a poor fit fails.
            r.assert_fits(&format!("{kind:?}"), SamplerKind::ALL.len());
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
