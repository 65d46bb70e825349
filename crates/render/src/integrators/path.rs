//! Unidirectional path tracing of the rendering equation (Kajiya 1986), as pbrt-v4's
//! `PathIntegrator` and Mitsuba 3's `path` do it: one random continuation per bounce drawn
//! from the material, next-event estimation at every non-specular vertex (one shadow ray to
//! a light picked by power, solid-angle sampled unless it is a small flat light), emitters reached by the continuation rays
//! weighted against it by the power heuristic (Veach and Guibas 1995), and Russian roulette
//! from `rr_depth` on with survival probability min(max throughput channel, 0.95).
//!
//! `max_depth` has Mitsuba's meaning: the largest number of path segments, so 1 shows the
//! emitters only, 2 gives direct lighting, and each further unit one more bounce.

use super::nee::{self, LightStrategy, Shading};
use super::{Integrator, IntegratorOptions, MisHeuristic, RayCounts};
use crate::lights::AreaSampling;
use crate::materials::{Material, SpecularRay};
use crate::Scene;
use penumbra_core::{PixelSampler, Ray, Rgb};

/// The depth (path segments) from which Russian roulette may end paths, as in Mitsuba.
pub const RR_DEPTH: u32 = 5;

pub struct PathTracer {
    pub options: IntegratorOptions,
}

impl Integrator for PathTracer {
    fn li(&self, scene: &Scene, camera_ray: &Ray, sampler: &mut PixelSampler, counts: &mut RayCounts) -> Rgb {
        let selection = self.options.direct.selection;
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
        for depth in 0.. {
            let Some(it) = scene.intersect(&ray, f32::INFINITY) else {
                radiance += beta * scene.background;
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

            // Choose the continuation: the diffuse + glossy lobes or one perfectly specular
            // ray, in proportion to their albedos (luminance).
            let Material::Phong(m) = it.material;
            let s = &it.surface;
            // At most three specular rays (mirror, Fresnel reflection and refraction): kept
            // on the stack.
            let mut specular = [SpecularRay::default(); 3];
            let mut count = 0;
            for r in m.specular_rays(s.ns, it.wo) {
                specular[count] = r;
                count += 1;
            }
            let specular = &specular[..count];
            let lobe_albedo = if m.has_lobes(s.uv) {
                (m.albedo(s.uv) + m.specular).luminance().max(1e-6)
            } else {
                0.0
            };
            let total = lobe_albedo + specular.iter().map(|r| r.weight.luminance()).sum::<f32>();
            if total <= 0.0 {
                break;
            }
            let sh = Shading::new(&it, lobe_albedo / total);

            if lobe_albedo > 0.0 {
                let u_pick = sampler.next_1d();
                let u = sampler.next_2d();
                if let Some((index, p_pick)) = scene.lights.pick(selection, u_pick) {
                    radiance += beta * nee::light_sample(scene, &sh, index, p_pick, u, &nee, counts);
                }
            }

            let u_choice = sampler.next_1d() * total;
            let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
            let next = if u_choice < lobe_albedo {
                let Some(wi) = m.sample(s.uv, sh.n, it.wo, u_lobe, u) else {
                    break;
                };
                let pdf = sh.bsdf_pdf(wi);
                if pdf.is_nan() || pdf <= 0.0 || sh.ng.dot(wi) <= 0.0 {
                    break;
                }
                beta *= sh.eval(wi) * (sh.n.dot(wi) / pdf);
                previous = Some((sh.origin, pdf));
                wi
            } else {
                // The specular ray whose share of the albedo holds u_choice (rounding may
                // leave u_choice at the very end: then the last ray with a share).
                let mut rest = u_choice - lobe_albedo;
                let mut chosen = specular.iter().filter(|r| r.weight.luminance() > 0.0);
                let Some(r) = chosen
                    .clone()
                    .find(|r| {
                        rest -= r.weight.luminance();
                        rest < 0.0
                    })
                    .or_else(|| chosen.next_back())
                else {
                    break;
                };
                beta *= r.weight * (total / r.weight.luminance());
                previous = None;
                r.wi
            };
            counts.secondary += 1;
            ray = Ray::spawn(s.p, s.ng, next);

            if depth + 1 >= RR_DEPTH {
                let q = beta.max_component().min(0.95);
                if sampler.next_1d() >= q {
                    break;
                }
                beta = beta / q;
            }
        }
        radiance
    }
}
