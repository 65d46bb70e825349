//! Direct lighting from an environment map at the first surface the camera sees, by one
//! of five strategies, to compare them (`--env-sampling`):
//!
//! - `light`: directions from the map's own distribution (luminance × sin θ);
//! - `bsdf`: directions from the BSDF;
//! - `mis`: one of each per shadow ray, weighted by the power heuristic (Veach and Guibas
//!   1995);
//! - `sir`: sampling-importance-resampling toward the product of the two factors (Burke,
//!   Ghosh and Heidrich 2005, "Bidirectional Importance Sampling for Direct Illumination";
//!   Talbot et al. 2005, resampled importance sampling): M candidates, half drawn from the
//!   map and half from the BSDF, weighted by the unshadowed product over their mixture
//!   density; N of them resampled in proportion to the weights get a shadow ray. Shadow
//!   rays, the expensive part, go only where the product is large;
//! - `smc`: sequential Monte Carlo across the frames of an animation (Ghosh, Doucet and
//!   Heidrich 2006, "Sequential Sampling for Dynamic Environment Map Illumination"): each
//!   pixel sample keeps N particles from frame to frame, reweighted by the change of the
//!   product, resampled and moved by Metropolis steps (`smc.rs`).
//!
//! The product is p(ω) = Y(f(ωo, ω) L(ω) |cos θ|), Y the luminance, without visibility.
//! Delta lobes (mirrors, glass) are followed by one shadow ray each under every strategy.
//! Only the environment lights the surfaces; other lights are ignored, emitters are seen.

mod resample;
mod smc;

use super::nee::Shading;
use super::{Integrator, MisHeuristic, PassIntegrator, RayCounts, Splat};
use crate::bsdfs::TransportMode;
use crate::interface::{Capabilities, Progress};
use crate::lights::Environment;
use crate::Scene;
use glam::{Vec2, Vec3};
use penumbra_core::{Draws, PixelSampler, Ray, Rgb};
use std::sync::Mutex;

/// How the environment's light at a surface is sampled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EnvSampling {
    Light,
    Bsdf,
    #[default]
    Mis,
    Sir,
    Smc,
}

impl EnvSampling {
    pub const NAMES: [&'static str; 5] = ["mis", "light", "bsdf", "sir", "smc"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "light" => Some(EnvSampling::Light),
            "bsdf" => Some(EnvSampling::Bsdf),
            "mis" => Some(EnvSampling::Mis),
            "sir" => Some(EnvSampling::Sir),
            "smc" => Some(EnvSampling::Smc),
            _ => None,
        }
    }
}

/// The settings of the `env` integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvOptions {
    pub sampling: EnvSampling,
    /// Shadow rays per pixel sample (N; for `mis`, N light and N BSDF samples).
    pub samples: u32,
    /// `sir` and `smc` (its ∫ p each frame and its first particles): candidates per pixel
    /// sample (M). Few are best where rays are cheap: on `scenes/glossy-env.toml` at equal
    /// time, 8 gave a third of the error of 32.
    pub candidates: u32,
    /// `smc`: Metropolis moves per particle per frame (4 followed the turning sky better
    /// than 2: error in the eighth frame 5.5e-3 against 1.4e-2).
    pub moves: u32,
    /// `smc`: the memory its particles may take (MiB): they are kept, to be carried to
    /// the next frame, for as many passes as fit; later passes start afresh in each frame.
    pub memory_mib: u32,
}

impl Default for EnvOptions {
    fn default() -> Self {
        EnvOptions {
            sampling: EnvSampling::Mis,
            samples: 4,
            candidates: 8,
            moves: 4,
            memory_mib: 512,
        }
    }
}

pub struct EnvDirect {
    pub options: EnvOptions,
    pub seed: u64,
    /// `smc`'s particles of every pixel sample, and the frames rendered so far.
    state: Mutex<smc::State>,
}

impl EnvDirect {
    pub fn new(options: EnvOptions, seed: u64) -> Self {
        EnvDirect {
            options,
            seed,
            state: Mutex::new(smc::State::default()),
        }
    }
}

/// A shading point and the environment, with what the strategies evaluate there.
pub(super) struct Target<'a> {
    pub sh: &'a Shading<'a>,
    pub env: &'a Environment,
}

impl Target<'_> {
    /// f L |cos θ| towards world direction `w` (no visibility), and its luminance p(ω).
    pub fn product(&self, w: Vec3) -> (Rgb, f32) {
        let Some(l) = self.sh.local(w) else {
            return (Rgb::BLACK, 0.0);
        };
        let v = self.sh.bsdf.eval(self.sh.wo, l, TransportMode::Radiance) * self.env.le(w) * l.z.abs();
        let y = v.luminance();
        if v.is_finite() && y > 0.0 {
            (v, y)
        } else {
            (Rgb::BLACK, 0.0)
        }
    }

    /// The BSDF's density of the non-delta direction `w`.
    fn bsdf_pdf(&self, w: Vec3) -> f32 {
        let l = self.sh.frame.to_local(w);
        self.sh.bsdf.pdf(self.sh.wo, l, TransportMode::Radiance)
    }

    /// The density of a direction from the map with probability `share`, else from the
    /// BSDF (the balance heuristic's density for that split of the samples).
    pub fn mixture_pdf(&self, w: Vec3, share: f32) -> f32 {
        share * self.env.pdf(w) + (1.0 - share) * self.bsdf_pdf(w)
    }

    /// A direction from the map (`from_map`) or from the BSDF's non-delta part.
    pub fn draw(&self, from_map: bool, u_lobe: f32, u: Vec2) -> Option<Vec3> {
        if from_map {
            return self.env.sample_li(u).map(|s| s.wi);
        }
        let s = self.sh.bsdf.sample(self.sh.wo, u_lobe, u, TransportMode::Radiance)?;
        (!s.delta).then(|| self.sh.frame.to_world(s.wi))
    }

    /// 1 if nothing blocks the way from the point towards `w`, else 0 (counted).
    pub fn visible(&self, scene: &Scene, w: Vec3, counts: &mut RayCounts) -> bool {
        counts.shadow += 1;
        !scene.occluded(&Ray::new(self.sh.origin_towards(w), w), f32::INFINITY)
    }

    /// M candidates, the first ⌊M/2⌋ from the map and the rest from the BSDF, each with its
    /// product and weight p / q (q the mixture density for that split: Veach's balance
    /// heuristic with sample counts, so an odd M is unbiased too); their mean weight
    /// estimates ∫ p (Burke et al. 2005).
    pub fn candidates(&self, m: usize, sampler: &mut impl Draws, out: &mut Vec<(Vec3, Rgb, f32)>) -> f64 {
        out.clear();
        let mut sum = 0.0f64;
        for j in 0..m {
            let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
            let Some(w) = self.draw(j < m / 2, u_lobe, u) else {
                continue;
            };
            let (v, y) = self.product(w);
            let q = self.mixture_pdf(w, (m / 2) as f32 / m as f32);
            if y > 0.0 && q > 0.0 {
                let weight = y / q;
                sum += weight as f64;
                out.push((w, v, weight));
            }
        }
        sum / m.max(1) as f64
    }
}

impl EnvDirect {
    /// The environment's light reflected at `sh` by the non-pass strategies.
    fn reflected(&self, scene: &Scene, t: &Target, sampler: &mut impl Draws, counts: &mut RayCounts) -> Rgb {
        let n = self.options.samples.max(1) as usize;
        let mut sum = Rgb::BLACK;
        // One sample of one factor (the map's or the BSDF's), weighted against the other's
        // density by the power heuristic when `mis`.
        let one = |draw: &mut dyn FnMut() -> (f32, Vec2), counts: &mut RayCounts, from_map: bool, mis: bool| {
            let (u_lobe, u) = draw();
            let Some(w) = t.draw(from_map, u_lobe, u) else {
                return Rgb::BLACK;
            };
            let (v, _) = t.product(w);
            let (map, bsdf) = (|| t.env.pdf(w), || t.bsdf_pdf(w));
            let p = if from_map { map() } else { bsdf() };
            if v.is_black() || p <= 0.0 || !t.visible(scene, w, counts) {
                return Rgb::BLACK;
            }
            let weight = match (mis, from_map) {
                (false, _) => 1.0,
                (true, true) => MisHeuristic::Power.weight(p, bsdf()),
                (true, false) => MisHeuristic::Power.weight(p, map()),
            };
            v * (weight / p)
        };
        let mut draw = || (sampler.next_1d(), sampler.next_2d());
        match self.options.sampling {
            EnvSampling::Light => (0..n).for_each(|_| sum += one(&mut draw, counts, true, false)),
            EnvSampling::Bsdf => (0..n).for_each(|_| sum += one(&mut draw, counts, false, false)),
            EnvSampling::Mis => {
                (0..n).for_each(|_| sum += one(&mut draw, counts, true, true) + one(&mut draw, counts, false, true))
            }
            EnvSampling::Sir | EnvSampling::Smc => {
                let mut candidates = Vec::new();
                let m = self.options.candidates.max(2) as usize;
                let z = t.candidates(m, sampler, &mut candidates);
                let picks = resample::systematic(candidates.iter().map(|c| c.2), n, sampler.next_1d());
                // The picks come sorted: a candidate picked r times takes one shadow ray.
                for run in picks.chunk_by(|a, b| a == b) {
                    let (w, v, _) = candidates[run[0]];
                    let y = v.luminance();
                    if t.visible(scene, w, counts) {
                        sum += v * (run.len() as f32 * z as f32 / y);
                    }
                }
            }
        }
        sum * (1.0 / n as f32)
    }

    /// What the camera sees along `ray`: the environment, or a surface's emission and the
    /// environment's light it reflects (delta lobes traced once each); `particles`, when
    /// given, supply the smooth part (`smc`).
    pub(super) fn radiance(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        particles: Option<&mut Reflected>,
    ) -> Rgb {
        let Some(it) = scene.intersect(ray, f32::INFINITY) else {
            return scene.escaped(ray.dir);
        };
        let mut radiance = scene.emitted(&it);
        let Some((_, env)) = scene.environment() else {
            return radiance;
        };
        let sh = Shading::new(&it);
        let t = Target { sh: &sh, env };
        let rays = sh.bsdf.specular_rays(sh.wo, TransportMode::Radiance);
        counts.specular_overflows += (rays.dropped() > 0.0) as u64;
        for r in rays.as_slice() {
            let w = sh.frame.to_world(r.wi);
            if sh.agrees(w, r.wi) && t.visible(scene, w, counts) {
                radiance += r.weight * env.le(w);
            }
        }
        if sh.bsdf.has_smooth() {
            radiance += match particles {
                Some(f) => f(&t, sampler, counts),
                None => self.reflected(scene, &t, sampler, counts),
            };
        }
        radiance
    }
}

/// What supplies the smooth part of the reflected light instead of the strategies (`smc`'s
/// particles).
pub(super) type Reflected<'a> = dyn FnMut(&Target, &mut PixelSampler, &mut RayCounts) -> Rgb + 'a;

impl Integrator for EnvDirect {
    fn capabilities(&self) -> Capabilities {
        if self.options.sampling != EnvSampling::Smc {
            return Capabilities::default();
        }
        Capabilities {
            state: Some("particles (smc)"),
            own_numbers: Some("env with smc draws each pass's camera samples from a Sobol sequence"),
            pixel_samples: false,
            carries_frames: true,
            ..Capabilities::default()
        }
    }

    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        _: &mut Vec<Splat>,
    ) -> Rgb {
        self.radiance(scene, ray, sampler, counts, None)
    }

    fn passes(&self) -> Option<&dyn PassIntegrator> {
        (self.options.sampling == EnvSampling::Smc).then_some(self as &dyn PassIntegrator)
    }

    fn prepare(&self, _: &Scene, _: &dyn Progress) -> RayCounts {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).frames += 1;
        RayCounts::default()
    }

    fn report(&self) -> Vec<String> {
        if self.options.sampling != EnvSampling::Smc {
            return Vec::new();
        }
        self.state
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .report(self.options.memory_mib)
    }
}
