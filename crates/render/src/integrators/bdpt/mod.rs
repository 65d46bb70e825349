//! Bidirectional path tracing (Veach and Guibas 1994; Veach 1997 chapter 10; pbrt-v4
//! section 13.4 as the reading). For each camera sample a camera subpath and a light
//! subpath are traced, and every light prefix of s vertices is joined to every camera
//! prefix of t vertices: s = 0 is the camera path reaching a light by itself; s = 1 a
//! fresh light sample (next-event estimation); t = 1 a fresh point on the lens, the light
//! path seen by the camera (light tracing), whose value is splatted to the pixel it lands
//! in; the rest join two scattering vertices with a shadow ray. Each strategy's value is
//! weighted by multiple importance sampling over all strategies that could make the same
//! path (`mis.rs`). `max_depth` keeps its meaning: at most that many segments per path.
//!
//! Both walks play Russian roulette from `rr_depth` vertices on (the light walk relative
//! to its starting throughput); it scales throughputs only, so the weights stay exact.

mod mis;
mod vertex;

use super::{Integrator, IntegratorOptions, RayCounts, Splat};
use crate::bsdfs::TransportMode;
use crate::interface::Capabilities;
use crate::lights::{AreaSampling, LightSelection};
use crate::Scene;
use glam::Vec3;
use penumbra_core::{Draws, PixelSampler, Ray, Rgb};
pub(super) use vertex::shading_correction;
use vertex::{geometry, sides_agree, unoccluded, Kind, Vertex};

pub struct Bdpt {
    pub options: IntegratorOptions,
}

/// What a walk found besides its vertices: radiance from a background that is not a light
/// (reachable only by the camera path itself).
struct Walk {
    background: Rgb,
}

impl Integrator for Bdpt {
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            splats: true,
            strategy_images: true,
            ..Capabilities::default()
        }
    }

    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        self.sample(scene, ray, sampler, counts, splats, PerLength::default())
    }
}

/// What a bidirectional sample does per path length (segments, from 1).
#[derive(Default)]
pub(crate) struct PerLength<'a> {
    /// Adds the luminance each path length brings to `sums[segments - 1]`.
    pub sums: Option<&'a mut [f64]>,
    /// Only the path lengths marked here contribute (every length when `None`).
    pub only: Option<&'a [bool]>,
}

impl Bdpt {
    /// One bidirectional sample for camera ray `ray`: the radiance of the camera sample,
    /// with light tracing's contributions to other pixels in `splats`; what `lengths`
    /// asks per path length. The numbers come from three streams of `sampler`: the
    /// camera subpath (0), the light subpath (1), the connections (2).
    pub(crate) fn sample(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut impl Draws,
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
        lengths: PerLength<'_>,
    ) -> Rgb {
        let PerLength { mut sums, only } = lengths;
        let kept = |segments: usize| only.is_none_or(|only| only.get(segments - 1).copied().unwrap_or(false));
        let max_depth = self.options.max_depth as usize;
        let mut camera = Vec::with_capacity(max_depth + 1);
        let walk = self.camera_subpath(scene, ray, sampler, max_depth + 1, &mut camera, counts);
        let mut light = Vec::with_capacity(max_depth);
        sampler.start_stream(1);
        self.light_subpath(scene, sampler, max_depth, &mut light, counts);
        sampler.start_stream(2);
        let mut radiance = if kept(camera.len()) {
            walk.background
        } else {
            Rgb::BLACK
        };
        if let Some(l) = sums.as_deref_mut().and_then(|l| l.get_mut(camera.len() - 1)) {
            *l += radiance.luminance() as f64;
        }
        // Where the camera sample lies on the film, for the strategies' own images.
        let own = match (self.options.debug_strategies, scene.camera.image_plane()) {
            (true, Some(plane)) => plane.we(ray.origin, ray.dir).map(|(_, film)| film),
            _ => None,
        };
        for t in 1..=camera.len() {
            // (s = 1 samples a light of its own: it needs no light subpath.)
            for s in 0..=light.len().max(1) {
                let segments = s + t - 1;
                if (s == 1 && t == 1) || segments < 1 || segments > max_depth || !kept(segments) {
                    continue;
                }
                let Some((value, weight, film)) = connect(scene, &light, &camera, s, t, sampler, counts) else {
                    continue;
                };
                match film {
                    Some(film) => splats.push(Splat {
                        film,
                        value: value * weight,
                        layer: 0,
                    }),
                    None => radiance += value * weight,
                }
                if let Some(l) = sums.as_deref_mut() {
                    let y = (value * weight).luminance() as f64;
                    if y.is_finite() {
                        l[segments - 1] += y;
                    }
                }
                if let Some(film) = film.or(own).filter(|_| self.options.debug_strategies) {
                    for (weighted, v) in [(true, value * weight), (false, value)] {
                        let layer = strategy_layer(s, t, weighted);
                        splats.push(Splat { film, value: v, layer });
                    }
                }
            }
        }
        radiance
    }

    /// The value of strategy (s, t) for one path of `segments` segments, the strategy
    /// chosen by the sampler's first number, each of the `segments + 1` equally likely
    /// (Hachisuka et al. 2014's multiplexing, as pbrt's `MLTIntegrator` does it): the
    /// MIS-weighted value over that probability, and the film position it belongs to.
    /// `None` when either subpath falls short or the strategy brings nothing.
    pub(crate) fn strategy_sample(
        &self,
        scene: &Scene,
        segments: usize,
        sampler: &mut impl Draws,
        counts: &mut RayCounts,
    ) -> Option<(Rgb, glam::Vec2)> {
        sampler.start_stream(0);
        let (s, t, n) = if segments == 1 {
            (0, 2, 1)
        } else {
            let n = segments + 1;
            let s = ((sampler.next_1d() * n as f32) as usize).min(n - 1);
            (s, n - s, n)
        };
        let film = sampler.next_2d() * glam::Vec2::new(scene.width as f32, scene.height as f32);
        let u_lens = sampler.next_2d();
        let ray = scene.camera.generate_ray(film, u_lens);
        let mut camera = Vec::with_capacity(t);
        let walk = self.camera_subpath(scene, &ray, sampler, t, &mut camera, counts);
        if camera.len() != t {
            // A camera path that left the scene one vertex short sees a background that is
            // no light: only s = 0 makes such paths.
            let escaped = s == 0 && camera.len() + 1 == t && !walk.background.is_black();
            return escaped.then(|| (walk.background * n as f32, film));
        }
        sampler.start_stream(1);
        let mut light = Vec::with_capacity(s);
        self.light_subpath(scene, sampler, s, &mut light, counts);
        // (s = 1 samples a light of its own: it needs no light subpath.)
        if light.len() != s && s != 1 {
            return None;
        }
        sampler.start_stream(2);
        let (value, weight, at) = connect(scene, &light, &camera, s, t, sampler, counts)?;
        Some((value * (weight * n as f32), at.unwrap_or(film)))
    }

    /// The camera subpath of `ray` of at most `max` vertices: the lens point, then what
    /// the walk meets.
    fn camera_subpath<'a>(
        &self,
        scene: &'a Scene,
        ray: &Ray,
        sampler: &mut impl Draws,
        max: usize,
        path: &mut Vec<Vertex<'a>>,
        counts: &mut RayCounts,
    ) -> Walk {
        let plane = scene.camera.image_plane();
        let normal = plane.map_or(Vec3::ZERO, |p| p.normal());
        let mut v = Vertex::new(scene, Kind::Camera, ray.origin, normal, Rgb::WHITE);
        // A camera no light path can be joined to (orthographic) is a delta vertex; its
        // direction density then never enters a weight.
        v.delta = plane.is_none();
        let pdf_dir = plane.map_or(1.0, |p| p.pdf_we(ray.origin, ray.dir).1);
        path.push(v);
        self.walk(
            scene,
            *ray,
            Rgb::WHITE,
            pdf_dir,
            max,
            TransportMode::Radiance,
            sampler,
            path,
            counts,
        )
    }

    /// The light subpath of at most `max` vertices: a light chosen by power, an emitted
    /// ray, then the walk.
    fn light_subpath<'a>(
        &self,
        scene: &'a Scene,
        sampler: &mut impl Draws,
        max: usize,
        path: &mut Vec<Vertex<'a>>,
        counts: &mut RayCounts,
    ) {
        let (u_pick, u_pos, u_dir) = (sampler.next_1d(), sampler.next_2d(), sampler.next_2d());
        if max == 0 {
            return;
        }
        let Some((index, pick)) = scene.lights.pick(LightSelection::Power, u_pick) else {
            return;
        };
        let light = &scene.lights.lights()[index as usize];
        let Some(e) = light.sample_le(u_pos, u_dir, scene.sphere) else {
            return;
        };
        let mut v = Vertex::new(scene, Kind::Light { index }, e.ray.origin, e.normal, e.le);
        v.pdf_fwd = e.pdf_pos * pick;
        path.push(v);
        let beta = e.throughput(pick);
        counts.secondary += 1;
        self.walk(
            scene,
            e.ray,
            beta,
            e.pdf_dir,
            max,
            TransportMode::Importance,
            sampler,
            path,
            counts,
        );
        if light.is_infinite() {
            // From infinity, the first surface's density is the disk's, projected; the
            // light's own is that of its direction.
            if let Some(first) = path.get_mut(1) {
                first.pdf_fwd = e.pdf_pos
                    * if let Kind::Surface { .. } = first.kind {
                        first.ng.dot(e.ray.dir).abs()
                    } else {
                        1.0
                    };
            }
            path[0].pdf_fwd = pick * light.pdf_from_infinity(e.ray.dir);
        }
    }

    /// Extends `path` (whose last vertex left along `ray` with direction density `pdf_dir`
    /// and throughput `beta`) by a random walk until it holds `max` vertices, leaves the
    /// scene, is absorbed, or loses at roulette.
    #[allow(clippy::too_many_arguments)]
    fn walk<'a>(
        &self,
        scene: &'a Scene,
        mut ray: Ray,
        mut beta: Rgb,
        pdf_dir: f32,
        max: usize,
        mode: TransportMode,
        sampler: &mut impl Draws,
        path: &mut Vec<Vertex<'a>>,
        counts: &mut RayCounts,
    ) -> Walk {
        let mut walk = Walk { background: Rgb::BLACK };
        let mut pdf_fwd = pdf_dir;
        let start = beta.max_component();
        // The product of η² over refractions (radiance only is scaled by them).
        let mut eta_scale = 1.0;
        while path.len() < max {
            let prev = path.len() - 1;
            let Some(it) = scene.intersect(&ray, f32::INFINITY) else {
                if mode == TransportMode::Radiance {
                    match scene.environment() {
                        Some((index, _)) => {
                            let mut v = Vertex::new(scene, Kind::Light { index }, ray.origin + ray.dir, -ray.dir, beta);
                            v.pdf_fwd = pdf_fwd;
                            path.push(v);
                        }
                        None => walk.background = beta * scene.background,
                    }
                }
                break;
            };
            let frame = it.material.shading_frame(&it.surface);
            let bsdf = it.material.bsdf(it.surface.uv);
            let light = scene.emitter_at(&it).map(|(index, _)| index);
            let kind = Kind::Surface {
                bsdf,
                frame,
                wo: it.wo,
                light,
            };
            let mut v = Vertex::new(scene, kind, it.surface.p, it.surface.ng, beta);
            v.pdf_fwd = path[prev].convert_density(pdf_fwd, &v);
            path.push(v);
            if path.len() >= max {
                break;
            }
            let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
            let wo = frame.to_local(it.wo);
            let Some(bs) = bsdf.sample(wo, u_lobe, u, mode) else {
                break;
            };
            let wi = frame.to_world(bs.wi);
            if !(sides_agree(v.ng, frame.n, it.wo) && sides_agree(v.ng, frame.n, wi)) {
                break;
            }
            beta *= bs.weight;
            match mode {
                TransportMode::Radiance => eta_scale *= bs.eta * bs.eta,
                TransportMode::Importance => beta = beta * vertex::shading_correction(v.ng, frame.n, it.wo, wi),
            }
            let reverse = match mode {
                TransportMode::Radiance => TransportMode::Importance,
                TransportMode::Importance => TransportMode::Radiance,
            };
            let mut pdf_rev = bsdf.pdf(bs.wi, wo, reverse);
            pdf_fwd = bs.pdf;
            let last = path.len() - 1;
            if bs.delta {
                path[last].delta = true;
                (pdf_fwd, pdf_rev) = (0.0, 0.0);
            }
            let rev = path[last].convert_density(pdf_rev, &path[prev]);
            path[prev].pdf_rev = rev;
            // Russian roulette, as the path tracer plays it (η² undone on the camera side).
            if path.len() as u32 >= self.options.rr_depth {
                let q = (beta.max_component() / start * eta_scale).min(0.95);
                if sampler.next_1d() >= q {
                    break;
                }
                beta = beta / q;
            }
            counts.secondary += 1;
            ray = Ray::spawn(it.surface.p, it.surface.ng, wi);
        }
        walk
    }
}

/// The film layer of strategy (s, t)'s own image, weighted by MIS or not (pbrt's
/// `visualizestrategies` and `visualizeweights`): 1 + 2 (256 s + t) + weighted.
pub fn strategy_layer(s: usize, t: usize, weighted: bool) -> u32 {
    1 + 2 * (256 * s as u32 + t as u32) + weighted as u32
}

/// The unweighted value of strategy (s, t), its MIS weight and, for light tracing (t = 1),
/// the film position it is splatted at; `None` when it brings nothing.
fn connect(
    scene: &Scene,
    light: &[Vertex],
    camera: &[Vertex],
    s: usize,
    t: usize,
    sampler: &mut impl Draws,
    counts: &mut RayCounts,
) -> Option<(Rgb, f32, Option<glam::Vec2>)> {
    let pt = &camera[t - 1];
    // A camera path that left the scene ends at infinity: only s = 0 uses it.
    if t > 1 && s != 0 && matches!(pt.kind, Kind::Light { .. }) {
        return None;
    }
    let mut sampled = None;
    let mut film = None;
    let value = if s == 0 {
        pt.le(scene, &camera[t - 2]) * pt.beta
    } else if t == 1 {
        let qs = &light[s - 1];
        if !qs.is_connectible(scene) {
            return None;
        }
        let plane = scene.camera.image_plane()?;
        let cs = plane.sample_wi(qs.p, sampler.next_2d())?;
        let mut v = Vertex::new(
            scene,
            Kind::Camera,
            cs.point,
            plane.normal(),
            Rgb::splat(cs.we / cs.pdf),
        );
        v.pdf_fwd = 0.0;
        let l = qs.beta * qs.f(&v, TransportMode::Importance) * v.beta * qs.ns().dot(cs.wi).abs();
        if l.is_black() {
            return None;
        }
        counts.shadow += 1;
        if !unoccluded(scene, qs, &v) {
            return None;
        }
        film = Some(cs.film);
        sampled = Some(v);
        l
    } else if s == 1 {
        if !pt.is_connectible(scene) {
            return None;
        }
        let (u_pick, u) = (sampler.next_1d(), sampler.next_2d());
        let (index, pick) = scene.lights.pick(LightSelection::Power, u_pick)?;
        let light_ref = &scene.lights.lights()[index as usize];
        let ls = light_ref.sample_li(pt.p, u, AreaSampling::Adaptive)?;
        if ls.li.is_black() || ls.pdf <= 0.0 {
            return None;
        }
        let (p, ng) = if ls.dist.is_finite() {
            let p = pt.p + ls.wi * ls.dist;
            (p, light_ref.surface_normal(p).unwrap_or(Vec3::ZERO))
        } else {
            (pt.p + ls.wi, -ls.wi)
        };
        let mut v = Vertex::new(scene, Kind::Light { index }, p, ng, ls.li / (pick * ls.pdf));
        v.pdf_fwd = v.pdf_light_origin(scene, pt);
        let l = pt.beta * pt.f(&v, TransportMode::Radiance) * v.beta * pt.ns().dot(ls.wi).abs();
        if l.is_black() {
            return None;
        }
        counts.shadow += 1;
        if !unoccluded(scene, pt, &v) {
            return None;
        }
        sampled = Some(v);
        l
    } else {
        let qs = &light[s - 1];
        if !(qs.is_connectible(scene) && pt.is_connectible(scene)) {
            return None;
        }
        let l = qs.beta * qs.f(pt, TransportMode::Importance) * pt.f(qs, TransportMode::Radiance) * pt.beta;
        if l.is_black() {
            return None;
        }
        let g = geometry(qs, pt);
        counts.shadow += 1;
        if g == 0.0 || !unoccluded(scene, qs, pt) {
            return None;
        }
        l * g
    };
    if value.is_black() {
        return None;
    }
    let w = mis::weight(scene, light, camera, sampled.as_ref(), s, t);
    Some((value, w, film))
}
