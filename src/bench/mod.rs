//! Accelerator benchmarks (`penumbra bench accel`): build every accelerator over the same
//! primitives, trace the same rays through each, and report build time, memory, throughput
//! on one thread and on all, traversal cost per ray, and disagreements with expected hits
//! (such as Embree's, from `../shared/anchors/run.sh setup`).

mod rays;

pub use rays::{coherent_rays, incoherent_rays, read_hits, read_rays, ExpectedHit, RaySet};

use penumbra_geometry::{Accel, AccelKind, Geometry, TraversalStats};
use rayon::prelude::*;
use std::sync::Arc;
use std::time::Instant;

/// Throughput of one ray set through one accelerator.
#[derive(Clone, Debug)]
pub struct Throughput {
    pub rays: String,
    /// Mrays/s on one thread: best and median of the repeats.
    pub single: (f64, f64),
    /// Mrays/s on every thread of the current pool: best and median.
    pub all: (f64, f64),
    pub threads: usize,
    /// Mean nodes (cells) visited and primitive tests per ray.
    pub nodes_per_ray: f64,
    pub prims_per_ray: f64,
    /// Rays whose closest hit differs from the expected one, if expected hits were given.
    pub mismatches: Option<usize>,
    /// Rays actually traced (the brute-force list traces a sample).
    pub traced: usize,
}

/// Everything measured for one accelerator.
#[derive(Clone, Debug)]
pub struct AccelReport {
    pub kind: AccelKind,
    /// Build times in seconds: best and median.
    pub build: (f64, f64),
    pub memory_bytes: usize,
    /// Bytes of the primitive data the accelerator reads.
    pub primitive_bytes: usize,
    pub throughput: Vec<Throughput>,
}

/// Best (smallest time, so largest rate) and median of a set of measurements.
fn best_and_median(mut xs: Vec<f64>, higher_is_better: bool) -> (f64, f64) {
    xs.sort_by(f64::total_cmp);
    let best = if higher_is_better { xs[xs.len() - 1] } else { xs[0] };
    (best, xs[xs.len() / 2])
}

/// The brute-force list traces a sample of each set: at most this many ray-primitive tests.
const LIST_TESTS: usize = 50_000_000;

/// Benchmarks accelerator `kind` over `geometry` with `sets` of rays, `repeats` times each.
pub fn bench_accel(kind: AccelKind, geometry: &Arc<Geometry>, sets: &[RaySet], repeats: usize) -> AccelReport {
    let repeats = repeats.max(1);
    let mut builds = Vec::with_capacity(repeats);
    let mut accel: Box<dyn Accel> = geometry.accel(kind);
    for _ in 0..repeats {
        let start = Instant::now();
        accel = geometry.accel(kind);
        builds.push(start.elapsed().as_secs_f64());
    }
    let throughput = sets
        .iter()
        .map(|set| measure(accel.as_ref(), kind, set, repeats, geometry.primitive_count()))
        .collect();
    AccelReport {
        kind,
        build: best_and_median(builds, false),
        memory_bytes: accel.memory_bytes(),
        primitive_bytes: accel.primitive_bytes(),
        throughput,
    }
}

fn measure(accel: &dyn Accel, kind: AccelKind, set: &RaySet, repeats: usize, prims: usize) -> Throughput {
    let sample = (LIST_TESTS / prims.max(1)).max(16);
    let rays = if kind == AccelKind::List {
        &set.rays[..set.rays.len().min(sample)]
    } else {
        &set.rays[..]
    };
    let n = rays.len() as f64;
    let single: Vec<f64> = (0..repeats)
        .map(|_| {
            let start = Instant::now();
            let hits = rays
                .iter()
                .filter(|r| accel.intersect(r, f32::INFINITY).is_some())
                .count();
            std::hint::black_box(hits);
            n / start.elapsed().as_secs_f64() * 1e-6
        })
        .collect();
    let all: Vec<f64> = (0..repeats)
        .map(|_| {
            let start = Instant::now();
            let hits = rays
                .par_chunks(rays.len().div_ceil(rayon::current_num_threads() * 8).max(1))
                .map(|c| c.iter().filter(|r| accel.intersect(r, f32::INFINITY).is_some()).count())
                .sum::<usize>();
            std::hint::black_box(hits);
            n / start.elapsed().as_secs_f64() * 1e-6
        })
        .collect();
    let mut stats = TraversalStats::default();
    let mut mismatches = 0;
    for (i, r) in rays.iter().enumerate() {
        let hit = accel.intersect_counted(r, f32::INFINITY, &mut stats);
        if let Some(expected) = set.expected.as_ref().map(|e| e[i]) {
            if !expected.agrees(hit.map(|h| (h.prim, h.t))) {
                mismatches += 1;
            }
        }
    }
    Throughput {
        rays: set.name.clone(),
        single: best_and_median(single, true),
        all: best_and_median(all, true),
        threads: rayon::current_num_threads(),
        nodes_per_ray: stats.nodes as f64 / n,
        prims_per_ray: stats.prims as f64 / n,
        mismatches: set.expected.as_ref().map(|_| mismatches),
        traced: rays.len(),
    }
}
