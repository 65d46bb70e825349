//! Whitted's recursive ray tracer (Whitted 1980, "An Improved Illumination Model for Shaded
//! Display"), as the course teaches it: at each hit, local diffuse + Phong shading from
//! every light gated by a binary shadow ray, plus recursively traced mirror reflection and
//! Fresnel-weighted refraction. Recursion stops at `max_depth` bounces or when a ray's
//! accumulated weight falls below `min_weight`. Area lights shine as a point light at the
//! centre of each (of each triangle, for a mesh), and are seen directly with their radiance.

use super::{shadow_ray, specular_bounces, Integrator, IntegratorOptions, RayCounts};
use crate::lights::AreaSampling;
use crate::materials::Material;
use crate::Scene;
use glam::Vec2;
use penumbra_core::ray::offset_origin;
use penumbra_core::{PixelSampler, Ray, Rgb};

pub struct Whitted {
    pub options: IntegratorOptions,
}

impl Integrator for Whitted {
    fn li(&self, scene: &Scene, ray: &Ray, _sampler: &mut PixelSampler, counts: &mut RayCounts) -> Rgb {
        self.trace(scene, ray, 0, Rgb::WHITE, counts)
    }
}

impl Whitted {
    /// Radiance along `ray`, which carries the accumulated weight `beta` and is `depth`
    /// bounces from the camera.
    fn trace(&self, scene: &Scene, ray: &Ray, depth: u32, beta: Rgb, counts: &mut RayCounts) -> Rgb {
        let Some(it) = scene.intersect(ray, f32::INFINITY) else {
            return scene.background;
        };
        let Material::Phong(m) = it.material;
        let s = &it.surface;
        let wo = it.wo;
        // Local shading sees the side of the surface the ray arrived on.
        let n = if s.ns.dot(wo) < 0.0 { -s.ns } else { s.ns };
        let ng = if s.ng.dot(wo) < 0.0 { -s.ng } else { s.ng };

        // Lights are seen from the point pushed off the surface on the viewer's side.
        let origin = offset_origin(s.p, ng);
        let mut radiance = scene.emitted(&it) + scene.ambient * m.albedo(s.uv);
        for light in scene.lights.lights() {
            let Some(ls) = light.sample_li(origin, Vec2::splat(0.5), AreaSampling::SolidAngle) else {
                continue;
            };
            let cos = n.dot(ls.wi);
            if cos <= 0.0 || ng.dot(ls.wi) <= 0.0 || ls.li.is_black() {
                continue;
            }
            let f = m.eval(s.uv, n, wo, ls.wi);
            if f.is_black() {
                continue;
            }
            counts.shadow += 1;
            let (shadow, t_max) = shadow_ray(origin, &ls);
            if !scene.occluded(&shadow, t_max) {
                // An area light's sample is a point on it: divide by its density, as a
                // point light of intensity L A cos θ_light.
                radiance += f * ls.li * (cos / ls.pdf);
            }
        }

        radiance
            + specular_bounces(&self.options, m, s, wo, depth, beta, counts, |next, weight, counts| {
                self.trace(scene, next, depth + 1, weight, counts)
            })
    }
}
