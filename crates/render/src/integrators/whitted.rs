//! Whitted's recursive ray tracer (Whitted 1980, "An Improved Illumination Model for Shaded
//! Display"), as the course teaches it: at each hit, local diffuse + Phong shading from
//! every light gated by a binary shadow ray, plus recursively traced mirror reflection and
//! Fresnel-weighted refraction. Recursion stops at `max_depth` bounces or when a ray's
//! accumulated weight falls below `min_weight`.

use super::{Integrator, IntegratorOptions, RayCounts};
use crate::materials::Material;
use crate::Scene;
use glam::Vec2;
use penumbra_core::ray::SHADOW_EPSILON;
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

        let mut radiance = scene.ambient * m.albedo(s.uv);
        for light in &scene.lights {
            let Some(ls) = light.sample_li(s.p, Vec2::ZERO) else {
                continue;
            };
            let cos = n.dot(ls.wi);
            if cos <= 0.0 || ng.dot(ls.wi) <= 0.0 {
                continue;
            }
            let f = m.eval(s.uv, n, wo, ls.wi);
            if f.is_black() {
                continue;
            }
            counts.shadow += 1;
            let shadow = Ray::spawn(s.p, s.ng, ls.wi);
            if !scene.occluded(&shadow, ls.dist * (1.0 - SHADOW_EPSILON)) {
                radiance += f * ls.li * cos;
            }
        }

        if depth < self.options.max_depth {
            for r in m.specular_rays(s.ns, wo) {
                let weight = beta * r.weight;
                if weight.max_component() < self.options.min_weight {
                    continue;
                }
                counts.secondary += 1;
                let next = Ray::spawn(s.p, s.ng, r.wi);
                radiance += r.weight * self.trace(scene, &next, depth + 1, weight, counts);
            }
        }
        radiance
    }
}
