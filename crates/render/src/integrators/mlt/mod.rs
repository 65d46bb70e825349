//! Metropolis light transport in primary sample space (Kelemen et al. 2002) over
//! bidirectional paths, as pbrt-v4's `MLTIntegrator` does it.
//!
//! A state of a Markov chain is a vector of uniform numbers ([`PrimarySamples`]); the path
//! it maps to is made by bidirectional path tracing, and the chain's target is the
//! luminance I of what the path brings to the film. Each mutation is a large step (every
//! number afresh, with the large-step probability) or a small one (each moved by a normal
//! offset of size `sigma`); it is accepted with probability min(1, I'/I), and both the
//! proposal and the current state are splatted, weighted by their acceptance
//! probabilities (Veach's expected-value form). A bootstrap phase of uniformly drawn
//! states picks the chains' starting states in proportion to I, so that no start-up bias
//! remains; the normalisation b = ∫ I, the image's mean luminance, is estimated by
//! stratified bidirectional samples (see `Mlt::start`).
//!
//! Multiplexed (the default; Hachisuka et al., "Multiplexed Metropolis Light Transport",
//! 2014): each chain keeps one path length, and the first number of the state chooses the
//! bidirectional strategy (s, t), so the chain moves between strategies where each does
//! well; the value is the strategy's MIS-weighted contribution over its probability.
//! Plain (Kelemen's): the state is a whole bidirectional sample (a camera ray, both
//! subpaths, every strategy), which may splat to several pixels.
//!
//! A pass is one mutation per pixel, shared among the chains; the film's splat layer holds
//! the sums, and the image is their mean per pass. Chains run in parallel, and each
//! chunk of chains is added to the film in chain order, so the image does not depend on
//! the thread count.

mod sampler;

pub use sampler::PrimarySamples;

use super::bdpt::{Bdpt, PerLength};
use super::{Integrator, IntegratorOptions, PassIntegrator, RayCounts, Splat};
use crate::filter::Filters;
use crate::interface::{Capabilities, Progress};
use crate::{Film, Scene};
use glam::Vec2;
use penumbra_core::{Distribution1D, Draws, PixelSampler, Ray, Rgb};
use rayon::prelude::*;
use std::sync::Mutex;

/// The Metropolis settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MltOptions {
    /// Uniform states drawn to estimate the normalisation and start the chains (per path
    /// length when multiplexed).
    pub bootstrap: u32,
    /// Independent Markov chains.
    pub chains: u32,
    /// Probability of a large step (every number afresh).
    pub large_step_probability: f32,
    /// Standard deviation of a small step's offsets.
    pub sigma: f32,
    /// Multiplexed: chains choose the bidirectional strategy; else each state is a whole
    /// bidirectional sample.
    pub multiplexed: bool,
}

impl Default for MltOptions {
    fn default() -> Self {
        MltOptions {
            bootstrap: 100_000,
            chains: 1000,
            large_step_probability: 0.3,
            sigma: 0.01,
            multiplexed: true,
        }
    }
}

pub struct Mlt {
    bdpt: Bdpt,
    options: MltOptions,
    max_depth: usize,
    seed: u64,
    state: Mutex<Option<Chains>>,
}

/// The chains and what the bootstrap found.
struct Chains {
    chains: Vec<Chain>,
    /// The normalisation b = ∫ I over primary sample space (over all path lengths).
    b: f64,
    /// Its share at each path length (segments from 1), for the multiplexed form, whose
    /// chains each keep one length: their splats are scaled so that each length gets its
    /// share whatever the number of chains the bootstrap gave it.
    b_lengths: Vec<f64>,
    /// Bootstrap states that brought anything, out of how many.
    bootstrap_hits: (u64, u64),
}

struct Chain {
    samples: PrimarySamples,
    /// Path segments (multiplexed; 0 for plain).
    segments: usize,
    /// Not a Markov chain when set: every mutation is a fresh bidirectional sample (all
    /// strategies) of the path lengths marked here (segments from 1: those no Markov
    /// chain keeps), splatted as is.
    independent: Option<Vec<bool>>,
    current: Vec<Splat>,
    importance: f32,
    /// Mutations (large, small) proposed and accepted.
    proposed: [u64; 2],
    accepted: [u64; 2],
}

/// A splat weighted for one pixel: (film layer, pixel index, value).
type PixelSplat = (u32, u32, Rgb);

/// The chains added to the film together: their splat lists held at once stay bounded.
const CHAIN_CHUNK: usize = 64;

impl Mlt {
    pub fn new(options: IntegratorOptions) -> Self {
        let (mlt, seed) = (options.mlt, options.seed);
        // Roulette would only add noise to paths of a chosen length.
        let bdpt = Bdpt {
            options: IntegratorOptions {
                rr_depth: u32::MAX,
                debug_strategies: false,
                ..options
            },
        };
        Mlt {
            bdpt,
            options: mlt,
            max_depth: options.max_depth as usize,
            seed,
            state: Mutex::new(None),
        }
    }

    /// The contributions of the state `samples` maps to (with `segments` segments when
    /// multiplexed; a whole bidirectional sample of the lengths marked in `only` when
    /// that is given), into `out`; their importance (total luminance).
    fn evaluate(
        &self,
        scene: &Scene,
        samples: &mut PrimarySamples,
        (segments, only): (usize, Option<&[bool]>),
        out: &mut Vec<Splat>,
        counts: &mut RayCounts,
    ) -> f32 {
        out.clear();
        if self.options.multiplexed && only.is_none() {
            if let Some((value, film)) = self.bdpt.strategy_sample(scene, segments, samples, counts) {
                out.push(Splat { film, value, layer: 0 });
            }
        } else {
            samples.start_stream(0);
            let film = samples.next_2d() * Vec2::new(scene.width as f32, scene.height as f32);
            let u_lens = samples.next_2d();
            let ray = scene.camera.generate_ray(film, u_lens);
            counts.camera += 1;
            let lengths = PerLength { sums: None, only };
            let value = self.bdpt.sample(scene, &ray, samples, counts, out, lengths);
            out.push(Splat { film, value, layer: 0 });
        }
        out.retain(|s| s.value.is_finite() && !s.value.is_black());
        out.iter().map(|s| s.value.luminance().max(0.0)).sum()
    }

    /// The bootstrap: uniform states (per path length when multiplexed), the normalisation
    /// and the chains started in proportion to their importance.
    fn start(&self, scene: &Scene, counts: &mut RayCounts) -> Chains {
        let lengths = if self.options.multiplexed { self.max_depth } else { 1 };
        let n = self.options.bootstrap as usize * lengths;
        let new_samples = |k: usize| {
            PrimarySamples::new(
                self.seed,
                k as u64,
                self.options.sigma,
                self.options.large_step_probability,
            )
        };
        let segments_of = |k: usize| if self.options.multiplexed { k % lengths + 1 } else { 0 };
        let (weights, rays): (Vec<f32>, Vec<RayCounts>) = (0..n)
            .into_par_iter()
            .map(|k| {
                let mut counts = RayCounts::default();
                let mut out = Vec::new();
                let w = self.evaluate(
                    scene,
                    &mut new_samples(k),
                    (segments_of(k), None),
                    &mut out,
                    &mut counts,
                );
                (w, counts)
            })
            .unzip();
        rays.iter().for_each(|r| counts.add(r));
        let hits = weights.iter().filter(|&&w| w > 0.0).count() as u64;
        // b is the image's mean luminance (for either form: the expected luminance a
        // uniform state brings, summed over path lengths). Estimated by bidirectional
        // samples stratified over the pixels, with every strategy weighted, not from the
        // bootstrap's uniform states: those find small bright emitters seen directly or
        // through a slit so rarely that b, and with it the whole image's brightness, was
        // off by 2 to 20% (Cornell box, Veach MIS) where the image's shape was right.
        let pixels = scene.width as usize * scene.height as usize;
        let spp = (n.div_ceil(pixels)).clamp(4, 256) as u32;
        let b_lengths = self.mean_luminance(scene, spp, counts);
        let b = b_lengths.iter().sum();
        // The chains' starting states, in proportion to their importance.
        let count = self.options.chains.max(1) as u64;
        let mut starts: Vec<usize> = match Distribution1D::new(weights.iter().copied()) {
            Some(distribution) => (0..count)
                .map(|c| {
                    let mut pick = penumbra_core::Pcg32::new(self.seed ^ 0x9e37_79b9_7f4a_7c15, c);
                    distribution.sample(pick.next_f32()).0
                })
                .collect(),
            None => Vec::new(),
        };
        // Each path length (when multiplexed) carries its share b_l of the image through
        // its own chains, so a length with light but no chain would lose it (a glass and
        // white blend in a furnace lost 10%). A length the bootstrap lit but whose states
        // drew no chain gets one chain more, started from one of them; the lengths that no
        // bootstrap state lit are left to an independent chain of plain bidirectional
        // samples (the blend lost 2% to such lengths).
        let mut remainder = vec![true; lengths];
        starts.iter().for_each(|&k| remainder[k % lengths] = false);
        for (l, unkept) in remainder.iter_mut().enumerate() {
            let states = (l..n).step_by(lengths);
            let total: f64 = states.clone().map(|k| weights[k] as f64).sum();
            if !*unkept || total <= 0.0 {
                continue;
            }
            let mut pick = penumbra_core::Pcg32::new(self.seed ^ 0x7f4a_7c15_9e37_79b9, l as u64);
            let mut u = pick.next_f32() as f64 * total;
            let chosen = states
                .clone()
                .find(|&k| {
                    u -= weights[k] as f64;
                    u < 0.0 && weights[k] > 0.0
                })
                .or_else(|| states.clone().rfind(|&k| weights[k] > 0.0));
            starts.extend(chosen);
            *unkept = false;
        }
        if !self.options.multiplexed {
            // The plain form's chains keep every length (`remainder` is then [no chain]).
            remainder = vec![remainder[0]; self.max_depth];
        }
        let remainder_light: f64 = b_lengths
            .iter()
            .zip(&remainder)
            .filter(|(_, &r)| r)
            .map(|(b, _)| b)
            .sum();
        let mut chains: Vec<Chain> = starts
            .into_par_iter()
            // One item per job, so no thread idles at the end (see `driver::render_pass`).
            .with_max_len(1)
            .enumerate()
            .map(|(c, k)| {
                let c = c as u64;
                let mut samples = new_samples(k);
                let mut current = Vec::new();
                let importance = self.evaluate(
                    scene,
                    &mut samples,
                    (segments_of(k), None),
                    &mut current,
                    &mut RayCounts::default(),
                );
                samples.reseed(self.seed ^ 0x2545_f491_4f6c_dd1d, c);
                Chain::new(samples, segments_of(k), current, importance)
            })
            .collect();
        chains.retain(|c| c.importance > 0.0);
        if remainder_light > 0.0 {
            // Every step large: each mutation a fresh uniform state.
            let samples = PrimarySamples::new(self.seed ^ 0x94d0_49bb_1331_11eb, 0, self.options.sigma, 1.0);
            let mut chain = Chain::new(samples, 0, Vec::new(), 0.0);
            chain.independent = Some(remainder);
            chains.push(chain);
        }
        Chains {
            chains,
            b,
            b_lengths,
            bootstrap_hits: (hits, n as u64),
        }
    }

    /// The image's mean luminance by `spp` bidirectional samples per pixel (Sobol points,
    /// rows in parallel, added in row order), per path length (segments from 1).
    fn mean_luminance(&self, scene: &Scene, spp: u32, counts: &mut RayCounts) -> Vec<f64> {
        let sampler = PixelSampler::new(penumbra_core::SamplerKind::Sobol, self.seed ^ 0x5bd1_e995, spp);
        let lengths = self.max_depth.max(1);
        let rows: Vec<(Vec<f64>, RayCounts)> = (0..scene.height)
            .into_par_iter()
            // One item per job, so no thread idles at the end (see `driver::render_pass`).
            .with_max_len(1)
            .map(|y| {
                let (mut sums, mut rays, mut splats) = (vec![0.0; lengths], RayCounts::default(), Vec::new());
                let mut by_length = vec![0.0f64; lengths];
                let mut sampler = sampler.clone();
                for x in 0..scene.width {
                    for index in 0..spp {
                        sampler.start(glam::UVec2::new(x, y), index);
                        let film = Vec2::new(x as f32, y as f32) + sampler.next_2d();
                        let ray = scene.camera.generate_ray(film, sampler.next_2d());
                        rays.camera += 1;
                        splats.clear();
                        by_length.fill(0.0);
                        self.bdpt.sample(
                            scene,
                            &ray,
                            &mut sampler,
                            &mut rays,
                            &mut splats,
                            PerLength {
                                sums: Some(&mut by_length),
                                only: None,
                            },
                        );
                        if by_length.iter().all(|v| v.is_finite()) {
                            sums.iter_mut().zip(&by_length).for_each(|(s, v)| *s += v);
                        }
                    }
                }
                (sums, rays)
            })
            .collect();
        let mut sums = vec![0.0; lengths];
        for (s, r) in rows {
            sums.iter_mut().zip(&s).for_each(|(a, b)| *a += b);
            counts.add(&r);
        }
        let n = scene.width as f64 * scene.height as f64 * spp as f64;
        sums.iter().map(|s| s / n).collect()
    }
}

impl Chain {
    fn new(samples: PrimarySamples, segments: usize, current: Vec<Splat>, importance: f32) -> Self {
        Chain {
            samples,
            segments,
            independent: None,
            current,
            importance,
            proposed: [0; 2],
            accepted: [0; 2],
        }
    }

    /// `m` mutations; the splats they make (weighted by `filter`; in units of the
    /// normalisation, which the film's splat scale supplies).
    fn run(
        &mut self,
        (mlt, scene): (&Mlt, &Scene),
        filter: &Filters,
        (m, b): (usize, f32),
        out: &mut Vec<PixelSplat>,
        counts: &mut RayCounts,
    ) {
        let size = (scene.width, scene.height);
        let mut proposal = Vec::new();
        if let Some(lengths) = &self.independent {
            // Plain Monte Carlo: each sample's contributions times `b`, which is then
            // pixels / (normalisation × m).
            for _ in 0..m {
                self.samples.start_iteration();
                mlt.evaluate(scene, &mut self.samples, (0, Some(lengths)), &mut proposal, counts);
                for s in &proposal {
                    filter.splat(
                        &Splat {
                            value: s.value * b,
                            ..*s
                        },
                        size,
                        out,
                    );
                }
                self.samples.accept();
            }
            return;
        }
        for _ in 0..m {
            self.samples.start_iteration();
            let large = self.samples.is_large_step() as usize;
            let importance = mlt.evaluate(scene, &mut self.samples, (self.segments, None), &mut proposal, counts);
            let accept = if self.importance > 0.0 {
                (importance / self.importance).min(1.0)
            } else {
                1.0
            };
            if accept > 0.0 {
                for s in &proposal {
                    let value = s.value * (accept * b / importance);
                    filter.splat(&Splat { value, ..*s }, size, out);
                }
            }
            if accept < 1.0 {
                for s in &self.current {
                    let value = s.value * ((1.0 - accept) * b / self.importance);
                    filter.splat(&Splat { value, ..*s }, size, out);
                }
            }
            self.proposed[1 - large] += 1;
            if self.samples.uniform() < accept {
                std::mem::swap(&mut self.current, &mut proposal);
                self.importance = importance;
                self.samples.accept();
                self.accepted[1 - large] += 1;
            } else {
                self.samples.reject();
            }
        }
    }
}

impl Integrator for Mlt {
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            state: Some("Markov chains"),
            own_numbers: Some("mlt mutates primary samples of its own"),
            pixel_samples: false,
            splats: true,
            ..Capabilities::default()
        }
    }

    /// A plain bidirectional sample (what a large step draws): for callers that ask one
    /// camera ray at a time; renders go through the passes.
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        self.bdpt
            .sample(scene, ray, sampler, counts, splats, PerLength::default())
    }

    fn passes(&self) -> Option<&dyn PassIntegrator> {
        Some(self)
    }

    fn prepare(&self, scene: &Scene, _: &dyn Progress) -> RayCounts {
        let mut counts = RayCounts::default();
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        state.get_or_insert_with(|| self.start(scene, &mut counts));
        counts
    }

    fn report(&self) -> Vec<String> {
        let state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let Some(chains) = state.as_ref() else {
            return Vec::new();
        };
        let (hits, n) = chains.bootstrap_hits;
        let markov = || chains.chains.iter().filter(|c| c.independent.is_none());
        let mut lines = vec![format!(
            "mlt: bootstrap {hits} of {n} states brought light; normalisation {:.6e}; {} chains",
            chains.b,
            markov().count()
        )];
        if let Some(lengths) = chains.chains.iter().find_map(|c| c.independent.as_ref()) {
            let (count, light) = lengths
                .iter()
                .zip(&chains.b_lengths)
                .filter(|(&r, _)| r)
                .fold((0, 0.0), |(n, sum), (_, b)| (n + 1, sum + b));
            lines.push(format!(
                "mlt: {count} path length(s) without a chain ({:.2}% of the image's light), from plain bidirectional samples (a larger bootstrap gives them chains)",
                100.0 * light / chains.b.max(f64::MIN_POSITIVE)
            ));
        }
        let sum = |f: fn(&Chain) -> [u64; 2]| markov().map(f).fold([0u64; 2], |a, b| [a[0] + b[0], a[1] + b[1]]);
        let (proposed, accepted) = (sum(|c| c.proposed), sum(|c| c.accepted));
        let rate = |a: u64, p: u64| if p > 0 { 100.0 * a as f64 / p as f64 } else { 0.0 };
        lines.push(format!(
            "mlt: acceptance {:.1}% of {} mutations (large steps {:.1}%, small steps {:.1}%)",
            rate(accepted[0] + accepted[1], proposed[0] + proposed[1]),
            proposed[0] + proposed[1],
            rate(accepted[0], proposed[0]),
            rate(accepted[1], proposed[1])
        ));
        let stuck = markov()
            .filter(|c| c.proposed[1] >= 100 && c.accepted[1] * 100 < c.proposed[1])
            .count();
        if stuck > 0 {
            lines.push(format!(
                "warning: mlt: {stuck} of {} chains accepted fewer than 1% of their small steps: they may be stuck on a few bright paths (more chains, a larger large-step probability or more bootstrap samples help)",
                markov().count()
            ));
        }
        lines
    }
}

impl PassIntegrator for Mlt {
    fn pass(
        &self,
        scene: &Scene,
        filter: &Filters,
        _index: u32,
        film: &mut Film,
        progress: &dyn Progress,
    ) -> RayCounts {
        let mut counts = RayCounts::default();
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let chains = state.get_or_insert_with(|| self.start(scene, &mut counts));
        let pixels = scene.width as usize * scene.height as usize;
        let n = chains.chains.len();
        if n == 0 {
            // Nothing in the scene reaches the camera: the image stays black.
            progress.advance(pixels as u64, counts.total());
            return counts;
        }
        // Multiplexed: the mutations this pass gives each path length, and the scale that
        // makes that length's splats add up to its share b_l of b.
        let share = |c: usize| pixels / n + usize::from(c < pixels % n);
        let mut scales = vec![0.0f64; chains.b_lengths.len()];
        if self.options.multiplexed {
            for (c, chain) in chains
                .chains
                .iter()
                .enumerate()
                .filter(|(_, c)| c.independent.is_none())
            {
                scales[chain.segments - 1] += share(c) as f64;
            }
            for (k, m) in scales.iter_mut().enumerate() {
                *m = if *m > 0.0 && chains.b > 0.0 {
                    chains.b_lengths[k] * pixels as f64 / (chains.b * *m)
                } else {
                    0.0
                };
            }
        }
        let scales: Vec<f32> = scales.iter().map(|&x| x as f32).collect();
        let (scales, b) = (&scales, chains.b);
        for (c0, chunk) in chains.chains.chunks_mut(CHAIN_CHUNK).enumerate() {
            let results: Vec<(Vec<PixelSplat>, RayCounts)> = chunk
                .par_iter_mut()
                // One item per job, so no thread idles at the end (see `driver::render_pass`).
                .with_max_len(1)
                .enumerate()
                .map(|(i, chain)| {
                    // This pass's mutations shared out: one per pixel in all.
                    let c = c0 * CHAIN_CHUNK + i;
                    let m = share(c);
                    let (mut out, mut rays) = (Vec::new(), RayCounts::default());
                    let scale = if chain.independent.is_some() {
                        (pixels as f64 / (b * m.max(1) as f64)) as f32
                    } else {
                        scales.get(chain.segments.wrapping_sub(1)).copied().unwrap_or(1.0)
                    };
                    chain.run((self, scene), filter, (m, scale), &mut out, &mut rays);
                    progress.advance(m as u64, rays.total());
                    (out, rays)
                })
                .collect();
            for (out, rays) in results {
                counts.add(&rays);
                for (layer, i, v) in out {
                    film.add_splat(layer, i as usize, v);
                }
            }
        }
        film.splat_scale = chains.b;
        counts
    }
}
