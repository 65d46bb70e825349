//! Sequential Monte Carlo across the frames of an animation (Ghosh, Doucet and Heidrich
//! 2006; the sampler is Del Moral, Doucet and Jasra's 2006 "SMC samplers"). Each pixel
//! sample keeps N particles, directions distributed in proportion to the unshadowed
//! product p_t of its shading point:
//!
//! - first frame (or when the point changes): sampling-importance-resampling from M
//!   candidates (`Target::candidates`);
//! - each later frame: reweight each particle by p_t(ω) / p_{t-1}(ω) (the environment has
//!   turned) and resample N in proportion to the weights (systematic resampling);
//! - then rejuvenate: Metropolis-Hastings moves (Metropolis et al. 1953, Hastings 1970)
//!   that leave p_t invariant, each either a small
//!   random-walk step (uniform in a cone about the particle: symmetric) or an independent
//!   draw from the map/BSDF mixture (accepted with p' q / (p q')).
//!
//! The estimate is Z_t × the mean of f L |cos θ| V / p_t over the particles (one shadow
//! ray each). In the first frame (resampling, then moves that keep p invariant) it is
//! unbiased; afterwards the carried particles only approximate p_t, and the estimate is
//! biased by their lag behind a changing sky, a bias that more samples per pixel do not
//! remove (more particles or moves do). Z_t = ∫ p_t is estimated afresh in every frame by
//! the mean weight of M unshadowed candidates from the map/BSDF mixture (no rays: only the
//! map and the BSDF are evaluated). Two other ways were tried and measured first. Carrying Z from frame to
//! frame by the mean incremental weight (the SMC sampler's own normalising constant) is
//! unbiased, but a sun that moves further than its own width between frames leaves no
//! particle where it now is: relative MSE 10 to 20 from the second frame on. Using the
//! particles only to shape a known importance density (narrow lobes about them plus a
//! defensive share of the mixture) was unbiased but 50 times noisier than MIS: four
//! particles cannot stand for a product that has a sun, a sky and a glossy lobe at once.
//!
//! The particles of pass k of a frame carry on in pass k of the next, and the camera
//! samples of a pass are the same in every frame (same seed), so a particle set stays on
//! its shading point while the scene holds still. The candidates and the resampling draw
//! on the pixel sampler (stratified over the passes, as the other strategies' samples
//! are: with independent numbers instead, the same estimator was 4 times noisier); the
//! Metropolis moves on a stream of the seed, the pixel, the pass and the frame.

use super::resample::systematic;
use super::{EnvDirect, Target};
use crate::film::Pixel;
use crate::filter::Filters;
use crate::integrators::{PassIntegrator, RayCounts};
use crate::interface::Progress;
use crate::{Film, Scene};
use glam::{UVec2, Vec2, Vec3};
use penumbra_core::hash::hash_words;
use penumbra_core::{warp, Draws, Frame, Pcg32, PixelSampler, Rgb, SamplerKind};
use rayon::prelude::*;

/// The particles of all pixel samples, and the frames rendered.
#[derive(Default)]
pub(super) struct State {
    /// Renders (frames) started with this integrator.
    pub frames: u32,
    /// By pass, the particles of each pixel in a flat layout (see [`Particles::store`]),
    /// for the passes whose particles fit in the memory allowed (`EnvOptions::memory_mib`;
    /// the pixel samples of later passes start afresh in each frame, carrying nothing).
    passes: Vec<Vec<f32>>,
    /// Passes rendered in the latest render, and how many of them kept their particles.
    kept: (u32, u32),
    /// This frame's Metropolis moves (proposed, accepted) and pixel samples started afresh
    /// (of those with a surface).
    moves: [u64; 2],
    fresh: [u64; 2],
}

/// One pixel sample's particles.
#[derive(Clone, Debug)]
pub(super) struct Particles {
    /// The shading point they belong to.
    point: Vec3,
    /// Directions and their product p at the frame they were last moved in.
    dirs: Vec<(Vec3, f32)>,
}

/// Half-angle of the random-walk moves' cone (radians).
const STEP: f32 = 0.05;

impl Particles {
    /// Floats per pixel in the flat layout for `n` particles: the point, the count, then
    /// each particle's direction and p.
    fn stride(n: usize) -> usize {
        4 + 4 * n
    }

    /// The particles stored in `slot` (none when its count is 0).
    fn load(slot: &[f32]) -> Option<Particles> {
        let count = (slot[3] as usize).min((slot.len() - 4) / 4);
        (count > 0).then(|| Particles {
            point: Vec3::new(slot[0], slot[1], slot[2]),
            dirs: slot[4..4 + 4 * count]
                .chunks_exact(4)
                .map(|c| (Vec3::new(c[0], c[1], c[2]), c[3]))
                .collect(),
        })
    }

    /// Stores the particles in `slot` (as many as fit).
    fn store(&self, slot: &mut [f32]) {
        let count = self.dirs.len().min((slot.len() - 4) / 4);
        slot[..3].copy_from_slice(&self.point.to_array());
        slot[3] = count as f32;
        for (c, (w, p)) in slot[4..].chunks_exact_mut(4).zip(&self.dirs) {
            c.copy_from_slice(&[w.x, w.y, w.z, *p]);
        }
    }
}

/// A PCG32 stream as a source of the strategies' numbers.
struct Stream(Pcg32);

impl Draws for Stream {
    fn next_1d(&mut self) -> f32 {
        self.0.next_f32()
    }

    fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.0.next_f32(), self.0.next_f32())
    }
}

impl State {
    /// What the latest render did; `memory_mib` the memory its particles were allowed.
    pub fn report(&self, memory_mib: u32) -> Vec<String> {
        let rate = |a: u64, b: u64| if b > 0 { 100.0 * a as f64 / b as f64 } else { 0.0 };
        let mut lines = vec![format!(
            "smc: render {} with these particles: {:.1}% of {} Metropolis moves accepted; {} of {} pixel samples started afresh",
            self.frames,
            rate(self.moves[1], self.moves[0]),
            self.moves[0],
            self.fresh[0],
            self.fresh[1]
        )];
        let (passes, kept) = self.kept;
        if kept < passes {
            lines.push(format!(
                "smc: the particles of {kept} of {passes} passes are carried to the next frame (--smc-memory {memory_mib} MiB); the other pixel samples start afresh in each frame"
            ));
        }
        lines
    }
}

/// What the Metropolis moves need of the product p they keep invariant.
pub(super) trait Product {
    /// p(ω) for a world direction.
    fn p(&self, w: Vec3) -> f32;
    /// A direction from the map (`from_map`) or from the BSDF's non-delta part.
    fn draw(&self, from_map: bool, u_lobe: f32, u: Vec2) -> Option<Vec3>;
    /// The density of [`Product::draw`] taking the map with probability `share`.
    fn mixture_pdf(&self, w: Vec3, share: f32) -> f32;
}

impl Product for Target<'_> {
    fn p(&self, w: Vec3) -> f32 {
        self.product(w).1
    }

    fn draw(&self, from_map: bool, u_lobe: f32, u: Vec2) -> Option<Vec3> {
        Target::draw(self, from_map, u_lobe, u)
    }

    fn mixture_pdf(&self, w: Vec3, share: f32) -> f32 {
        Target::mixture_pdf(self, w, share)
    }
}

/// `moves` Metropolis-Hastings steps of one particle (ω, p(ω)), each leaving p invariant:
/// with probability 1/2 a random-walk step (uniform in a cone about ω: symmetric, so
/// accepted with p'/p), else an independent draw ω' from the map/BSDF mixture q, accepted
/// with p' q(ω) / (p q(ω')) (Hastings 1970). Returns the moves proposed and accepted.
fn rejuvenate(t: &impl Product, (w, p): &mut (Vec3, f32), moves: u32, rng: &mut impl Draws) -> [u64; 2] {
    let cos_step = STEP.cos();
    let mut tally = [0u64; 2];
    for _ in 0..moves {
        let (choice, u_lobe, u) = (rng.next_1d(), rng.next_1d(), rng.next_2d());
        tally[0] += 1;
        let (proposal, ratio) = if choice < 0.5 {
            (Frame::from_normal(*w).to_world(warp::uniform_cone(u, cos_step)), 1.0)
        } else {
            let Some(v) = t.draw(choice < 0.75, u_lobe, u) else {
                continue;
            };
            let (q_old, q_new) = (t.mixture_pdf(*w, 0.5), t.mixture_pdf(v, 0.5));
            (v, if q_new > 0.0 { q_old / q_new } else { 0.0 })
        };
        let y = t.p(proposal);
        let accept = if *p > 0.0 { (y / *p * ratio).min(1.0) } else { 1.0 };
        if y > 0.0 && rng.next_1d() < accept {
            (*w, *p) = (proposal, y);
            tally[1] += 1;
        }
    }
    tally
}

impl EnvDirect {
    /// One pixel sample's frame: the particles in `slot` carried to this frame (or started
    /// afresh), moved, and the estimate they make; the particles stored back in `slot`
    /// (when its pass keeps them).
    fn carry(
        &self,
        scene: &Scene,
        t: &Target,
        mut slot: Option<&mut [f32]>,
        (sampler, rng): (&mut PixelSampler, &mut Stream),
        tally: &mut [u64; 4],
    ) -> (Rgb, RayCounts) {
        let mut counts = RayCounts::default();
        let n = self.options.samples.max(1) as usize;
        let point = t.sh.it.surface.p;
        tally[3] += 1;
        // Reweight and resample the particles carried over, if they are this point's.
        let carried = slot
            .as_deref_mut()
            .and_then(|slot| {
                let particles = Particles::load(slot);
                slot[3] = 0.0;
                particles
            })
            .filter(|s| s.point.distance_squared(point) <= 1e-10 * (1.0 + point.length_squared()));
        let mut candidates = Vec::new();
        let z = t.candidates(self.options.candidates.max(2) as usize, sampler, &mut candidates);
        if z <= 0.0 {
            return (Rgb::BLACK, counts);
        }
        let mut particles = carried.and_then(|mut s| {
            let now: Vec<(Vec3, f32)> = s.dirs.iter().map(|&(w, _)| (w, t.product(w).1)).collect();
            let weights = s.dirs.iter().zip(&now).map(|(&(_, before), &(_, p))| p / before);
            let picks = systematic(weights, n, sampler.next_1d());
            if picks.is_empty() {
                return None;
            }
            s.dirs = picks.iter().map(|&k| now[k]).collect();
            Some(s)
        });
        if particles.is_none() {
            tally[2] += 1;
            let picks = systematic(candidates.iter().map(|c| c.2), n, sampler.next_1d());
            let dirs: Vec<(Vec3, f32)> = picks
                .iter()
                .map(|&k| (candidates[k].0, candidates[k].1.luminance()))
                .collect();
            particles = Some(Particles { point, dirs });
        }
        let mut s = particles.expect("set above");
        // Rejuvenate: Metropolis moves invariant for this frame's product.
        for particle in s.dirs.iter_mut() {
            let [proposed, accepted] = rejuvenate(t, particle, self.options.moves, rng);
            tally[0] += proposed;
            tally[1] += accepted;
        }
        // The frame's estimate: Z_t times the particles' mean of g / p.
        let mut sum = Rgb::BLACK;
        for &(w, p) in &s.dirs {
            let (v, _) = t.product(w);
            if p > 0.0 && t.visible(scene, w, &mut counts) {
                sum += v * (1.0 / p);
            }
        }
        let count = s.dirs.len().max(1) as f32;
        if let Some(slot) = slot {
            s.store(slot);
        }
        (sum * (z as f32 / count), counts)
    }
}

impl PassIntegrator for EnvDirect {
    fn pass(&self, scene: &Scene, filter: &Filters, index: u32, film: &mut Film, progress: &dyn Progress) -> RayCounts {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let (width, pixels) = (scene.width as usize, scene.width as usize * scene.height as usize);
        if pixels == 0 {
            return RayCounts::default();
        }
        let stride = Particles::stride(self.options.samples.max(1) as usize);
        if state.passes.first().is_some_and(|p| p.len() != pixels * stride) {
            state.passes.clear();
        }
        let memory = (self.options.memory_mib as usize) << 20;
        let kept = (memory / (pixels * stride * std::mem::size_of::<f32>())).min(u32::MAX as usize) as u32;
        while state.passes.len() <= index as usize && index < kept {
            state.passes.push(vec![0.0; pixels * stride]);
        }
        if index == 0 {
            (state.moves, state.fresh) = ([0; 2], [0; 2]);
        }
        state.kept = (index + 1, kept.min(index + 1));
        let frame = state.frames as u64;
        let sampler = PixelSampler::new(SamplerKind::Sobol, self.seed ^ 0x5eed_f4a3, 1);
        // Per row: each pixel's radiance and filter weight, the rays, and the tallies.
        type Row = (Vec<(Rgb, f32)>, RayCounts, [u64; 4]);
        let rows: Vec<Option<&mut [f32]>> = match state.passes.get_mut(index as usize) {
            Some(particles) => particles.chunks_mut(width * stride).map(Some).collect(),
            None => (0..scene.height).map(|_| None).collect(),
        };
        let rows: Vec<Row> = rows
            .into_par_iter()
            // One item per job, so no thread idles at the end (see `driver::render_pass`).
            .with_max_len(1)
            .enumerate()
            .map(|(y, mut row)| {
                let (mut sampler, mut counts, mut tally) = (sampler.clone(), RayCounts::default(), [0u64; 4]);
                let values = (0..width)
                    .map(|x| {
                        let pixel = UVec2::new(x as u32, y as u32);
                        sampler.start(pixel, index);
                        let (offset, weight) = filter.sample(sampler.next_2d());
                        let film_pos = pixel.as_vec2() + Vec2::splat(0.5) + offset;
                        let ray = scene.camera.generate_ray(film_pos, sampler.next_2d());
                        counts.camera += 1;
                        let stream = hash_words(&[(y * width + x) as u64, index as u64, frame]);
                        let mut rng = Stream(Pcg32::new(self.seed ^ 0x0005_3c5e_9a11, stream));
                        let mut carry = |t: &Target, sampler: &mut PixelSampler, c: &mut RayCounts| {
                            let slot = row.as_deref_mut().map(|r| &mut r[x * stride..(x + 1) * stride]);
                            let (v, rays) = self.carry(scene, t, slot, (sampler, &mut rng), &mut tally);
                            c.add(&rays);
                            v
                        };
                        let l = self.radiance(scene, &ray, &mut sampler, &mut counts, Some(&mut carry));
                        (l, weight)
                    })
                    .collect();
                progress.advance(width as u64, counts.total());
                (values, counts, tally)
            })
            .collect();
        let mut counts = RayCounts::default();
        for (i, (l, weight)) in rows.iter().flat_map(|r| r.0.iter()).enumerate() {
            if l.is_finite() {
                let mut p = Pixel::default();
                p.add(*l, *weight);
                film.pixels_mut()[i].add(&p);
            } else {
                film.rejected += 1;
            }
        }
        for (_, rays, tally) in &rows {
            counts.add(rays);
            state.moves[0] += tally[0];
            state.moves[1] += tally[1];
            state.fresh[0] += tally[2];
            state.fresh[1] += tally[3];
        }
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_testkit::chi2_directions;

    /// A product with a lobe towards +x, e^{5x}, and a mixture that is not uniform (a
    /// cosine lobe about +z from the "map", uniform directions from the "BSDF"): a wrong
    /// Hastings ratio would bend the particles towards +z.
    struct Lobe;

    impl Product for Lobe {
        fn p(&self, w: Vec3) -> f32 {
            (5.0 * w.x).exp()
        }

        fn draw(&self, from_map: bool, _: f32, u: Vec2) -> Option<Vec3> {
            Some(if from_map {
                warp::cosine_hemisphere(u)
            } else {
                warp::uniform_sphere(u)
            })
        }

        fn mixture_pdf(&self, w: Vec3, share: f32) -> f32 {
            let cosine = w.z.max(0.0) * std::f32::consts::FRAC_1_PI;
            share * cosine + (1.0 - share) * std::f32::consts::FRAC_1_PI / 4.0
        }
    }

    /// Particles drawn exactly from p (by rejection from the uniform sphere) and moved keep
    /// the law p: chi-square over the sphere (10 × 20 bins, 200,000 particles, 1% level).
    #[test]
    fn moves_leave_the_product_invariant() {
        let normalisation = 4.0 * std::f32::consts::PI * (5.0f32).sinh() / 5.0;
        let mut rng = Stream(Pcg32::new(7, 1));
        let mut accepted = [0u64; 2];
        let result = chi2_directions(
            11,
            200_000,
            |_| {
                let w = loop {
                    let w = warp::uniform_sphere(rng.next_2d());
                    if rng.next_1d() * (5.0f32).exp() < Lobe.p(w) {
                        break w;
                    }
                };
                let mut particle = (w, Lobe.p(w));
                let tally = rejuvenate(&Lobe, &mut particle, 4, &mut rng);
                (accepted[0], accepted[1]) = (accepted[0] + tally[0], accepted[1] + tally[1]);
                Some(particle.0)
            },
            |w| Lobe.p(w) / normalisation,
        );
        println!(
            "{} of {} moves accepted; {}",
            accepted[1],
            accepted[0],
            result.describe()
        );
        assert!(accepted[1] * 5 > accepted[0], "too few moves accepted to test anything");
        result.assert_fits("particles after Metropolis moves", 1);
    }
}
