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

use super::nee::{self, LightStrategy, Shading};
use super::{Integrator, IntegratorOptions, MisHeuristic, RayCounts};
use crate::bsdfs::TransportMode;
use crate::lights::{AreaSampling, LightSelection};
use crate::Scene;
use penumbra_core::{PixelSampler, Ray, Rgb};

/// The depth (path segments) from which Russian roulette may end paths, as in Mitsuba.
pub const RR_DEPTH: u32 = 5;

pub struct PathTracer {
    pub options: IntegratorOptions,
}

impl Integrator for PathTracer {
    fn li(&self, scene: &Scene, camera_ray: &Ray, sampler: &mut PixelSampler, counts: &mut RayCounts) -> Rgb {
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
        let mut radiance = Rgb::BLACK;
        let mut beta = Rgb::WHITE;
        let mut ray = *camera_ray;
        // The vertex the ray left and the BSDF density of its direction; `None` after the
        // camera or a perfectly specular bounce (nothing else could have sampled it).
        let mut previous: Option<(glam::Vec3, f32)> = None;
        // The product of η² over the refractions so far.
        let mut eta_scale = 1.0f32;
        for depth in 0.. {
            let Some(it) = scene.intersect(&ray, f32::INFINITY) else {
                // The environment, weighted against its light sampling as an emitter is.
                radiance += beta
                    * match scene.environment() {
                        Some(env) => {
                            let weight = previous.map_or(1.0, |(_, p_bsdf)| {
                                let mis = (selection, heuristic);
                                nee::environment_weight(scene, mis, env, ray.dir, (1.0, p_bsdf), 1.0)
                            });
                            env.1.le(ray.dir) * weight
                        }
                        None => scene.background,
                    };
                break;
            };
            if let Some((index, light)) = scene.emitter_at(&it) {
                let normal = light.emitter.normal_at(it.surface.p);
                let le = light.le(normal, it.wo);
                if !le.is_black() {
                    let weight = previous.map_or(1.0, |(p, p_bsdf)| {
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
                    radiance += beta * le * weight;
                }
            }
            // One more segment would exceed the maximum path length.
            if depth + 1 >= self.options.max_depth {
                break;
            }

            let sh = Shading::new(&it);
            if sh.bsdf.has_smooth() {
                let u_pick = sampler.next_1d();
                let u = sampler.next_2d();
                if let Some((index, p_pick)) = scene.lights.pick(selection, u_pick) {
                    radiance += beta * nee::light_sample(scene, &sh, index, p_pick, u, &nee, counts);
                }
            }

            // The continuation, drawn from the whole BSDF (delta lobes included).
            let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
            let Some(bs) = sh.bsdf.sample(sh.wo, u_lobe, u, TransportMode::Radiance) else {
                break;
            };
            let wi = sh.frame.to_world(bs.wi);
            if !sh.agrees(wi, bs.wi) {
                break;
            }
            beta *= bs.weight;
            eta_scale *= bs.eta * bs.eta;
            counts.secondary += 1;
            ray = Ray::new(sh.origin_towards(wi), wi);
            previous = (!bs.delta).then_some((ray.origin, bs.pdf));

            if depth + 1 >= RR_DEPTH {
                // Survival by the throughput with refraction's 1/η² undone (as Mitsuba and
                // pbrt-v4), so that paths inside glass are not cut for their scaling alone.
                let q = (beta.max_component() * eta_scale).min(0.95);
                if sampler.next_1d() >= q {
                    break;
                }
                beta = beta / q;
            }
        }
        radiance
    }
}
