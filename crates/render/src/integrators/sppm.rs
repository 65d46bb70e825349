//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009; pbrt-v3 section
//! 16.2 as the reading): photon mapping made consistent. Each pass traces one camera path
//! per pixel through delta bounces to a visible point (with the emission and direct
//! lighting met on the way, which need no photons), then a batch of photons from the
//! lights; each pixel adds the photons of at least two segments that land within its
//! radius r, f(wo, wi) Φ. Its statistics then shrink the radius as the photons gathered
//! grow (α the share kept):
//!
//! N' = N + α M,  r' = r √(N' / (N + M)),  τ' = (τ + Φ) r'² / r²,
//!
//! and the pixel's indirect radiance is τ / (π r² N_e), N_e the photons emitted so far.
//! As r → 0 and N → ∞ the estimate converges to the radiance, caustics seen directly or
//! through glass included.
//!
//! Photons of a pass are traced, mapped ([`PhotonMap`]) and gathered in batches of a
//! bounded size, each batch's gathering a query per pixel, so the image does not depend on
//! the thread count and memory stays bounded whatever the scene.

use super::photons::{trace_photons, walk, Photon, PhotonMap};
use super::{Integrator, IntegratorOptions, PassIntegrator, RayCounts, Splat};
use crate::filter::Filters;
use crate::interface::{Capabilities, Progress};
use crate::{Film, Scene};
use glam::{UVec2, Vec2};
use penumbra_core::{PixelSampler, Ray, Rgb, SamplerKind};
use rayon::prelude::*;
use std::sync::Mutex;

pub struct Sppm {
    pub options: IntegratorOptions,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    pixels: Vec<PixelState>,
    /// Photons emitted so far.
    emitted: u64,
    /// Photons kept in the last pass's maps (for the report).
    stored: u64,
}

/// A pixel's running statistics.
#[derive(Clone, Copy, Default)]
struct PixelState {
    /// Emission and direct lighting, summed over the passes.
    direct: [f64; 3],
    /// The flux gathered, rescaled to the current radius (τ).
    tau: [f64; 3],
    /// Photons accounted for (N).
    n: f64,
    /// Gather radius (0 until the pixel first sees a surface).
    r: f32,
}

/// Photons kept per batch of a pass: a batch ends once it holds this many (see
/// [`trace_photons`]: never more than twice), so memory stays bounded whatever the scene.
const BATCH_PHOTONS: usize = 1 << 21;

impl Sppm {
    pub fn new(options: IntegratorOptions) -> Self {
        Sppm {
            options,
            state: Mutex::new(State::default()),
        }
    }

    /// Photons emitted per pass.
    fn photons_per_pass(&self, scene: &Scene) -> u64 {
        match self.options.photon.photons {
            0 => scene.width as u64 * scene.height as u64,
            n => n,
        }
    }

    /// Each pixel's camera path of pass `index`: radiance met on the way and the visible
    /// point, with the radius a pixel gets when it first has one.
    fn camera_pass<'a>(
        &self,
        scene: &'a Scene,
        filter: &Filters,
        index: u32,
        counts: &mut RayCounts,
    ) -> Vec<(Rgb, Option<super::photons::VisiblePoint<'a>>, f32)> {
        let sampler = PixelSampler::new(SamplerKind::Sobol, self.options.seed ^ 0x5afe_c0de, 1);
        let rows: Vec<(Vec<_>, RayCounts)> = (0..scene.height)
            .into_par_iter()
            // One item per job, so no thread idles at the end (see `driver::render_pass`).
            .with_max_len(1)
            .map(|y| {
                let (mut sampler, mut rays) = (sampler.clone(), RayCounts::default());
                let row = (0..scene.width)
                    .map(|x| {
                        let pixel = UVec2::new(x, y);
                        sampler.start(pixel, index);
                        let (offset, weight) = filter.sample(sampler.next_2d());
                        let film = pixel.as_vec2() + Vec2::splat(0.5) + offset;
                        let u_lens = sampler.next_2d();
                        let ray = scene.camera.generate_ray(film, u_lens);
                        rays.camera += 1;
                        let mut w = walk(scene, ray, Rgb::WHITE, 0, &self.options, true, &mut sampler, &mut rays);
                        // The filter's weight (negative for some filters) only scales the
                        // estimate: roulette on the way saw the path's own throughput.
                        w.radiance = w.radiance * weight;
                        if let Some(vp) = w.point.as_mut() {
                            vp.beta = vp.beta * weight;
                        }
                        let footprint = w.point.map_or(0.0, |vp| {
                            let next = scene.camera.generate_ray(film + Vec2::X, u_lens);
                            footprint(&ray, &next, vp.distance)
                        });
                        (w.radiance, w.point, footprint)
                    })
                    .collect();
                (row, rays)
            })
            .collect();
        let mut all = Vec::with_capacity(scene.width as usize * scene.height as usize);
        for (row, rays) in rows {
            all.extend(row);
            counts.add(&rays);
        }
        all
    }
}

/// How far apart the camera rays `a` and `b` (a pixel apart) are at distance `t` along
/// them: a pixel's footprint there.
fn footprint(a: &Ray, b: &Ray, t: f32) -> f32 {
    let at = |r: &Ray| r.origin + r.dir.normalize() * t;
    at(a).distance(at(b))
}

impl Integrator for Sppm {
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            state: Some("pixel statistics (radii, photon counts)"),
            own_numbers: Some("sppm draws each pass's camera paths from a Sobol sequence"),
            pixel_samples: false,
            ..Capabilities::default()
        }
    }

    /// One camera path with its direct lighting only: renders go through the passes.
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        _: &mut Vec<Splat>,
    ) -> Rgb {
        walk(scene, *ray, Rgb::WHITE, 0, &self.options, true, sampler, counts).radiance
    }

    fn passes(&self) -> Option<&dyn PassIntegrator> {
        Some(self)
    }

    fn report(&self) -> Vec<String> {
        let state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let radii: Vec<f32> = state.pixels.iter().map(|p| p.r).filter(|&r| r > 0.0).collect();
        if radii.is_empty() {
            return Vec::new();
        }
        let mean = radii.iter().map(|&r| r as f64).sum::<f64>() / radii.len() as f64;
        vec![format!(
            "sppm: {} photons emitted; {} kept in the last pass; mean gather radius {:.3e}",
            state.emitted, state.stored, mean
        )]
    }
}

impl PassIntegrator for Sppm {
    fn pass(&self, scene: &Scene, filter: &Filters, index: u32, film: &mut Film, progress: &dyn Progress) -> RayCounts {
        let mut counts = RayCounts::default();
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let pixels = scene.width as usize * scene.height as usize;
        if index == 0 || state.pixels.len() != pixels {
            // A new render (or a new frame): nothing carries over.
            *state = State {
                pixels: vec![PixelState::default(); pixels],
                ..State::default()
            };
        }
        let camera = self.camera_pass(scene, filter, index, &mut counts);
        let options = &self.options.photon;
        for (p, (radiance, vp, footprint)) in state.pixels.iter_mut().zip(&camera) {
            if radiance.is_finite() {
                p.direct
                    .iter_mut()
                    .zip(radiance.to_array())
                    .for_each(|(s, v)| *s += v as f64);
            }
            if vp.is_some() && p.r == 0.0 {
                p.r = if options.radius > 0.0 {
                    options.radius
                } else {
                    2.0 * footprint
                };
            }
        }
        // The photons of this pass, in batches; each pixel's flux Φ and count M.
        let per_pass = self.photons_per_pass(scene);
        let max_depth = self.options.max_depth as usize;
        let mut gathered = vec![([0f64; 3], 0u64); pixels];
        let first = per_pass * index as u64;
        let keep = |ph: &Photon| ph.segments >= 2;
        state.stored = 0;
        let mut start = first;
        while start < first + per_pass {
            let seed = self.options.seed ^ 0x0b5e_55ed;
            let (photons, end) = trace_photons(
                scene,
                &self.options,
                (seed, start..first + per_pass),
                (max_depth.saturating_sub(1), BATCH_PHOTONS),
                &keep,
                &mut counts,
            );
            state.stored += photons.len() as u64;
            let map = PhotonMap::build(photons);
            let radii: Vec<f32> = state.pixels.iter().map(|p| p.r).collect();
            gathered
                .par_iter_mut()
                .zip(&camera)
                .zip(&radii)
                .for_each(|(((phi, m), (_, vp, _)), &r)| {
                    let Some(vp) = vp else {
                        return;
                    };
                    let mut sum = Rgb::BLACK;
                    map.within(vp.p, r * r, |ph| {
                        if ph.segments as usize + vp.segments <= max_depth && vp.same_surface(ph, r) {
                            sum += vp.photon_value(ph);
                            *m += 1;
                        }
                    });
                    let sum = sum * vp.beta;
                    if sum.is_finite() {
                        phi.iter_mut().zip(sum.to_array()).for_each(|(s, v)| *s += v as f64);
                    }
                });
            start = end;
        }
        state.emitted += per_pass;
        // The progressive update, and the image so far.
        let alpha = options.alpha as f64;
        let (passes, emitted) = ((index + 1) as f64, state.emitted as f64);
        if film.splats.len() != pixels {
            film.splats = vec![[0.0; 3]; pixels];
        }
        for ((p, (phi, m)), out) in state.pixels.iter_mut().zip(&gathered).zip(film.splats.iter_mut()) {
            if *m > 0 {
                let n = p.n + alpha * *m as f64;
                let ratio = n / (p.n + *m as f64);
                for (t, f) in p.tau.iter_mut().zip(phi) {
                    *t = (*t + f) * ratio;
                }
                p.r *= ratio.sqrt() as f32;
                p.n = n;
            }
            let area = std::f64::consts::PI * (p.r as f64).powi(2);
            for ((o, direct), tau) in out.iter_mut().zip(p.direct).zip(p.tau) {
                let indirect = if area > 0.0 { tau / (area * emitted) } else { 0.0 };
                // The film divides its splats by the passes done.
                *o = (direct / passes + indirect) * passes;
            }
        }
        film.splat_scale = 1.0;
        progress.advance(pixels as u64, counts.total());
        counts
    }
}
