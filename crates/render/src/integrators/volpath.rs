//! Volumetric path tracing: everything `path` does, plus participating media, by the
//! null-scattering path formulation of Miller, Georgiev and Jarosz ("A null-scattering
//! path integral formulation of light transport", SIGGRAPH 2019) as pbrt-v4's
//! `VolPathIntegrator` implements it (section 14.2): free flights drawn by delta tracking
//! against each medium's majorant in one "hero" RGB channel chosen per path, the other
//! channels carried by the rescaled path probabilities `r_u` (of the path as sampled) and
//! `r_l` (of the same path by light sampling), so that the channels are combined by the
//! balance heuristic (spectral MIS); light samples at surfaces and in media, their shadow
//! rays weighed by ratio tracking through the media and stepping over boundaries
//! ([`crate::Material::null`]), combined with BSDF and phase sampling by the balance
//! heuristic. Russian roulette as `path` (Mitsuba's rule, on the throughput over the mean
//! of `r_u`), after surface and medium vertices alike.
//!
//! A scene without media is rendered by `path` itself: the same image, bit for bit.

use super::nee::Shading;
use super::{Integrator, IntegratorOptions, PathTracer, RayCounts, Splat};
use crate::bsdfs::TransportMode;
use crate::interface::{Capabilities, Progress};
use crate::lights::{AreaSampling, LightSelection};
use crate::media::{attenuation, channel, Medium, MediumInterface, Segment, Step, Tracker};
use crate::phase::Phase;
use crate::Scene;
use glam::Vec3;
use penumbra_core::ray::{offset_origin, SHADOW_EPSILON};
use penumbra_core::{Pcg32, PixelSampler, Ray, Rgb};

pub struct VolPath {
    options: IntegratorOptions,
    /// The integrator of scenes without media.
    path: PathTracer,
}

impl VolPath {
    pub fn new(options: IntegratorOptions) -> Self {
        VolPath {
            options,
            path: PathTracer::new(options),
        }
    }
}

/// A path's throughput and its rescaled probabilities (pbrt-v4's β, r_u, r_l): the path's
/// estimate is β L / mean(r_u) for light found by sampling it, and β L / mean(r_u + r_l)
/// where light sampling could have found it too.
#[derive(Clone, Copy, Debug)]
struct Weights {
    beta: Rgb,
    r_u: Rgb,
    r_l: Rgb,
}

/// Where a path scatters: at a surface (with the media on its sides, if it separates
/// media), or at a point of a medium.
enum Vertex<'a> {
    Surface(&'a Shading<'a>, Option<MediumInterface>),
    Medium { p: Vec3, wo: Vec3, phase: Phase },
}

/// What one path carries through [`VolPath::trace`]'s stages.
struct PathSampling<'a> {
    sampler: &'a mut PixelSampler,
    /// The generator of the tracking's numbers (their count varies from path to path, so
    /// they do not come from the sampler's dimensions: pbrt-v4's rule).
    rng: Pcg32,
    /// The RGB channel whose majorant draws the free flights.
    hero: usize,
    /// The majorant segments of the medium being tracked (a buffer the batch's paths share).
    segments: &'a mut Vec<Segment>,
}

/// The most boundaries a ray may cross in a row before it is given up (a ray caught
/// crossing one surface over and over, as rounding could make it, must not hang a render).
const MAX_CROSSINGS: u32 = 1024;

/// What a medium did to a ray before its surface.
enum Flight {
    /// The ray reached its end (the surface hit, or infinity).
    Through,
    Absorbed,
    Scattered {
        p: Vec3,
        phase: Phase,
    },
}

impl Integrator for VolPath {
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            media: true,
            ..Capabilities::default()
        }
    }

    fn batch_size(&self) -> usize {
        self.path.batch_size()
    }

    fn prepare(&self, scene: &Scene, progress: &dyn Progress) -> RayCounts {
        self.path.prepare(scene, progress)
    }

    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        if scene.media.is_empty() {
            return self.path.li(scene, ray, sampler, counts, splats);
        }
        self.trace(scene, ray, sampler, counts, &mut Vec::new())
    }

    fn li_batch(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &mut [PixelSampler],
        out: &mut [Rgb],
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
    ) {
        if scene.media.is_empty() {
            return self.path.li_batch(scene, rays, samplers, out, counts, splats);
        }
        let mut segments = Vec::new();
        for ((ray, sampler), out) in rays.iter().zip(samplers).zip(out) {
            *out = self.trace(scene, ray, sampler, counts, &mut segments);
        }
    }
}

impl VolPath {
    /// The lights' selection and area sampling, as `path` uses them.
    fn light_strategy(&self) -> (LightSelection, AreaSampling) {
        let selection = match self.options.direct.selection {
            LightSelection::All => LightSelection::Power,
            s => s,
        };
        (selection, AreaSampling::Adaptive)
    }

    /// The radiance arriving along `camera_ray` in a scene with media.
    fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        segments: &mut Vec<Segment>,
    ) -> Rgb {
        let (selection, sampling) = self.light_strategy();
        let hero = ((sampler.next_1d() * 3.0) as usize).min(2);
        let seed = (u64::from(sampler.next_1d().to_bits()) << 32) | u64::from(sampler.next_1d().to_bits());
        let mut s = PathSampling {
            sampler,
            rng: Pcg32::new(seed, 0x0076_6f6c_7061_7468),
            hero,
            segments,
        };
        let mut w = Weights {
            beta: Rgb::WHITE,
            r_u: Rgb::WHITE,
            r_l: Rgb::WHITE,
        };
        let mut radiance = Rgb::BLACK;
        let mut ray = Ray::new(camera_ray.origin, camera_ray.dir.normalize());
        let mut medium = scene.camera_medium;
        // Whether the last vertex was the camera or a perfectly specular bounce (no light
        // sample could have found what the ray meets), and where it was.
        let (mut specular, mut previous) = (true, ray.origin);
        let mut eta_scale = 1.0f32;
        let (mut depth, mut crossings) = (0u32, 0u32);
        loop {
            let hit = scene.accel.intersect(&ray, f32::INFINITY);
            if let Some(m) = medium {
                let t_max = hit.map_or(f32::INFINITY, |h| h.t);
                match fly(&scene.media[m as usize], &ray, t_max, &mut w, &mut s) {
                    Flight::Through => {}
                    Flight::Absorbed => break,
                    Flight::Scattered { p, phase } => {
                        if depth + 1 >= self.options.max_depth {
                            break;
                        }
                        let wo = -ray.dir;
                        let at = Vertex::Medium { p, wo, phase };
                        radiance += self.light_sample(scene, &at, medium, &w, &mut s, counts);
                        // The phase function is sampled exactly: its weight p/pdf is 1.
                        let (wi, pdf) = phase.sample(wo, s.sampler.next_2d());
                        w.r_l = w.r_u / pdf;
                        (specular, previous, crossings) = (false, p, 0);
                        counts.secondary += 1;
                        ray = Ray::new(p, wi);
                        if !self.roulette(&mut w, eta_scale, depth, s.sampler) {
                            break;
                        }
                        depth += 1;
                        continue;
                    }
                }
            }
            let Some(hit) = hit else {
                radiance += self.escaped(scene, &ray, &w, specular);
                break;
            };
            let it = scene.interaction(&ray, &hit);
            if let Some((index, light)) = scene.emitter_at(&it) {
                let normal = light.emitter.normal_at(it.surface.p);
                let le = light.le(it.surface.p, normal, it.wo);
                if !le.is_black() {
                    let r = if specular {
                        w.r_u
                    } else {
                        let p_light =
                            scene.lights.pmf(selection, index) * light.pdf(previous, it.surface.p, normal, sampling);
                        w.r_u + w.r_l * p_light
                    };
                    radiance += w.beta * le / r.mean();
                }
            }
            let crossing = scene.media_of(it.surface.object).copied();
            if scene.is_boundary(it.surface.object) {
                // A boundary between media only: the ray goes on, the depth unchanged.
                crossings += 1;
                if crossings > MAX_CROSSINGS {
                    break;
                }
                if let Some(mi) = crossing {
                    medium = mi.towards(it.surface.ng, ray.dir);
                }
                ray = Ray::new(beyond(it.surface.p, it.surface.ng, ray.dir), ray.dir);
                continue;
            }
            if depth + 1 >= self.options.max_depth {
                break;
            }
            let sh = Shading::new(&it);
            if sh.bsdf.has_smooth() {
                let at = Vertex::Surface(&sh, crossing);
                radiance += self.light_sample(scene, &at, medium, &w, &mut s, counts);
            }
            let (u_lobe, u) = (s.sampler.next_1d(), s.sampler.next_2d());
            let Some(bs) = sh.bsdf.sample(sh.wo, u_lobe, u, TransportMode::Radiance) else {
                break;
            };
            let wi = sh.frame.to_world(bs.wi);
            if !sh.agrees(wi, bs.wi) {
                break;
            }
            w.beta *= bs.weight;
            w.r_l = w.r_u / bs.pdf;
            eta_scale *= bs.eta * bs.eta;
            let origin = sh.origin_towards(wi);
            (specular, previous, crossings) = (bs.delta, origin, 0);
            counts.secondary += 1;
            ray = Ray::new(origin, wi);
            if let Some(mi) = crossing {
                medium = mi.towards(it.surface.ng, wi);
            }
            if !self.roulette(&mut w, eta_scale, depth, s.sampler) {
                break;
            }
            depth += 1;
        }
        radiance
    }

    /// The environment (or the background) met by a ray that left the scene, weighted
    /// against the environment's light samples unless the last vertex was specular.
    fn escaped(&self, scene: &Scene, ray: &Ray, w: &Weights, specular: bool) -> Rgb {
        let Some((index, env)) = scene.environment() else {
            return w.beta * scene.background / w.r_u.mean();
        };
        let at = env.lookup(ray.dir);
        let r = if specular {
            w.r_u
        } else {
            let (selection, _) = self.light_strategy();
            w.r_u + w.r_l * (scene.lights.pmf(selection, index) * env.pdf_at(&at))
        };
        w.beta * env.le_at(&at) / r.mean()
    }

    /// One light sample at `at` (in `medium`, the vertex's own for a medium point and the
    /// incoming ray's for a surface): its contribution, its shadow ray's transmittance
    /// estimated by ratio tracking, weighed against BSDF or phase sampling (balance
    /// heuristic over both strategies and the three channels).
    fn light_sample(
        &self,
        scene: &Scene,
        at: &Vertex,
        medium: Option<u32>,
        w: &Weights,
        s: &mut PathSampling,
        counts: &mut RayCounts,
    ) -> Rgb {
        let (selection, sampling) = self.light_strategy();
        let (u_pick, u) = (s.sampler.next_1d(), s.sampler.next_2d());
        let Some((index, p_pick)) = scene.lights.pick(selection, u_pick) else {
            return Rgb::BLACK;
        };
        let light = &scene.lights.lights()[index as usize];
        let p = match at {
            Vertex::Surface(sh, _) => sh.origin,
            Vertex::Medium { p, .. } => *p,
        };
        let Some(ls) = light.sample_li(p, u, sampling) else {
            return Rgb::BLACK;
        };
        if ls.li.is_black() || !ls.wi.is_finite() {
            return Rgb::BLACK;
        }
        let (f, pdf_scatter, origin, medium) = match at {
            Vertex::Surface(sh, crossing) => {
                let Some(l) = sh.local(ls.wi) else {
                    return Rgb::BLACK;
                };
                let f = sh.bsdf.eval(sh.wo, l, TransportMode::Radiance) * l.z.abs();
                let pdf = sh.bsdf.pdf(sh.wo, l, TransportMode::Radiance);
                let medium = crossing.map_or(medium, |mi| mi.towards(sh.it.surface.ng, ls.wi));
                (f, pdf, sh.origin_towards(ls.wi), medium)
            }
            Vertex::Medium { p, wo, phase } => {
                let v = phase.p(*wo, ls.wi);
                (Rgb::splat(v), v, *p, medium)
            }
        };
        if f.is_black() {
            return Rgb::BLACK;
        }
        let Some(tr) = transmittance(scene, (origin, ls.wi, ls.dist), medium, s, counts) else {
            return Rgb::BLACK;
        };
        let r_l = w.r_u * tr.r_l * (p_pick * ls.pdf);
        let value = w.beta * f * tr.t * ls.li;
        if ls.delta {
            value / r_l.mean()
        } else {
            value / (r_l + w.r_u * tr.r_u * pdf_scatter).mean()
        }
    }

    /// Russian roulette from `rr_depth` on (`path`'s rule, with the throughput β/mean(r_u)):
    /// whether the path survives.
    fn roulette(&self, w: &mut Weights, eta_scale: f32, depth: u32, sampler: &mut PixelSampler) -> bool {
        if depth + 1 < self.options.rr_depth {
            return true;
        }
        let q = ((w.beta / w.r_u.mean()).max_component() * eta_scale).min(0.95);
        if sampler.next_1d() >= q {
            return false;
        }
        w.beta = w.beta / q;
        true
    }
}

/// Delta tracking of `ray` (unit direction) through `medium` up to `t_max`: each tentative
/// collision is real with the hero channel's probability σt/σ_maj, else null. A real
/// collision always scatters, its throughput weighted by σs (the albedo, where pbrt-v4
/// draws absorption as an event that ends the path: the weight, as Mitsuba's `volpath`
/// uses it, keeps the paths that absorption would end and leaves them to Russian roulette,
/// which costs less variance); its density σt T_maj goes into r_u. A null collision
/// weights β and r_u by σn T_maj over its density and r_l by σ_maj T_maj (pbrt-v4).
fn fly(medium: &Medium, ray: &Ray, t_max: f32, w: &mut Weights, s: &mut PathSampling) -> Flight {
    let hero = s.hero;
    let mut walk = Tracker::new(medium, (ray.origin, ray.dir, t_max), hero, s.segments);
    loop {
        match walk.step(&mut s.rng) {
            Step::End { t_maj } => {
                let Some(ratio) = over_hero(t_maj, hero) else {
                    return Flight::Absorbed;
                };
                for x in [&mut w.beta, &mut w.r_u, &mut w.r_l] {
                    *x *= ratio;
                }
                return Flight::Through;
            }
            Step::Collision { t, sigma_maj, t_maj } => {
                let p = ray.at(t);
                let mp = medium.at(p);
                let sigma_t = mp.sigma_t();
                let t_hero = channel(t_maj, hero);
                if s.rng.next_f32() * channel(sigma_maj, hero) < channel(sigma_t, hero) {
                    let pdf = t_hero * channel(sigma_t, hero);
                    w.beta *= t_maj * mp.sigma_s / pdf;
                    w.r_u *= t_maj * sigma_t / pdf;
                    if w.beta.is_black() {
                        return Flight::Absorbed;
                    }
                    return Flight::Scattered { p, phase: mp.phase };
                }
                let sigma_n = (sigma_maj - sigma_t).max(Rgb::BLACK);
                let pdf = t_hero * channel(sigma_n, hero);
                if pdf == 0.0 {
                    return Flight::Absorbed;
                }
                w.beta *= t_maj * sigma_n / pdf;
                w.r_u *= t_maj * sigma_n / pdf;
                w.r_l *= t_maj * sigma_maj / pdf;
                if w.beta.is_black() || w.r_u.is_black() {
                    return Flight::Absorbed;
                }
            }
        }
    }
}

/// A shadow ray's transmittance estimate `t` and the factors it brings to the rescaled
/// probabilities of the light-sampled path (`r_l`) and of the same path sampled
/// unidirectionally (`r_u`).
struct Transmittance {
    t: Rgb,
    r_l: Rgb,
    r_u: Rgb,
}

/// Ratio tracking (Novák et al. 2014, pbrt-v4's `SampleLd` loop) from `origin` along the
/// unit `dir` to the light's point at distance `dist` (infinite for lights at infinity),
/// starting in `medium`: through every medium met, stepping over boundaries
/// ([`crate::Material::null`]) and switching media there; `None` where a surface blocks the
/// ray or the estimate is zero. The estimate is cut by Russian roulette (kept with
/// probability 1/4) where it falls below 0.05.
///
/// After each boundary the ray is aimed again from where it now starts (pushed off the
/// boundary) at the light's point, and ends short of it by [`SHADOW_EPSILON`] of the whole
/// distance (pbrt-v4's `SpawnRayTo`): going on along the old direction from the pushed-off
/// point, or shortening the extent by the boundary's hit distance, carried the ray onto the
/// light itself where the light lies just beyond a boundary (it was then taken as blocked).
fn transmittance(
    scene: &Scene,
    (mut origin, dir, dist): (Vec3, Vec3, f32),
    mut medium: Option<u32>,
    s: &mut PathSampling,
    counts: &mut RayCounts,
) -> Option<Transmittance> {
    let hero = s.hero;
    let target = origin + dir * dist;
    let margin = dist * SHADOW_EPSILON;
    let mut tr = Transmittance {
        t: Rgb::WHITE,
        r_l: Rgb::WHITE,
        r_u: Rgb::WHITE,
    };
    let mut dir = dir;
    for _ in 0..=MAX_CROSSINGS {
        let reach = if dist.is_finite() {
            let to_target = target - origin;
            dir = to_target.normalize_or(dir);
            to_target.length() - margin
        } else {
            f32::INFINITY
        };
        if reach <= 0.0 {
            return Some(tr);
        }
        counts.shadow += 1;
        let ray = Ray::new(origin, dir);
        let hit = scene.accel.intersect(&ray, reach);
        let it = hit.map(|h| scene.interaction(&ray, &h));
        if it.as_ref().is_some_and(|it| !scene.is_boundary(it.surface.object)) {
            return None;
        }
        if let Some(m) = medium {
            let m = &scene.media[m as usize];
            let end = hit.map_or(reach, |h| h.t);
            if m.is_homogeneous() {
                // The expectation of ratio tracking's estimate, which is binary here (no
                // null collisions): passing, with the hero channel's probability T, it
                // weighs T/T_hero into the estimate and the two r's.
                let t = attenuation(m.at(origin).sigma_t(), end);
                let ratio = over_hero(t, hero)?;
                tr.t *= t;
                tr.r_l *= ratio;
                tr.r_u *= ratio;
            } else if !ratio_tracking(m, &ray, end, s, &mut tr) {
                return None;
            }
        }
        let Some(it) = it else {
            return Some(tr);
        };
        if let Some(mi) = scene.media_of(it.surface.object) {
            medium = mi.towards(it.surface.ng, dir);
        }
        origin = beyond(it.surface.p, it.surface.ng, dir);
    }
    None
}

/// Ratio tracking of `ray` (unit direction) through `m` over `[0, end)` into `tr`, as
/// pbrt-v4's `SampleLd`; whether the estimate is still above zero.
fn ratio_tracking(m: &Medium, ray: &Ray, end: f32, s: &mut PathSampling, tr: &mut Transmittance) -> bool {
    let hero = s.hero;
    let mut walk = Tracker::new(m, (ray.origin, ray.dir, end), hero, s.segments);
    loop {
        match walk.step(&mut s.rng) {
            Step::Collision { t, sigma_maj, t_maj } => {
                let sigma_n = (sigma_maj - m.at(ray.at(t)).sigma_t()).max(Rgb::BLACK);
                let pdf = channel(t_maj, hero) * channel(sigma_maj, hero);
                tr.t *= t_maj * sigma_n / pdf;
                tr.r_l *= t_maj * sigma_maj / pdf;
                tr.r_u *= t_maj * sigma_n / pdf;
                let estimate = tr.t / (tr.r_l + tr.r_u).mean();
                if estimate.max_component() < 0.05 {
                    tr.t = if s.rng.next_f32() < 0.75 {
                        Rgb::BLACK
                    } else {
                        tr.t / 0.25
                    };
                }
                if tr.t.is_black() {
                    return false;
                }
            }
            Step::End { t_maj } => {
                let Some(ratio) = over_hero(t_maj, hero) else {
                    return false;
                };
                for x in [&mut tr.t, &mut tr.r_l, &mut tr.r_u] {
                    *x *= ratio;
                }
                return true;
            }
        }
    }
}

/// A transmittance `t` over its hero channel's (the probability with which the hero
/// channel's tracking passed); `None` where that is zero.
fn over_hero(t: Rgb, hero: usize) -> Option<Rgb> {
    let p = channel(t, hero);
    (p > 0.0).then(|| t / p)
}

/// The surface point `p` (geometric normal `ng`) pushed off to the side `dir` leaves by.
fn beyond(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    offset_origin(p, if ng.dot(dir) >= 0.0 { ng } else { -ng })
}
