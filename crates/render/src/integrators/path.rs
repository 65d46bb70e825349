//! Unidirectional path tracing of the rendering equation (Kajiya 1986), as pbrt-v4's
//! `PathIntegrator` and Mitsuba 3's `path` do it: one random continuation per bounce drawn
//! from the BSDF, next-event estimation at every vertex with a non-delta part (one shadow
//! ray to a light picked by power, solid-angle sampled unless it is a small flat light),
//! emitters and the environment reached by the continuation rays weighted against it by the
//! power heuristic (Veach and Guibas 1995), and Russian roulette from `rr_depth` on with
//! survival probability min(max throughput channel × η², 0.95).
//!
//! `max_depth` has Mitsuba's meaning: the largest number of path segments, so 1 shows the
//! emitters only, 2 gives direct lighting, and each further unit one more bounce.
//!
//! The paths of a batch of camera rays advance in lockstep, one stage at a time over all
//! of them (a wavefront, as in Laine, Karras and Aila, "Megakernels Considered Harmful",
//! 2013): closest hits for every live path; then at each surface the emission met, a light
//! sample (its shadow ray kept) and the continuation; then every shadow ray. Each stage is
//! a loop over the batch (a whole tile of camera rays, [`BATCH`]), so the rays of a stage
//! go to the accelerator together (`Accel::intersect_batch`, [`Scene::occluded_batch`]:
//! one call, at the CPU's SIMD level, for all of them; the camera rays, coherent, by
//! `Accel::intersect_coherent`, which walks the BVH in packets of eight); paths at plain Lambertian
//! triangles are set aside at the hit and take their bounce eight at a time in SIMD lanes
//! (`diffuse_lanes.rs`). Every path draws its random numbers and adds its terms in the
//! order a path traced alone would, so a batch gives exactly the radiance of its paths
//! traced one by one ([`PathTracer::li`] is a batch of one).

use super::bsdf_lanes::{BsdfAnswer, BsdfQuery, Buckets};
use super::light_lanes::{sample_lights, LightRequest};
use super::nee::{self, LightPoint, LightStrategy, Shading};
use super::path_diffuse::{Columns, LaneTable};
use super::{Integrator, IntegratorOptions, MisHeuristic, RayCounts, Splat, VolPath};
use crate::bsdfs::BsdfSample;
use crate::interface::Progress;
use crate::lights::{AreaSampling, LightSelection};
use crate::Scene;
use glam::Vec3;
use penumbra_core::{PixelSampler, Ray, Rgb};
use penumbra_geometry::Hit;

/// The default depth (path segments) from which Russian roulette may end paths, Mitsuba's.
pub const RR_DEPTH: u32 = 5;

/// The most paths traced in lockstep: a whole tile of the driver at its default size (16 x
/// 16 pixels), so that the eight-lane groups stay full as paths end.
pub const BATCH: usize = 256;

pub struct PathTracer {
    pub options: IntegratorOptions,
    /// Bounces at plain Lambertian surfaces taken eight paths at a time
    /// (`integrators/diffuse_lanes.rs`); the same image either way, `false` only to show that.
    pub eight_wide: bool,
    /// The scene's meshes that take the eight-lane bounce, made by `prepare`.
    pub lanes: LaneTable,
}

impl PathTracer {
    pub fn new(options: IntegratorOptions) -> Self {
        PathTracer {
            options,
            eight_wide: true,
            lanes: LaneTable::default(),
        }
    }
}

/// Up to [`BATCH`] camera rays, their samplers and where their radiance goes.
struct Batch<'a> {
    rays: &'a [Ray],
    samplers: &'a mut [PixelSampler],
    out: &'a mut [Rgb],
}

/// What one path carries from bounce to bounce.
#[derive(Clone, Copy)]
pub(super) struct PathState {
    pub radiance: Rgb,
    pub beta: Rgb,
    pub ray: Ray,
    /// The BSDF density of the ray's direction at the vertex it left (its origin); `None`
    /// after the camera or a perfectly specular bounce (nothing else could have sampled it).
    pub previous_pdf: Option<f32>,
    /// The product of η² over the refractions so far.
    pub eta_scale: f32,
    pub alive: bool,
}

/// The shadow rays of a depth, the path and light each brings if unblocked.
pub(super) struct Shadows<'a, const N: usize> {
    pub rays: &'a mut [(Ray, f32); N],
    pub light: &'a mut [(usize, Rgb); N],
    pub len: usize,
}

impl<const N: usize> Shadows<'_, N> {
    /// Adds the shadow ray from `origin` along `dir` up to `t_max`, field by field (a
    /// whole ray copied through a temporary costs a stalled reload).
    #[inline(always)]
    pub fn push(&mut self, origin: Vec3, dir: Vec3, t_max: f32, light: (usize, Rgb)) {
        let (ray, t) = &mut self.rays[self.len];
        (ray.origin, ray.dir, *t) = (origin, dir, t_max);
        self.light[self.len] = light;
        self.len += 1;
    }
}

impl Integrator for PathTracer {
    fn capabilities(&self) -> crate::interface::Capabilities {
        crate::interface::Capabilities {
            spectral: true,
            ..Default::default()
        }
    }

    /// The wavefront's batch: [`BATCH`] paths traced and shaded together.
    fn batch_size(&self) -> usize {
        BATCH
    }

    fn prepare(&self, scene: &Scene, _: &dyn Progress) -> RayCounts {
        self.lanes.fill(scene);
        RayCounts::default()
    }

    fn li(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        _: &mut Vec<Splat>,
    ) -> Rgb {
        if scene.spectral {
            return VolPath::new(self.options).trace(scene, camera_ray, sampler, counts, &mut Vec::new());
        }
        let mut out = [Rgb::BLACK];
        let batch = Batch {
            rays: std::slice::from_ref(camera_ray),
            samplers: std::slice::from_mut(sampler),
            out: &mut out,
        };
        self.trace_batch::<1>(scene, batch, counts);
        out[0]
    }

    fn li_batch(
        &self,
        scene: &Scene,
        camera_rays: &[Ray],
        samplers: &mut [PixelSampler],
        out: &mut [Rgb],
        counts: &mut RayCounts,
        _: &mut Vec<Splat>,
    ) {
        if scene.spectral {
            // Spectral paths are traced one at a time by `volpath`'s program over the
            // wavelengths' payload (the same image `volpath` gives without media).
            let volpath = VolPath::new(self.options);
            let mut segments = Vec::new();
            for ((ray, sampler), out) in camera_rays.iter().zip(samplers).zip(out) {
                *out = volpath.trace(scene, ray, sampler, counts, &mut segments);
            }
            return;
        }
        for ((rays, samplers), out) in camera_rays
            .chunks(BATCH)
            .zip(samplers.chunks_mut(BATCH))
            .zip(out.chunks_mut(BATCH))
        {
            self.trace_batch::<BATCH>(scene, Batch { rays, samplers, out }, counts);
        }
    }
}

impl PathTracer {
    /// Traces up to `N` paths in lockstep (a batch of one for [`Integrator::li`]: no
    /// room set up for the lanes it does not use).
    fn trace_batch<const N: usize>(&self, scene: &Scene, batch: Batch, counts: &mut RayCounts) {
        let Batch {
            rays: camera_rays,
            samplers,
            out,
        } = batch;
        let n = camera_rays.len();
        // One shadow ray per vertex: "every light in turn" makes no sense here, and picking
        // by power with `All`'s within-object probabilities would break the MIS weights.
        let selection = match self.options.direct.selection {
            LightSelection::All => LightSelection::Power,
            s => s,
        };
        let heuristic = MisHeuristic::Power;
        let nee = LightStrategy {
            sampling: AreaSampling::Adaptive,
            samples: 1.0,
            mis: Some((heuristic, 1.0)),
        };
        let no_ray = Ray::new(Vec3::ZERO, Vec3::Z);
        // The arrays below are written in place (no temporaries copied in) and hold only
        // what a stage needs: a batch's whole state fits the first-level data cache better.
        // (The shading points are collected anew at each depth: they borrow that depth's
        // surfaces.)
        let mut paths = [PathState {
            radiance: Rgb::BLACK,
            beta: Rgb::WHITE,
            ray: no_ray,
            previous_pdf: None,
            eta_scale: 1.0,
            alive: false,
        }; N];
        for (path, ray) in paths.iter_mut().zip(camera_rays) {
            (path.ray, path.alive) = (*ray, true);
        }
        let mut live = [0usize; N];
        // The paths at plain Lambertian triangles, for the lanes, and the others (surfaces
        // of any kind, or nothing met), each in the order of `live`.
        let mut group = Vec::with_capacity(N);
        let mut others: Vec<(usize, Option<Hit>)> = Vec::with_capacity(N);
        // Shadow rays (ray, t_max), the path and light each brings if unblocked, and the
        // answers.
        let mut shadow_rays = [(no_ray, 0.0f32); N];
        // The live paths' rays, traced together, and their hits.
        let mut closest_rays = [(no_ray, 0.0f32); N];
        let mut hits = [None; N];
        let mut shadow_light = [(0usize, Rgb::BLACK); N];
        let mut blocked = [false; N];
        // The shading points of a depth (other than the lanes' Lambertian triangles), what
        // each asks of its BSDF and the answers, the light samples waiting for them.
        let mut its = Vec::with_capacity(N);
        let (mut queries, mut answers, mut points) =
            (Vec::with_capacity(N), Vec::with_capacity(N), Vec::with_capacity(N));
        // The paths that left the scene at a depth.
        let mut escaped = Vec::with_capacity(N);
        // The lights picked there (their probabilities), and their samples.
        let (mut picks, mut requests, mut light_samples) =
            (Vec::with_capacity(N), Vec::with_capacity(N), Vec::with_capacity(N));
        let mut one_by_one = Vec::with_capacity(N);
        let mut buckets = Buckets::default();
        let mut columns = Columns::new();
        // The paths still alive, compacted as paths end.
        for (i, l) in live.iter_mut().enumerate() {
            *l = i;
        }
        let mut count = n;
        let lanes = self.lanes.read();
        for depth in 0.. {
            // Closest hits of every live path.
            // Without a branch: which paths ended is a coin toss for the predictor.
            let mut still = 0;
            for j in 0..count {
                let i = live[j];
                live[still] = i;
                still += paths[i].alive as usize;
            }
            count = still;
            if count == 0 {
                break;
            }
            // The surfaces met; plain Lambertian triangles are set aside for the lanes (they
            // are not emitters: nothing to add before their bounce).
            group.clear();
            others.clear();
            for (k, r) in closest_rays[..count].iter_mut().enumerate() {
                *r = (paths[live[k]].ray, f32::INFINITY);
            }
            if depth == 0 {
                scene
                    .accel
                    .intersect_coherent(&closest_rays[..count], &mut hits[..count]);
            } else {
                scene.accel.intersect_batch(&closest_rays[..count], &mut hits[..count]);
            }
            for (k, &hit) in hits[..count].iter().enumerate() {
                match hit.and_then(|hit| self.diffuse_lane(scene, &lanes, k, &hit)) {
                    Some(_) if depth + 1 >= self.options.max_depth => paths[live[k]].alive = false,
                    Some(d) => group.push(d),
                    None => others.push((k, hit)),
                }
            }

            // Emission met at each surface, and where paths end; plain Lambertian triangles
            // after the others, eight at a time.
            its.clear();
            escaped.clear();
            for &(k, hit) in &others {
                let path = &mut paths[live[k]];
                let Some(hit) = hit else {
                    escaped.push(live[k]);
                    path.alive = false;
                    continue;
                };
                let it = scene.interaction(&path.ray, &hit);
                if let Some((index, light)) = scene.emitter_at(&it) {
                    let normal = light.emitter.normal_at(it.surface.p);
                    let le = light.le(it.surface.p, normal, it.wo);
                    if !le.is_black() {
                        let weight = path.previous_pdf.map_or(1.0, |p_bsdf| {
                            let p = path.ray.origin;
                            let hit = (index, light);
                            nee::emitter_weight(
                                scene,
                                (selection, nee.sampling),
                                heuristic,
                                p,
                                hit,
                                it.surface.p,
                                normal,
                                (1.0, p_bsdf),
                                1.0,
                            )
                        });
                        path.radiance += path.beta * le * weight;
                    }
                }
                // One more segment would exceed the maximum path length.
                if depth + 1 >= self.options.max_depth {
                    path.alive = false;
                    continue;
                }
                its.push((k, it));
            }
            // The environment met by the paths that left the scene, looked up eight at a
            // time, weighted against its light sampling as an emitter is.
            for group in escaped.chunks(8) {
                let Some(env) = scene.environment() else {
                    for &i in group {
                        paths[i].radiance += paths[i].beta * scene.background;
                    }
                    continue;
                };
                let dirs = std::array::from_fn(|j| paths[group[j.min(group.len() - 1)]].ray.dir);
                for (&i, at) in group.iter().zip(env.1.lookup8(&dirs)) {
                    let path = &mut paths[i];
                    let weight = path.previous_pdf.map_or(1.0, |p_bsdf| {
                        nee::environment_weight(scene, (selection, heuristic), env, &at, (1.0, p_bsdf), 1.0)
                    });
                    path.radiance += path.beta * (env.1.le_at(&at) * weight);
                }
            }
            // At each shading point, in each path's order of random numbers: a light
            // sample (the point on the light), then what the BSDF is asked (its value
            // and density towards the light, a continuation), answered by kind in lanes.
            // The light samples are taken together (in lanes where the light's kind has
            // a lane kernel), after every point has drawn its numbers.
            let shs: Vec<Shading> = its.iter().map(|(_, it)| Shading::new(it)).collect();
            queries.clear();
            picks.clear();
            requests.clear();
            for ((k, _), sh) in its.iter().zip(&shs) {
                let sampler = &mut samplers[live[*k]];
                let pick = sh.bsdf.has_smooth().then(|| {
                    let u_pick = sampler.next_1d();
                    let u = sampler.next_2d();
                    let (light, p_pick) = scene.lights.pick(selection, u_pick)?;
                    requests.push(LightRequest { light, p: sh.origin, u });
                    Some(p_pick)
                });
                picks.push(pick.flatten());
                let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
                queries.push(BsdfQuery {
                    light: None,
                    sample: true,
                    u_lobe,
                    u,
                });
            }
            sample_lights(scene, &requests, nee.sampling, &mut light_samples, &mut one_by_one);
            points.clear();
            let mut samples = light_samples.iter();
            for ((query, sh), pick) in queries.iter_mut().zip(&shs).zip(&picks) {
                let point = pick.and_then(|p_pick| LightPoint::new(sh, samples.next().copied().flatten()?, p_pick));
                query.light = point.map(|p| (p.l, !p.ls.delta));
                points.push(point);
            }
            answers.resize(queries.len(), BsdfAnswer::default());
            buckets.answer(&shs, &queries, &mut answers);
            // The light samples' shadow rays (kept for later) and the continuations.
            let mut m = 0;
            for (j, ((k, _), sh)) in its.iter().zip(&shs).enumerate() {
                let path = &mut paths[live[*k]];
                let a = &answers[j];
                if let Some(test) = points[j].and_then(|p| p.finish(a.f, || a.pdf, &nee)) {
                    // What the light brings if visible, with the throughput up to here.
                    shadow_rays[m] = (test.ray, test.t_max);
                    shadow_light[m] = (live[*k], path.beta * test.value);
                    m += 1;
                }
                let sampler = &mut samplers[live[*k]];
                path.alive = self.continue_with(sh, path, a.sample, sampler, depth, counts);
            }

            let mut shadows = Shadows {
                rays: &mut shadow_rays,
                light: &mut shadow_light,
                len: m,
            };
            for group in group.chunks(8) {
                self.diffuse_bounces(
                    scene,
                    group,
                    &live,
                    (&mut paths, samplers),
                    &mut shadows,
                    (depth, &nee, selection),
                    counts,
                    &mut columns,
                );
            }
            let m = shadows.len;

            // Every shadow ray of the batch, then the light of those that reached it.
            counts.shadow += m as u64;
            scene.occluded_batch(&shadow_rays[..m], &mut blocked[..m]);
            for (&(lane, value), &blocked) in shadow_light[..m].iter().zip(&blocked) {
                if !blocked {
                    paths[lane].radiance += value;
                }
            }
        }
        for (o, path) in out.iter_mut().zip(&paths) {
            *o = path.radiance;
        }
    }

    /// Continues `path` at `sh` along `bs`, drawn from the whole BSDF (delta lobes
    /// included), and plays Russian roulette; whether the path goes on.
    fn continue_with(
        &self,
        sh: &Shading,
        path: &mut PathState,
        bs: Option<BsdfSample>,
        sampler: &mut PixelSampler,
        depth: u32,
        counts: &mut RayCounts,
    ) -> bool {
        let Some(bs) = bs else {
            return false;
        };
        let wi = sh.frame.to_world(bs.wi);
        if !sh.agrees(wi, bs.wi) {
            return false;
        }
        path.beta *= bs.weight;
        path.eta_scale *= bs.eta * bs.eta;
        counts.secondary += 1;
        path.ray = Ray::new(sh.origin_towards(wi), wi);
        path.previous_pdf = (!bs.delta).then_some(bs.pdf);

        self.roulette(path, depth, || sampler.next_1d())
    }

    /// Russian roulette from `rr_depth` on, with `u()` the path's next random number;
    /// whether the path survives. Survival by the throughput with refraction's 1/η²
    /// undone (as Mitsuba and pbrt-v4), so that paths inside glass are not cut for their
    /// scaling alone.
    pub(super) fn roulette(&self, path: &mut PathState, depth: u32, u: impl FnOnce() -> f32) -> bool {
        if depth + 1 >= self.options.rr_depth {
            let q = (path.beta.max_component() * path.eta_scale).min(0.95);
            if u() >= q {
                return false;
            }
            path.beta = path.beta / q;
        }
        true
    }
}
