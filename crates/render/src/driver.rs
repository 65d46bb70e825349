//! The render driver: splits the image into tiles, renders them in parallel with rayon and
//! gathers them into the film in a fixed order.
//!
//! Each pixel's samples depend only on (seed, pixel, sample index), and each pixel is
//! accumulated by one thread in sample order, so the image is bit-identical for any
//! thread count and tile order. A raised cancel flag stops work at tile granularity: the
//! tiles finished so far are kept.

use crate::film::Pixel;
use crate::filter::FilterSampler;
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
    pixels: Vec<Pixel>,
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
            progress.advance(result.pixels.len() as u64, result.rays.total());
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
        for (i, px) in r.pixels.iter().enumerate() {
            let (x, y) = (i as u32 % r.tile.size.x, i as u32 / r.tile.size.x);
            *film.pixel_mut(r.tile.origin.x + x, r.tile.origin.y + y) = *px;
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
    let mut pixels = Vec::with_capacity(tile.size.x as usize * tile.size.y as usize);
    let mut rays = RayCounts::default();
    let mut rejected = 0;
    for y in 0..tile.size.y {
        for x in 0..tile.size.x {
            let pixel = tile.origin + UVec2::new(x, y);
            let mut acc = Pixel::default();
            for index in 0..options.spp {
                sampler.start(pixel, index);
                let (offset, weight) = filter.sample(sampler.next_2d());
                let film_pos = pixel.as_vec2() + Vec2::splat(0.5) + offset;
                let ray = scene.camera.generate_ray(film_pos);
                rays.camera += 1;
                let l = integrator.li(scene, &ray, &mut sampler, &mut rays);
                if l.is_finite() {
                    acc.add(l, weight);
                } else {
                    rejected += 1;
                }
            }
            pixels.push(acc);
        }
    }
    TileResult {
        tile,
        pixels,
        rejected,
        rays,
    }
}
