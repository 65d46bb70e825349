//! Volumetric path tracing: everything `path` does, plus participating media, by the
//! null-scattering path formulation of Miller, Georgiev and Jarosz ("A null-scattering
//! path integral formulation of light transport", SIGGRAPH 2019) as pbrt-v4's
//! `VolPathIntegrator` implements it (section 14.2): free flights drawn by delta tracking
//! against each medium's majorant in one "hero" RGB channel chosen per path, the other
//! channels carried by the rescaled path probabilities `r_u` (of the path as sampled) and
//! `r_l` (of the same path by light sampling), so that the channels are combined by the
//! balance heuristic (spectral MIS); light samples at surfaces and in media, their shadow
//! rays weighed by ratio tracking through the media and stepping over boundaries
//! ([`crate::Material::null`]), combined with BSDF and phase sampling by the power
//! heuristic on the channels' mean probabilities (as `path` and Mitsuba's `volpath` weigh
//! the two strategies). Russian roulette as `path` (Mitsuba's rule, on the throughput over the mean
//! of `r_u`), after surface and medium vertices alike.
//!
//! A scene without media is rendered by `path` itself: the same image, bit for bit. In
//! spectral mode ([`crate::spectral`]) this integrator renders for `path` too: the same
//! program over a path's four wavelengths ([`SpectralTint`]; the hero wavelength draws the
//! free flights), scene colours turned into values there by the tint.

use super::nee::Shading;
use super::{Integrator, IntegratorOptions, PathTracer, RayCounts, Splat};
use crate::bsdfs::TransportMode;
use crate::bsdfs::{BsdfKind, Dielectric, Role};
use crate::interface::{Capabilities, Progress};
use crate::lights::{AreaSampling, LightSelection};
use crate::media::{MediumInterface, Segment};
use crate::phase::Phase;
use crate::spectral::{MaterialSpectra, RgbTint, SpectralTint, Tint};
use crate::Scene;
use glam::Vec3;
use tracking::{fly, transmittance};

mod tracking;
use penumbra_core::lanes::V3;
use penumbra_core::ray::offset_origin;
use penumbra_core::spectrum::Spectrum;
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
struct Weights<S> {
    beta: S,
    r_u: S,
    r_l: S,
}

/// `a` over the mean of the channels of `r` that the path still carries (the path's
/// estimate, see [`Weights`]; [`Tint::mean`]).
#[inline]
fn over_mean<T: Tint>(tint: &T, a: T::S, r: T::S) -> T::S {
    a.scale(1.0 / tint.mean(r))
}

/// `value` found by one of two strategies whose rescaled probabilities for the path are
/// `own` and `other` (their means over the channels: the spectral MIS), weighted against
/// the other by the power heuristic (Veach and Guibas 1995, as `path` and Mitsuba weigh
/// light and BSDF samples): value/own × own²/(own² + other²).
#[inline]
fn power_weighted<T: Tint>(tint: &T, value: T::S, own: T::S, other: T::S) -> T::S {
    let (a, b) = (tint.mean(own), tint.mean(other));
    value.scale(a / (a * a + b * b))
}

/// Where a path scatters: at a surface (with the media on its sides, if it separates
/// media), or at a point of a medium.
enum Vertex<'a> {
    Surface(&'a Shading<'a>, Option<MediumInterface>),
    Medium { p: Vec3, wo: Vec3, phase: Phase },
}

/// What one path carries through [`VolPath::trace`]'s stages.
struct PathSampling<'a, T> {
    /// How the scene's colours become the path's payload.
    tint: T,
    sampler: &'a mut PixelSampler,
    /// The generator of the tracking's numbers (their count varies from path to path, so
    /// they do not come from the sampler's dimensions: pbrt-v4's rule).
    rng: Pcg32,
    /// The payload's channel whose majorant draws the free flights (RGB: chosen per path;
    /// spectral: the hero wavelength).
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
            spectral: true,
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
        if scene.media.is_empty() && !scene.spectral {
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
        if scene.media.is_empty() && !scene.spectral {
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

    /// The radiance arriving along `camera_ray`, as linear RGB: RGB paths in a scene with
    /// media, paths of four wavelengths in spectral mode (the first number of the sample
    /// draws the hero channel or wavelength).
    pub(super) fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        segments: &mut Vec<Segment>,
    ) -> Rgb {
        let u = sampler.next_1d();
        if scene.spectral {
            let tint = SpectralTint::sample(u);
            return self.trace_in(scene, camera_ray, sampler, counts, segments, (tint, 0));
        }
        let hero = ((u * 3.0) as usize).min(2);
        self.trace_in(scene, camera_ray, sampler, counts, segments, (RgbTint, hero))
    }

    /// [`VolPath::trace`] in the payload of `tint`, `hero` its channel that draws flights.
    fn trace_in<T: Tint>(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        segments: &mut Vec<Segment>,
        (tint, hero): (T, usize),
    ) -> Rgb {
        let (selection, sampling) = self.light_strategy();
        let seed = (u64::from(sampler.next_1d().to_bits()) << 32) | u64::from(sampler.next_1d().to_bits());
        let mut s = PathSampling {
            tint,
            sampler,
            rng: Pcg32::new(seed, 0x0076_6f6c_7061_7468),
            hero,
            segments,
        };
        let one = T::S::splat(1.0);
        let mut w = Weights {
            beta: one,
            r_u: one,
            r_l: one,
        };
        let mut radiance = T::S::splat(0.0);
        // Radiance found before the path became its hero wavelength's alone (dispersion).
        let mut banked = Rgb::BLACK;
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
                        radiance = radiance + self.light_sample(scene, &at, medium, &w, &mut s, counts);
                        // The phase function is sampled exactly: its weight p/pdf is 1.
                        let (wi, pdf) = phase.sample(wo, s.sampler.next_2d());
                        w.r_l = w.r_u.div_by(pdf);
                        (specular, previous, crossings) = (false, p, 0);
                        counts.secondary += 1;
                        ray = Ray::new(p, wi);
                        if !self.roulette(&s.tint, &mut w, eta_scale, depth, s.sampler) {
                            break;
                        }
                        depth += 1;
                        continue;
                    }
                }
            }
            let Some(hit) = hit else {
                radiance = radiance + self.escaped(scene, &ray, &w, specular, &s.tint);
                break;
            };
            let it = scene.interaction(&ray, &hit);
            if let Some((index, light)) = scene.emitter_at(&it) {
                let normal = light.emitter.normal_at(it.surface.p);
                let le = light.le(it.surface.p, normal, it.wo);
                if !le.is_black() {
                    let le = w.beta.mul_each(s.tint.illuminant(scene.light_spectrum(index), le));
                    radiance = radiance
                        + if specular {
                            over_mean(&s.tint, le, w.r_u)
                        } else {
                            let p_light = scene.lights.pmf(selection, index)
                                * light.pdf(previous, it.surface.p, normal, sampling);
                            power_weighted(&s.tint, le, w.r_u, w.r_l.scale(p_light))
                        };
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
            let mut sh = Shading::new(&it);
            let spectra = scene.spectra_of(it.surface.object);
            if let Some((ior, outside, d)) = dispersive(&sh, spectra) {
                if s.tint.carries_several() {
                    // What the four wavelengths found so far is theirs, weighed by their
                    // spectral MIS; from here on only the hero could have drawn the path,
                    // so its own probabilities weigh the rest ([`Tint::mean`]).
                    banked += s.tint.to_rgb(radiance);
                    radiance = T::S::splat(0.0);
                    s.tint.keep_hero_only();
                }
                if let Some(lambda) = s.tint.hero() {
                    sh.bsdf.kind = BsdfKind::Dielectric(Dielectric {
                        eta: ior.eval(lambda) / outside,
                        ..d
                    });
                }
            }
            if sh.bsdf.has_smooth() {
                let at = Vertex::Surface(&sh, crossing);
                radiance = radiance + self.light_sample(scene, &at, medium, &w, &mut s, counts);
            }
            let (u_lobe, u) = (s.sampler.next_1d(), s.sampler.next_2d());
            let Some(bs) = sample_bsdf(&sh, spectra, &s.tint, u_lobe, u) else {
                break;
            };
            let wi = sh.frame.to_world(bs.wi);
            if !sh.agrees(wi, bs.wi) {
                break;
            }
            w.beta = w.beta.mul_each(bs.weight);
            w.r_l = w.r_u.div_by(bs.pdf);
            eta_scale *= bs.eta * bs.eta;
            let origin = sh.origin_towards(wi);
            (specular, previous, crossings) = (bs.delta, origin, 0);
            counts.secondary += 1;
            ray = Ray::new(origin, wi);
            if let Some(mi) = crossing {
                medium = mi.towards(it.surface.ng, wi);
            }
            if !self.roulette(&s.tint, &mut w, eta_scale, depth, s.sampler) {
                break;
            }
            depth += 1;
        }
        banked + s.tint.to_rgb(radiance)
    }

    /// The environment (or the background) met by a ray that left the scene, weighted
    /// against the environment's light samples unless the last vertex was specular.
    fn escaped<T: Tint>(&self, scene: &Scene, ray: &Ray, w: &Weights<T::S>, specular: bool, tint: &T) -> T::S {
        let Some((index, env)) = scene.environment() else {
            return over_mean(tint, w.beta.mul_each(tint.illuminant(None, scene.background)), w.r_u);
        };
        let at = env.lookup(ray.dir);
        let le = w.beta.mul_each(tint.illuminant(None, env.le_at(&at)));
        if specular {
            return over_mean(tint, le, w.r_u);
        }
        let (selection, _) = self.light_strategy();
        power_weighted(
            tint,
            le,
            w.r_u,
            w.r_l.scale(scene.lights.pmf(selection, index) * env.pdf_at(&at)),
        )
    }

    /// One light sample at `at` (in `medium`, the vertex's own for a medium point and the
    /// incoming ray's for a surface): its contribution, its shadow ray's transmittance
    /// estimated by ratio tracking, weighed against BSDF or phase sampling (the power
    /// heuristic between the strategies, the balance heuristic over the channels).
    fn light_sample<T: Tint>(
        &self,
        scene: &Scene,
        at: &Vertex,
        medium: Option<u32>,
        w: &Weights<T::S>,
        s: &mut PathSampling<T>,
        counts: &mut RayCounts,
    ) -> T::S {
        let zero = T::S::splat(0.0);
        let (selection, sampling) = self.light_strategy();
        let (u_pick, u) = (s.sampler.next_1d(), s.sampler.next_2d());
        let Some((index, p_pick)) = scene.lights.pick(selection, u_pick) else {
            return zero;
        };
        let light = &scene.lights.lights()[index as usize];
        let p = match at {
            Vertex::Surface(sh, _) => sh.origin,
            Vertex::Medium { p, .. } => *p,
        };
        let Some(ls) = light.sample_li(p, u, sampling) else {
            return zero;
        };
        if ls.li.is_black() || !ls.wi.is_finite() {
            return zero;
        }
        let (f, pdf_scatter, origin, medium) = match at {
            Vertex::Surface(sh, crossing) => {
                let Some(l) = sh.local(ls.wi) else {
                    return zero;
                };
                let spectra = scene.spectra_of(sh.it.surface.object);
                let (f, pdf) = eval_bsdf(sh, spectra, &s.tint, l);
                let medium = crossing.map_or(medium, |mi| mi.towards(sh.it.surface.ng, ls.wi));
                (f.scale(l.z.abs()), pdf, sh.origin_towards(ls.wi), medium)
            }
            Vertex::Medium { p, wo, phase } => {
                let v = phase.p(*wo, ls.wi);
                (T::S::splat(v), v, *p, medium)
            }
        };
        if Spectrum::is_black(f) {
            return zero;
        }
        let Some(tr) = transmittance(scene, (origin, ls.wi, ls.dist), medium, s, counts) else {
            return zero;
        };
        let r_l = w.r_u.mul_each(tr.r_l).scale(p_pick * ls.pdf);
        let li = s.tint.illuminant(scene.light_spectrum(index), ls.li);
        let value = w.beta.mul_each(f).mul_each(tr.t).mul_each(li);
        if ls.delta {
            over_mean(&s.tint, value, r_l)
        } else {
            power_weighted(&s.tint, value, r_l, w.r_u.mul_each(tr.r_u).scale(pdf_scatter))
        }
    }

    /// Russian roulette from `rr_depth` on (`path`'s rule, with the throughput β/mean(r_u)):
    /// whether the path survives.
    fn roulette<T: Tint>(
        &self,
        tint: &T,
        w: &mut Weights<T::S>,
        eta_scale: f32,
        depth: u32,
        sampler: &mut PixelSampler,
    ) -> bool {
        if depth + 1 < self.options.rr_depth {
            return true;
        }
        let q = (over_mean(tint, w.beta, w.r_u).max_channel() * eta_scale).min(0.95);
        if sampler.next_1d() >= q {
            return false;
        }
        w.beta = w.beta.scale(1.0 / q);
        true
    }
}

/// A dispersive glass at `sh` (a dielectric whose material gives its index by
/// wavelength): the index inside, outside, and the BSDF to give the hero's index. A
/// spectral path meeting one keeps its hero wavelength alone and refracts by the index
/// there (pbrt-v4's `TerminateSecondary`); RGB paths use the material's one index.
fn dispersive<'m>(
    sh: &Shading,
    spectra: Option<&'m MaterialSpectra>,
) -> Option<(&'m crate::spectral::SpectrumValue, f32, Dielectric)> {
    match (spectra.and_then(|m| m.ior.as_ref()), sh.bsdf.kind) {
        (Some((ior, outside)), BsdfKind::Dielectric(d)) => Some((ior, *outside, d)),
        _ => None,
    }
}

/// The BSDF's value and density towards `l` (local) in the tint's payload (a kind without
/// a kernel over payloads answers in RGB, uplifted as a reflectance).
fn eval_bsdf<T: Tint>(sh: &Shading, spectra: Option<&MaterialSpectra>, tint: &T, l: Vec3) -> (T::S, f32) {
    let mode = TransportMode::Radiance;
    let to = |role: Role, c: V3<f32>| tint.param(spectra, role, c);
    match sh.bsdf.eval_pdf_in(sh.wo, l, mode, &to) {
        Some(answer) => answer,
        None => (
            tint.param(None, Role::Reflectance, sh.bsdf.eval(sh.wo, l, mode).into()),
            sh.bsdf.pdf(sh.wo, l, mode),
        ),
    }
}

/// A direction from the BSDF, its weight in the tint's payload (see [`eval_bsdf`]).
fn sample_bsdf<T: Tint>(
    sh: &Shading,
    spectra: Option<&MaterialSpectra>,
    tint: &T,
    u_lobe: f32,
    u: glam::Vec2,
) -> Option<crate::bsdfs::SampleIn<T::S>> {
    let mode = TransportMode::Radiance;
    let to = |role: Role, c: V3<f32>| tint.param(spectra, role, c);
    match sh.bsdf.sample_in(sh.wo, u_lobe, u, mode, &to) {
        Some(s) => s,
        None => sh.bsdf.sample(sh.wo, u_lobe, u, mode).map(|b| crate::bsdfs::SampleIn {
            wi: b.wi,
            weight: tint.param(None, Role::Reflectance, b.weight.into()),
            pdf: b.pdf,
            delta: b.delta,
            eta: b.eta,
        }),
    }
}

/// The surface point `p` (geometric normal `ng`) pushed off to the side `dir` leaves by.
fn beyond(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    offset_origin(p, if ng.dot(dir) >= 0.0 { ng } else { -ng })
}
