//! What the photon-mapping integrators share (Jensen 1996, "Global Illumination Using
//! Photon Maps"; Hachisuka and Jensen 2009): photons traced from the lights and kept where
//! they meet a surface with a non-delta part ([`trace_photons`]), the map they are looked
//! up in ([`PhotonMap`]), and the camera's walk through perfect mirrors and glass to the
//! first surface that can take a density estimate ([`walk`]), with emission and direct
//! lighting gathered on the way.
//!
//! Path lengths keep the meaning of `max_depth` (segments): a photon of s segments found
//! at a point the camera reached in t segments makes a path of s + t segments, and is
//! counted only when that is at most `max_depth`.
//!
//! At a surface with both delta lobes (a coat, glass) and a smooth part, the walk either
//! stops there for a density estimate, with probability p_s (the albedo's share, kept in
//! [0.2, 0.8]), or goes on along one delta direction, chosen in proportion to its weight;
//! each branch is divided by its probability, so the estimate stays unbiased whatever p_s
//! is.

mod map;

pub use map::PhotonMap;

use super::bdpt::shading_correction;
use super::nee::{self, LightStrategy, Shading};
use super::{IntegratorOptions, MisHeuristic, RayCounts};
use crate::bsdfs::{Bsdf, TransportMode};
use crate::lights::{AreaSampling, LightSelection};
use crate::Scene;
use glam::{Vec2, Vec3};
use penumbra_core::{Draws, Frame, Pcg32, Ray, Rgb};
use rayon::prelude::*;

/// A photon where it met a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    pub p: Vec3,
    /// Unit direction back towards where it came from.
    pub wi: Vec3,
    /// The surface's geometric normal on the side the photon came from.
    pub n: Vec3,
    /// Flux it carries (before dividing by the photons emitted).
    pub power: Rgb,
    /// Segments from the light to `p` (1: straight from the light).
    pub segments: u16,
    /// Every scattering before `p` was perfectly specular, and there was one (a caustic
    /// photon: L S+ D).
    pub caustic: bool,
}

/// The settings of the photon-mapping integrators.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotonOptions {
    /// `sppm`: photons emitted per pass (0: one per pixel). `photon`: photons kept in the
    /// global map.
    pub photons: u64,
    /// `photon`: photons kept in the caustic map.
    pub caustic_photons: u64,
    /// `sppm`: the initial gather radius; `photon`: the largest lookup radius of the global
    /// map (a quarter of it for the caustic map). Scene units; 0 chooses (`sppm`: two
    /// pixel footprints at the visible point; `photon`: 5% of the scene's bounding
    /// sphere's diameter).
    pub radius: f32,
    /// `sppm`: the share of a pass's photons a pixel keeps as its radius shrinks
    /// (Hachisuka and Jensen's α).
    pub alpha: f32,
    /// `photon`: photons per density estimate (k nearest).
    pub lookup: u32,
    /// `photon`: final-gathering rays per camera sample.
    pub gather: u32,
}

impl Default for PhotonOptions {
    fn default() -> Self {
        PhotonOptions {
            photons: 0,
            caustic_photons: 100_000,
            radius: 0.0,
            alpha: 2.0 / 3.0,
            lookup: 100,
            gather: 4,
        }
    }
}

impl PhotonOptions {
    /// What is wrong with these settings, if anything.
    pub fn check(&self) -> Result<(), String> {
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(format!("the photon alpha must be in (0, 1], found {}", self.alpha));
        }
        if !(self.radius >= 0.0 && self.radius.is_finite()) {
            return Err(format!(
                "the photon radius must be 0 (automatic) or positive, found {}",
                self.radius
            ));
        }
        if !(1..=100_000).contains(&self.lookup) {
            return Err(format!(
                "the photon lookup size must be from 1 to 100000, found {}",
                self.lookup
            ));
        }
        if !(1..=4096).contains(&self.gather) {
            return Err(format!(
                "the final-gathering rays must be from 1 to 4096, found {}",
                self.gather
            ));
        }
        Ok(())
    }
}

/// Photons traced at once: their paths run in parallel, and the photons they leave are
/// concatenated in emission order.
const CHUNK: u64 = 1024;

/// The photons of emissions from `range.start` on (each photon's random numbers its own
/// stream of `seed`), traced up to `max_segments` segments, that `keep` accepts, in
/// emission order; emission stops at `range.end` or, at the end of a group of chunks, once
/// `limit` photons are kept (a fixed rule: the same for any thread count). Returns them and
/// where emission stopped. At most `limit` plus one group's photons are held, and a group
/// is small enough that even paths of `max_segments` keep that under 2 `limit`.
pub fn trace_photons(
    scene: &Scene,
    options: &IntegratorOptions,
    (seed, range): (u64, std::ops::Range<u64>),
    (max_segments, limit): (usize, usize),
    keep: &(dyn Fn(&Photon) -> bool + Sync),
    counts: &mut RayCounts,
) -> (Vec<Photon>, u64) {
    let group = (limit as u64 / max_segments.max(1) as u64).clamp(CHUNK, 64 * CHUNK);
    let mut photons = Vec::new();
    let mut start = range.start;
    while start < range.end && photons.len() < limit {
        let end = (start + group).min(range.end);
        let traced: Vec<(Vec<Photon>, RayCounts)> = (start..end)
            .step_by(CHUNK as usize)
            .collect::<Vec<u64>>()
            .into_par_iter()
            // One item per job, so no thread idles at the end (see `driver::render_pass`).
            .with_max_len(1)
            .map(|first| {
                let (mut out, mut rays) = (Vec::new(), RayCounts::default());
                for index in first..(first + CHUNK).min(end) {
                    let mut rng = Pcg32::new(seed, index);
                    trace_photon(scene, options, max_segments, &mut rng, keep, &mut out, &mut rays);
                }
                (out, rays)
            })
            .collect();
        for (p, r) in traced {
            photons.extend(p);
            counts.add(&r);
        }
        start = end;
    }
    (photons, start)
}

/// One photon: a light picked by power, an emitted ray, then a random walk scattering
/// importance by the BSDFs (with the shading-normal correction, Veach 1997 eq. 5.19) and
/// Russian roulette from `rr_depth` on.
fn trace_photon(
    scene: &Scene,
    options: &IntegratorOptions,
    max_segments: usize,
    rng: &mut Pcg32,
    keep: &(dyn Fn(&Photon) -> bool + Sync),
    out: &mut Vec<Photon>,
    counts: &mut RayCounts,
) {
    let u2 = |rng: &mut Pcg32| Vec2::new(rng.next_f32(), rng.next_f32());
    let Some((index, pick)) = scene.lights.pick(LightSelection::Power, rng.next_f32()) else {
        return;
    };
    let (u_pos, u_dir) = (u2(rng), u2(rng));
    let Some(e) = scene.lights.lights()[index as usize].sample_le(u_pos, u_dir, scene.sphere) else {
        return;
    };
    let mut beta = e.throughput(pick);
    if !beta.is_finite() || beta.is_black() {
        return;
    }
    let start = beta.max_component();
    let mut ray = e.ray;
    let mut specular_only = true;
    for segments in 1..=max_segments {
        counts.secondary += 1;
        let Some(it) = scene.intersect(&ray, f32::INFINITY) else {
            return;
        };
        let bsdf = it.material.bsdf(it.surface.uv);
        let ng = it.surface.ng;
        let photon = Photon {
            p: it.surface.p,
            wi: it.wo,
            n: if ng.dot(it.wo) < 0.0 { -ng } else { ng },
            power: beta,
            segments: segments.min(u16::MAX as usize) as u16,
            caustic: specular_only && segments >= 2,
        };
        if bsdf.has_smooth() && keep(&photon) {
            out.push(photon);
        }
        if segments == max_segments {
            return;
        }
        let frame = it.material.shading_frame(&it.surface);
        let Some(bs) = bsdf.sample(
            frame.to_local(it.wo),
            rng.next_f32(),
            u2(rng),
            TransportMode::Importance,
        ) else {
            return;
        };
        let wi = frame.to_world(bs.wi);
        if ng.dot(it.wo) * frame.n.dot(it.wo) <= 0.0 || ng.dot(wi) * frame.n.dot(wi) <= 0.0 {
            return;
        }
        beta = beta * bs.weight * shading_correction(ng, frame.n, it.wo, wi);
        specular_only &= bs.delta;
        if segments as u32 >= options.rr_depth {
            let q = (beta.max_component() / start).min(0.95);
            if rng.next_f32() >= q || q.is_nan() {
                return;
            }
            beta = beta * (1.0 / q);
        }
        if !beta.is_finite() || beta.is_black() {
            return;
        }
        ray = Ray::spawn(it.surface.p, ng, wi);
    }
}

/// Where a camera path stops for a density estimate: the surface, its BSDF towards the
/// viewer, and the path's weight and length.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint<'a> {
    pub p: Vec3,
    /// The geometric normal on the viewer's side.
    pub ng: Vec3,
    pub frame: Frame,
    /// Towards the viewer, in the shading frame.
    pub wo: Vec3,
    pub bsdf: Bsdf<'a>,
    /// The path's throughput, divided by the probability of stopping here.
    pub beta: Rgb,
    /// Segments from the camera.
    pub segments: usize,
    /// The path's length from the camera (for a footprint).
    pub distance: f32,
}

/// Photons whose surface normal leans further than this from a visible point's (cosine)
/// are not its surface's: the other wall at a corner.
const SAME_SURFACE_COS: f32 = 0.8;

/// Photons further than this share of the radius off a visible point's tangent plane are
/// not on its surface: a step or the top of a thin box near the point (Jensen 2001,
/// section 7.2.2, the disc).
const DISC_THICKNESS: f32 = 0.25;

impl VisiblePoint<'_> {
    /// Whether `photon` lies on this point's surface, as far as a disc of radius `r` can
    /// tell: its normal close to the point's (either way round), and near the tangent
    /// plane. On a surface smooth at the disc's scale both hold as r shrinks, so the
    /// estimate keeps its limit; they remove most of the light that leaks around corners
    /// at finite radii (faceted meshes lose some light at sharp creases until the radius
    /// is below a facet).
    pub fn same_surface(&self, photon: &Photon, r: f32) -> bool {
        // (Either side: light through a rough dielectric arrives from behind; the BSDF
        // itself gives nothing to photons behind an opaque surface.)
        photon.n.dot(self.ng).abs() >= SAME_SURFACE_COS && (photon.p - self.p).dot(self.ng).abs() <= DISC_THICKNESS * r
    }

    /// What `photon` adds to the radiance leaving towards the viewer, before dividing by
    /// the disc's area and the photons emitted: f(wo, wi) Φ |cos θ_s| / |cos θ_g| (the
    /// flux arrives per unit of geometric area; the BSDF is cosine-weighted by the shading
    /// normal). The path's weight `beta` is not applied.
    pub fn photon_value(&self, photon: &Photon) -> Rgb {
        let l = self.frame.to_local(photon.wi);
        let cos_g = photon.wi.dot(self.ng);
        // The geometric and shading normals must agree on the side (else light leaks).
        if (cos_g > 0.0) != (l.z * self.wo.z > 0.0) || cos_g == 0.0 || l.z == 0.0 {
            return Rgb::BLACK;
        }
        self.bsdf.eval(self.wo, l, TransportMode::Radiance) * photon.power * (l.z.abs() / cos_g.abs())
    }
}

/// What a camera walk found: radiance picked up on the way (emitters and the background
/// seen through delta bounces, direct lighting at smooth surfaces), and where it stopped.
pub struct Walk<'a> {
    pub radiance: Rgb,
    pub point: Option<VisiblePoint<'a>>,
}

/// Follows `ray` (after `segments` segments, with throughput `beta`) through delta bounces
/// to the first surface with a smooth part it stops at. With `lights`, adds the emitters
/// and the background it meets and the direct lighting at each smooth surface (one light
/// sample and one BSDF sample, weighted by the power heuristic, as `path` does); without,
/// only finds the point (a final-gathering ray, whose light the photons bring).
#[allow(clippy::too_many_arguments)]
pub fn walk<'a>(
    scene: &'a Scene,
    mut ray: Ray,
    mut beta: Rgb,
    mut segments: usize,
    options: &IntegratorOptions,
    lights: bool,
    sampler: &mut impl Draws,
    counts: &mut RayCounts,
) -> Walk<'a> {
    let max = options.max_depth as usize;
    let mut out = Walk {
        radiance: Rgb::BLACK,
        point: None,
    };
    let mut distance = 0.0;
    let mut eta_scale = 1.0;
    while segments < max {
        segments += 1;
        let Some(it) = scene.intersect(&ray, f32::INFINITY) else {
            if lights {
                out.radiance += beta * scene.escaped(ray.dir);
            }
            return out;
        };
        distance += it.surface.p.distance(ray.origin);
        if lights {
            out.radiance += beta * scene.emitted(&it);
        }
        let sh = Shading::new(&it);
        let bsdf = it.material.bsdf(it.surface.uv);
        let smooth = bsdf.has_smooth();
        if smooth && lights && segments < max {
            out.radiance += beta * direct(scene, &sh, sampler, counts);
        }
        let rays = bsdf.specular_rays(sh.wo, TransportMode::Radiance);
        counts.specular_overflows += (rays.dropped() > 0.0) as u64;
        let rays = rays.as_slice();
        let delta: f32 = rays.iter().map(|r| r.weight.luminance().max(0.0)).sum();
        let p_smooth = match (smooth, delta > 0.0) {
            (false, _) => 0.0,
            (true, false) => 1.0,
            // The albedo is only a guide (a Phong material's is its diffuse part alone), so
            // each branch keeps at least a fifth: no branch weight above 5.
            (true, true) => {
                let a = bsdf.albedo().luminance().max(0.0);
                (a / (a + delta)).clamp(0.2, 0.8)
            }
        };
        let u = sampler.next_1d();
        if u < p_smooth {
            // Photons must come at least one segment after this one.
            if segments < max {
                out.point = Some(VisiblePoint {
                    p: it.surface.p,
                    ng: sh.ng,
                    frame: sh.frame,
                    wo: sh.wo,
                    bsdf,
                    beta: beta * (1.0 / p_smooth),
                    segments,
                    distance,
                });
            }
            return out;
        }
        if delta <= 0.0 {
            return out;
        }
        // One delta direction, in proportion to its weight's luminance.
        let mut x = (u - p_smooth) / (1.0 - p_smooth) * delta;
        let mut chosen = rays[rays.len() - 1];
        for r in rays {
            let l = r.weight.luminance().max(0.0);
            if x < l {
                chosen = *r;
                break;
            }
            x -= l;
        }
        let q = chosen.weight.luminance().max(0.0) / delta;
        if q <= 0.0 {
            return out;
        }
        let wi = sh.frame.to_world(chosen.wi);
        if !sh.agrees(wi, chosen.wi) {
            return out;
        }
        beta = beta * chosen.weight * (1.0 / (q * (1.0 - p_smooth)));
        if chosen.wi.z * sh.wo.z < 0.0 {
            eta_scale *= bsdf_eta_squared(sh.wo, chosen.wi);
        }
        // Russian roulette, as the path tracer plays it.
        if segments as u32 >= options.rr_depth {
            let survive = (beta.max_component() * eta_scale).min(0.95);
            if sampler.next_1d() >= survive || survive.is_nan() {
                return out;
            }
            beta = beta * (1.0 / survive);
        }
        counts.secondary += 1;
        ray = Ray::new(sh.origin_towards(wi), wi);
    }
    out
}

/// η² of a refraction from `wo` to `wi` (shading frame), from Snell's law: the factor by
/// which radiance was scaled, undone for roulette.
fn bsdf_eta_squared(wo: Vec3, wi: Vec3) -> f32 {
    let (sin_o, sin_i) = ((1.0 - wo.z * wo.z).max(0.0).sqrt(), (1.0 - wi.z * wi.z).max(0.0).sqrt());
    if sin_i > 0.0 && sin_o > 0.0 {
        let eta = sin_o / sin_i;
        eta * eta
    } else {
        1.0
    }
}

/// Direct lighting at `sh`: a light picked by power and sampled by solid angle, and a
/// BSDF sample that may reach an emitter, weighted by the power heuristic (Veach and
/// Guibas 1995).
pub fn direct(scene: &Scene, sh: &Shading, sampler: &mut impl Draws, counts: &mut RayCounts) -> Rgb {
    let (selection, heuristic) = (LightSelection::Power, MisHeuristic::Power);
    let strategy = LightStrategy {
        sampling: AreaSampling::Adaptive,
        samples: 1.0,
        mis: Some((heuristic, 1.0)),
    };
    let mut radiance = Rgb::BLACK;
    let (u_pick, u_light) = (sampler.next_1d(), sampler.next_2d());
    if let Some((index, p_pick)) = scene.lights.pick(selection, u_pick) {
        if let Some(test) = nee::light_sample(scene, sh, index, p_pick, u_light, &strategy) {
            radiance += test.trace(scene, counts);
        }
    }
    let u = (sampler.next_1d(), sampler.next_2d());
    let mis = nee::BsdfMis {
        selection,
        sampling: strategy.sampling,
        heuristic,
        n_bsdf: 1.0,
        n_light: 1.0,
    };
    radiance + nee::bsdf_light_sample(scene, sh, u, Some(mis), true, counts)
}
