//! The render driver: splits the image into tiles, renders them in parallel with rayon and
//! gathers them into the film in a fixed order.
//!
//! Reconstruction: filters wider than a pixel (radius > 0.5) are applied by splatting, as
//! Mitsuba does: each sample, at a uniform position in its pixel, is added with weight
//! f(offset) to every pixel whose centre lies within the filter's radius, and a pixel is
//! the weighted mean of what it received. Narrower filters are applied by filter importance
//! sampling (see [`crate::filter`]): the sample position follows the filter and only its own
//! pixel receives it (a box of tiny radius then samples pixel centres). Splatting uses every
//! sample in several pixels, which lowers per-pixel variance (by about 1/(4πσ²) for a
//! Gaussian of standard deviation σ pixels) at the cost of correlated neighbours.
//!
//! Each pixel's samples depend only on (seed, pixel, sample index). Each tile accumulates
//! into its own buffer (with a margin for splats), and the buffers are added into the film
//! in a fixed tile order, so the image is bit-identical for any thread count and tile
//! order. A raised cancel flag stops work at tile granularity: the tiles finished so far
//! are kept.

use crate::film::Pixel;
use crate::filter::{FilterSampler, FilterTable};
use crate::{Film, Integrator, RayCounts, Scene};
use glam::{UVec2, Vec2};
use penumbra_core::{PixelSampler, SamplerKind};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    pub spp: u32,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// Side of the square tiles, in pixels.
    pub tile_size: u32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            spp: 4,
            seed: 0,
            sampler: SamplerKind::default(),
            tile_size: 16,
        }
    }
}

/// Receives progress reports from the worker threads.
pub trait Progress: Sync {
    /// `pixels` more pixels are done, for which `rays` rays were traced.
    fn advance(&self, pixels: u64, rays: u64);
}

/// A progress sink that ignores reports.
impl Progress for () {
    fn advance(&self, _: u64, _: u64) {}
}

#[derive(Clone, Debug, PartialEq)]
pub struct RenderStats {
    pub elapsed: Duration,
    pub samples: u64,
    pub rays: RayCounts,
    /// True when the render was cancelled before every tile was done.
    pub cancelled: bool,
}

pub struct RenderResult {
    pub film: Film,
    pub stats: RenderStats,
}

struct Tile {
    origin: UVec2,
    size: UVec2,
}

struct TileResult {
    tile: Tile,
    /// The tile's pixels and a margin of `margin` pixels on every side, row by row.
    pixels: Vec<Pixel>,
    margin: u32,
    rejected: u64,
    rays: RayCounts,
}

/// Renders `scene` with `integrator`, reporting to `progress`, until done or `cancel` is set.
pub fn render(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
    progress: &dyn Progress,
    cancel: &AtomicBool,
) -> RenderResult {
    let start = Instant::now();
    let filter = FilterSampler::new(scene.filter);
    let ts = options.tile_size.max(1);
    let tiles: Vec<Tile> = (0..scene.height.div_ceil(ts))
        .flat_map(|ty| (0..scene.width.div_ceil(ts)).map(move |tx| (tx, ty)))
        .map(|(tx, ty)| {
            let origin = UVec2::new(tx * ts, ty * ts);
            let size = UVec2::new(ts.min(scene.width - origin.x), ts.min(scene.height - origin.y));
            Tile { origin, size }
        })
        .collect();
    let results: Vec<TileResult> = tiles
        .into_par_iter()
        .filter_map(|tile| {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let result = render_tile(scene, integrator, options, &filter, tile);
            progress.advance((result.tile.size.x * result.tile.size.y) as u64, result.rays.total());
            Some(result)
        })
        .collect();

    let mut film = Film::new(scene.width, scene.height);
    let mut rays = RayCounts::default();
    let mut tiles_done = 0;
    for r in &results {
        tiles_done += 1;
        rays.add(&r.rays);
        film.rejected += r.rejected;
        let m = r.margin as i64;
        let w = r.tile.size.x as i64 + 2 * m;
        for (i, px) in r.pixels.iter().enumerate() {
            let x = r.tile.origin.x as i64 - m + i as i64 % w;
            let y = r.tile.origin.y as i64 - m + i as i64 / w;
            if (0..scene.width as i64).contains(&x) && (0..scene.height as i64).contains(&y) {
                film.pixel_mut(x as u32, y as u32).merge(px);
            }
        }
    }
    let total_tiles = scene.height.div_ceil(ts) * scene.width.div_ceil(ts);
    let stats = RenderStats {
        elapsed: start.elapsed(),
        samples: film.samples(),
        rays,
        cancelled: tiles_done < total_tiles,
    };
    RenderResult { film, stats }
}

fn render_tile(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
    filter: &FilterSampler,
    tile: Tile,
) -> TileResult {
    let mut sampler = PixelSampler::new(options.sampler, options.seed, options.spp);
    let radius = scene.filter.radius();
    let splat = radius > 0.5;
    let margin = if splat { (radius - 0.5).ceil() as u32 } else { 0 };
    let stride = tile.size.x + 2 * margin;
    let table = splat.then(|| FilterTable::new(&scene.filter));
    let lens = scene.camera.has_lens();
    // The filter's weights for the columns a sample reaches, worked out once per sample.
    let mut column_weights = Vec::with_capacity(2 * margin as usize + 2);
    let mut pixels = vec![Pixel::default(); (stride * (tile.size.y + 2 * margin)) as usize];
    let mut rays = RayCounts::default();
    let mut rejected = 0;
    for y in 0..tile.size.y {
        for x in 0..tile.size.x {
            let pixel = tile.origin + UVec2::new(x, y);
            for index in 0..options.spp {
                sampler.start(pixel, index);
                let u = sampler.next_2d();
                let (film_pos, weight) = if splat {
                    (pixel.as_vec2() + u, 1.0)
                } else {
                    let (offset, weight) = filter.sample(u);
                    (pixel.as_vec2() + Vec2::splat(0.5) + offset, weight)
                };
                let u_lens = if lens { sampler.next_2d() } else { Vec2::ZERO };
                let ray = scene.camera.generate_ray(film_pos, u_lens);
                rays.camera += 1;
                let l = integrator.li(scene, &ray, &mut sampler, &mut rays);
                let own = ((y + margin) * stride + x + margin) as usize;
                pixels[own].samples += 1;
                if !l.is_finite() {
                    rejected += 1;
                    continue;
                }
                let Some(table) = &table else {
                    pixels[own].add(l, weight);
                    continue;
                };
                // Every pixel whose centre is within the radius of the sample, in the
                // tile's buffer coordinates (the tile's first pixel at (margin, margin)).
                let local = film_pos - tile.origin.as_vec2() + Vec2::splat(margin as f32);
                let lo = (local - Vec2::splat(radius + 0.5)).ceil().max(Vec2::ZERO);
                let hi = (local + Vec2::splat(radius - 0.5)).floor();
                let columns = lo.x as u32..=(hi.x as u32).min(stride - 1);
                column_weights.clear();
                column_weights.extend(columns.clone().map(|px| table.eval(px as f32 + 0.5 - local.x)));
                for py in lo.y as u32..=(hi.y as u32).min(tile.size.y + 2 * margin - 1) {
                    let wy = table.eval(py as f32 + 0.5 - local.y);
                    for (px, &wx) in columns.clone().zip(&column_weights) {
                        let w = wy * wx;
                        if w != 0.0 {
                            pixels[(py * stride + px) as usize].add(l, w);
                        }
                    }
                }
            }
        }
    }
    TileResult {
        tile,
        pixels,
        margin,
        rejected,
        rays,
    }
}
