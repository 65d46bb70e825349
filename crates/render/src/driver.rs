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
//! Rendering is progressive: pass k takes sample k of every pixel. Each pixel's samples
//! depend only on (seed, pixel, sample index). Within a pass each tile accumulates into its
//! own buffer (with a margin for splats), and the buffers are added into the film in a
//! fixed tile order; the film adds the passes in order, in double precision. So the image
//! is bit-identical for any thread count and tile order, and a render stopped after any
//! pass and resumed from its film ends exactly where an uninterrupted one does. A raised
//! cancel flag or a spent time budget stops the render between passes.

use crate::film::Splat;
use crate::film::{add_aov, Pixel, AOV_CHANNELS};
use crate::filter::Filters;
use crate::interface::{Integrator, Progress, RayCounts};
use crate::{Film, Scene};
use glam::{UVec2, Vec2};
use penumbra_core::{PixelSampler, Ray, Rgb, SamplerKind};
use rayon::prelude::*;
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Samples per pixel to reach.
    pub spp: u32,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// Side of the square tiles, in pixels.
    pub tile_size: u32,
    /// Stop starting passes once the next would end beyond this much time.
    pub time_limit: Option<Duration>,
    /// Accumulate the AOVs (albedo, shading normal, depth) too.
    pub aovs: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            spp: 4,
            seed: 0,
            sampler: SamplerKind::default(),
            tile_size: 16,
            time_limit: None,
            aovs: false,
        }
    }
}

/// Why a render stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Every pixel has the samples asked for.
    Done,
    /// The time budget ran out first.
    TimeLimit,
    /// Cancelled (Ctrl-C): the pass in flight was finished.
    Cancelled,
}

#[derive(Clone, Debug, PartialEq)]
pub struct RenderStats {
    pub elapsed: Duration,
    /// Samples taken in this run (not counting a resumed film's).
    pub samples: u64,
    pub rays: RayCounts,
    pub stop: Stop,
    /// What the integrator reports about the render (Metropolis: acceptance rates).
    pub notes: Vec<String>,
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
    /// The tile's pixels and a margin of `margin` pixels on every side, row by row.
    pixels: Vec<Pixel>,
    /// What the tile's samples add to film pixels (layer, index, value), filter weights
    /// applied.
    splats: Vec<(u32, u32, Rgb)>,
    aovs: Vec<[f32; AOV_CHANNELS]>,
    rejected: u64,
    rays: RayCounts,
}

/// Renders `scene` progressively into `film` (a new one, or a saved one to resume): one
/// pass per sample index, until every pixel has `options.spp` samples, the time budget is
/// spent, or `cancel` is raised (checked between passes, so the pass in flight is
/// finished). `after_pass` sees the film after every pass (for checkpoints).
pub fn render(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
    film: Film,
    progress: &dyn Progress,
    cancel: &AtomicBool,
    after_pass: &mut dyn FnMut(&Film),
) -> RenderResult {
    let start = Instant::now();
    let filter = Filters::new(scene);
    let ts = options.tile_size.max(1);
    let tiles: Vec<Tile> = (0..scene.height.div_ceil(ts))
        .flat_map(|ty| (0..scene.width.div_ceil(ts)).map(move |tx| (tx, ty)))
        .map(|(tx, ty)| {
            let origin = UVec2::new(tx * ts, ty * ts);
            let size = UVec2::new(ts.min(scene.width - origin.x), ts.min(scene.height - origin.y));
            Tile { origin, size }
        })
        .collect();
    let covering = covering_tiles(&tiles, scene.height, filter.margin);
    let passes = integrator.passes();
    // Set-up before the first pass (Metropolis's bootstrap, photon maps): inside the time budget, but
    // not taken for a pass when the next pass's length is estimated.
    let prepared = integrator.prepare(scene, progress);
    let mut result = run_passes(
        scene,
        options,
        film,
        cancel,
        after_pass,
        start,
        |index, film| match passes {
            Some(p) => p.pass(scene, &filter, index, film, progress),
            None => render_pass(
                scene,
                integrator,
                options,
                &filter,
                (&tiles, &covering),
                index,
                film,
                progress,
            ),
        },
    );
    result.stats.notes = integrator.report();
    result.stats.rays.add(&prepared);
    let overflows = result.stats.rays.specular_overflows;
    if overflows > 0 {
        result.stats.notes.push(format!(
            "warning: {overflows} hits had more than {} distinct perfectly specular directions (a blend of many \
             glasses?); the weakest were left out",
            crate::bsdfs::MAX_SPECULAR_RAYS
        ));
    }
    result
}

/// The progressive loop every integrator shares: `pass(index, film)` adds sample `index`
/// of every pixel (for Metropolis: one mutation per pixel) to the film, until the film
/// has `options.spp`, the time budget is spent or `cancel` is raised; `after_pass` sees
/// the film after each pass.
fn run_passes(
    scene: &Scene,
    options: &RenderOptions,
    mut film: Film,
    cancel: &AtomicBool,
    after_pass: &mut dyn FnMut(&Film),
    start: Instant,
    mut pass: impl FnMut(u32, &mut Film) -> RayCounts,
) -> RenderResult {
    let mut rays = RayCounts::default();
    let mut passes = 0u32;
    let first_pass = Instant::now();
    let stop = loop {
        if film.samples_per_pixel >= options.spp {
            break Stop::Done;
        }
        if cancel.load(Ordering::Relaxed) {
            break Stop::Cancelled;
        }
        if let Some(limit) = options.time_limit {
            // Stop when the next pass, as long as the mean one so far, would overrun.
            let elapsed = start.elapsed();
            let mean = if passes > 0 {
                first_pass.elapsed() / passes
            } else {
                Duration::ZERO
            };
            if passes > 0 && elapsed + mean > limit {
                break Stop::TimeLimit;
            }
        }
        let index = film.samples_per_pixel;
        rays.add(&pass(index, &mut film));
        film.samples_per_pixel = index + 1;
        passes += 1;
        after_pass(&film);
    };
    let pixels = scene.width as u64 * scene.height as u64;
    let stats = RenderStats {
        elapsed: start.elapsed(),
        samples: passes as u64 * pixels,
        rays,
        stop,
        notes: Vec::new(),
    };
    RenderResult { film, stats }
}

/// Sample `index` of every pixel, tile by tile in parallel, added to `film` in tile order.
#[allow(clippy::too_many_arguments)]
fn render_pass(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
    filter: &Filters,
    (tiles, covering): (&[Tile], &[Vec<u32>]),
    index: u32,
    film: &mut Film,
    progress: &dyn Progress,
) -> RayCounts {
    let margin = filter.margin;
    // Tiles in chunks, whose splats are added to the film before the next chunk starts:
    // the splat lists held at once stay bounded whatever the image size.
    let mut results: Vec<TileResult> = Vec::with_capacity(tiles.len());
    for chunk in tiles.chunks(SPLAT_CHUNK) {
        // One tile per job: rayon otherwise stops splitting a range after a few halvings
        // unless a thief takes part of it, and the last unsplit run of tiles (a quarter of
        // the pass with two threads) leaves the other threads idle at the end of every pass.
        let mut done: Vec<TileResult> = chunk
            .par_iter()
            .with_max_len(1)
            .map(|tile| {
                let result =
                    with_scratch(|scratch| render_tile(scene, integrator, options, filter, tile, index, scratch));
                progress.advance((tile.size.x * tile.size.y) as u64, result.rays.total());
                result
            })
            .collect();
        for r in &mut done {
            for &(layer, i, v) in &r.splats {
                film.add_splat(layer, i as usize, v);
            }
            r.splats = Vec::new();
        }
        results.extend(done);
    }
    let mut rays = RayCounts::default();
    for r in &results {
        rays.add(&r.rays);
        film.rejected += r.rejected;
    }
    let width = film.width as usize;
    let merge = (tiles, covering, &results[..], margin);
    merge_rows(film.pixels_mut(), width, merge, |r, i, px| px.add(&r.pixels[i]));
    if let Some(aovs) = &mut film.aovs {
        merge_rows(aovs, width, merge, |r, i, a| add_aov(a, &r.aovs[i]));
    }
    rays
}

/// Tiles rendered before their splats are added to the film: at the default tile size
/// 65,536 pixel samples, each with at most `max_depth` splats (a few, after the filter's).
const SPLAT_CHUNK: usize = 256;

/// For each film row, the tiles whose buffers (each with a margin of `margin` pixels)
/// reach it, in tile order.
fn covering_tiles(tiles: &[Tile], height: u32, margin: u32) -> Vec<Vec<u32>> {
    let mut covering = vec![Vec::new(); height as usize];
    for (k, tile) in tiles.iter().enumerate() {
        let first = tile.origin.y.saturating_sub(margin);
        let end = (tile.origin.y + tile.size.y + margin).min(height);
        for row in &mut covering[first as usize..end as usize] {
            row.push(k as u32);
        }
    }
    covering
}

/// Adds the tiles' buffers (each with a margin of `margin` pixels) to the film's rows
/// `film` (`width` pixels each), the rows in parallel: each row takes the rows of the
/// tiles that cover it (`covering`, from [`covering_tiles`]) in tile order, so every
/// pixel's sums are added in the order of one tile after another, whatever the thread
/// count. `add(result, i, pixel)` adds entry `i` of a tile's buffer to a film pixel.
fn merge_rows<T: Send>(
    film: &mut [T],
    width: usize,
    (tiles, covering, results, margin): (&[Tile], &[Vec<u32>], &[TileResult], u32),
    add: impl Fn(&TileResult, usize, &mut T) + Sync,
) {
    let m = margin as i64;
    film.par_chunks_mut(width)
        .zip(covering)
        .enumerate()
        .for_each(|(y, (row, cover))| {
            for &k in cover {
                let (tile, r) = (&tiles[k as usize], &results[k as usize]);
                let ty = y as i64 - (tile.origin.y as i64 - m);
                let w = tile.size.x as i64 + 2 * m;
                let x0 = tile.origin.x as i64 - m;
                for tx in (-x0).max(0)..w.min(width as i64 - x0) {
                    add(r, (ty * w + tx) as usize, &mut row[(x0 + tx) as usize]);
                }
            }
        });
}

/// The AOVs of the first surface `ray` meets: albedo, shading normal, depth (zeros when
/// it meets none).
fn first_hit_aovs(scene: &Scene, ray: &Ray) -> [f32; AOV_CHANNELS] {
    let Some(it) = scene.intersect(ray, f32::INFINITY) else {
        return [0.0; AOV_CHANNELS];
    };
    let albedo = it.material.bsdf(it.surface.uv).albedo();
    let n = it.material.shading_frame(&it.surface).n;
    let depth = (it.surface.p - ray.origin).length();
    [albedo.r, albedo.g, albedo.b, n.x, n.y, n.z, depth]
}

thread_local! {
    /// Each worker thread's [`Scratch`], kept from tile to tile and pass to pass.
    static SCRATCH: RefCell<Scratch> = RefCell::default();
}

/// Runs `f` with this thread's [`Scratch`] (a fresh one if it is in use: a tile rendered
/// while another waits on this thread, should an integrator ever nest parallel work).
fn with_scratch<T>(f: impl FnOnce(&mut Scratch) -> T) -> T {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut scratch) => f(&mut scratch),
        Err(_) => f(&mut Scratch::default()),
    })
}

/// A worker's buffers for its tiles, kept from tile to tile (their contents are set
/// anew for every tile: they may come from another render).
#[derive(Default)]
struct Scratch {
    /// One sampler per lane of a batch, made for the render's settings; `start` sets all
    /// the rest of a sampler's state for each sample.
    samplers: Vec<PixelSampler>,
    rays_in: Vec<Ray>,
    film_positions: Vec<(UVec2, Vec2, f32)>,
    radiance: Vec<Rgb>,
    draws: Vec<(Vec2, Vec2)>,
    column_weights: Vec<f32>,
    /// The splats of a batch, as the integrator makes them.
    splats: Vec<Splat>,
}

/// `v.floor()` for coordinates well inside `i32`'s range, without the library call the
/// baseline x86-64 build makes for `f32::floor` (it has no rounding instruction).
#[inline(always)]
fn floor_small(v: Vec2) -> Vec2 {
    let floor = |x: f32| {
        let i = x as i32 as f32;
        if i > x {
            i - 1.0
        } else {
            i
        }
    };
    Vec2::new(floor(v.x), floor(v.y))
}

/// `v.ceil()` as [`floor_small`] (a ceiling of -0.5 gives +0, not -0).
#[inline(always)]
fn ceil_small(v: Vec2) -> Vec2 {
    let ceil = |x: f32| {
        let i = x as i32 as f32;
        if i < x {
            i + 1.0
        } else {
            i
        }
    };
    Vec2::new(ceil(v.x), ceil(v.y))
}

#[allow(clippy::too_many_arguments)]
fn render_tile(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
    filter: &Filters,
    tile: &Tile,
    index: u32,
    scratch: &mut Scratch,
) -> TileResult {
    let sampler = PixelSampler::new(options.sampler, options.seed, options.spp);
    let radius = scene.filter.radius();
    let table = filter.splat.as_ref();
    let splat = table.is_some();
    let margin = filter.margin;
    let stride = tile.size.x + 2 * margin;
    let lens = scene.camera.has_lens();
    // The filter's weights for the columns a sample reaches, worked out once per sample.
    let column_weights = &mut scratch.column_weights;
    let buffer = (stride * (tile.size.y + 2 * margin)) as usize;
    let mut pixels = vec![Pixel::default(); buffer];
    let mut aovs = if options.aovs {
        vec![[0.0; AOV_CHANNELS]; buffer]
    } else {
        Vec::new()
    };
    let mut rays = RayCounts::default();
    let mut rejected = 0;
    let mut splats = Vec::new();
    // The tile's pixels in row order, in batches handed to the integrator together.
    let pixel_count = (tile.size.x * tile.size.y) as usize;
    let Scratch {
        samplers,
        rays_in,
        film_positions,
        radiance,
        draws,
        splats: batch_splats,
        ..
    } = scratch;
    let batch = integrator.batch_size().max(1);
    let batch_size = batch.min(pixel_count);
    // Made anew: the kept ones may have another render's kind, seed or sample count.
    samplers.clear();
    samplers.resize(batch_size, sampler);
    radiance.resize(batch_size, Rgb::BLACK);
    for batch_start in (0..pixel_count).step_by(batch) {
        let lanes = batch.min(pixel_count - batch_start);
        rays_in.clear();
        film_positions.clear();
        let pixel_of = |lane: usize| {
            let i = (batch_start + lane) as u32;
            tile.origin + UVec2::new(i % tile.size.x, i / tile.size.x)
        };
        for (lane, sampler) in samplers[..lanes].iter_mut().enumerate() {
            sampler.start(pixel_of(lane), index);
        }
        // Each pixel's first two dimensions (its position in the pixel, then the lens),
        // eight samplers at a time.
        draws.clear();
        draws.resize(lanes, (Vec2::ZERO, Vec2::ZERO));
        for first in (0..lanes).step_by(8) {
            let all: [usize; 8] = std::array::from_fn(|j| first + j);
            let group = &all[..8.min(lanes - first)];
            let xy = PixelSampler::next_2d_lanes(samplers, group);
            let lens_xy = lens.then(|| PixelSampler::next_2d_lanes(samplers, group));
            for (j, &lane) in group.iter().enumerate() {
                draws[lane].0 = Vec2::new(xy.0[j], xy.1[j]);
                if let Some(l) = lens_xy {
                    draws[lane].1 = Vec2::new(l.0[j], l.1[j]);
                }
            }
        }
        for (lane, &(u, u_lens)) in draws.iter().enumerate() {
            let pixel = pixel_of(lane);
            let (film_pos, weight) = if splat {
                (pixel.as_vec2() + u, 1.0)
            } else {
                let (offset, weight) = filter.sampler.sample(u);
                (pixel.as_vec2() + Vec2::splat(0.5) + offset, weight)
            };
            rays_in.push(scene.camera.generate_ray(film_pos, u_lens));
            film_positions.push((pixel - tile.origin, film_pos, weight));
        }
        rays.camera += lanes as u64;
        batch_splats.clear();
        integrator.li_batch(
            scene,
            rays_in,
            &mut samplers[..lanes],
            &mut radiance[..lanes],
            &mut rays,
            batch_splats,
        );
        // What an integrator declares is what it does (checked in every debug render).
        debug_assert!(
            batch_splats.is_empty() || integrator.capabilities().splats,
            "an integrator that declares no splats made some"
        );
        for s in batch_splats.iter() {
            if s.value.is_finite() {
                filter.splat(s, (scene.width, scene.height), &mut splats);
            } else {
                rejected += 1;
            }
        }
        for ((&(UVec2 { x, y }, film_pos, weight), &l), ray) in
            film_positions.iter().zip(radiance.iter()).zip(rays_in.iter())
        {
            if !l.is_finite() {
                rejected += 1;
                continue;
            }
            let aov = options.aovs.then(|| first_hit_aovs(scene, ray));
            let mut add = |i: usize, w: f32| {
                pixels[i].add(l, w);
                // (An AOV may not be finite: no zero-weight share of it.)
                if let Some(a) = aov.as_ref().filter(|_| w != 0.0) {
                    aovs[i].iter_mut().zip(a).for_each(|(s, v)| *s += v * w);
                }
            };
            let Some(table) = table else {
                add(((y + margin) * stride + x + margin) as usize, weight);
                continue;
            };
            // Every pixel whose centre is within the radius of the sample, in the
            // tile's buffer coordinates (the tile's first pixel at (margin, margin)).
            let local = film_pos - tile.origin.as_vec2() + Vec2::splat(margin as f32);
            let lo = ceil_small(local - Vec2::splat(radius + 0.5)).max(Vec2::ZERO);
            let hi = floor_small(local + Vec2::splat(radius - 0.5));
            // Half-open ranges (an inclusive range costs a flag test per step).
            let (x0, x1) = (lo.x as u32, (hi.x as u32).min(stride - 1) + 1);
            let (y0, y1) = (lo.y as u32, (hi.y as u32).min(tile.size.y + 2 * margin - 1) + 1);
            column_weights.clear();
            column_weights.extend((x0..x1).map(|px| table.eval(px as f32 + 0.5 - local.x)));
            for py in y0..y1 {
                let wy = table.eval(py as f32 + 0.5 - local.y);
                let row = (py * stride) as usize;
                // A zero weight (a pixel centre exactly at the radius) adds exact zeros of
                // finite radiance to sums that are never -0: no test needed.
                for (px, &wx) in (x0 as usize..).zip(column_weights.iter()) {
                    add(row + px, wy * wx);
                }
            }
        }
    }
    TileResult {
        pixels,
        splats,
        aovs,
        rejected,
        rays,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The splat's pixel range: the same whole numbers as `floor`/`ceil` over film
    /// coordinates, integers, halves and values just off them, of either sign.
    #[test]
    fn small_floor_and_ceil_are_the_library_ones() {
        let mut x = -70.0f32;
        let mut checked = 0;
        while x < 70.0 {
            for v in [x, x.next_up(), x.next_down(), x + 0.5, -x] {
                let p = Vec2::new(v, -v * 0.75);
                assert_eq!(floor_small(p), p.floor(), "floor of {p}");
                // Equal as numbers: -0 and +0 alike (both become pixel 0).
                assert_eq!(ceil_small(p), p.ceil(), "ceil of {p}");
                checked += 1;
            }
            x += 0.125;
        }
        assert!(checked > 5000);
    }
}
