//! Whitted's recursive ray tracer (Whitted 1980, "An Improved Illumination Model for Shaded
//! Display"), as the course teaches it: at each hit, local diffuse + Phong shading from
//! every light gated by a binary shadow ray, plus recursively traced mirror reflection and
//! Fresnel-weighted refraction. Recursion stops at `max_depth` bounces or when a ray's
//! accumulated weight falls below `min_weight`. Area lights shine as a point light at the
//! centre of each (of each triangle, for a mesh), and are seen directly with their radiance.

use super::nee::{self, LightStrategy, Shading};
use super::{specular_bounces, Integrator, IntegratorOptions, RayCounts, Splat};
use crate::lights::AreaSampling;
use crate::Scene;
use glam::Vec2;
use penumbra_core::{PixelSampler, Ray, Rgb};

pub struct Whitted {
    pub options: IntegratorOptions,
}

impl Integrator for Whitted {
    fn li(&self, scene: &Scene, ray: &Ray, _: &mut PixelSampler, counts: &mut RayCounts, _: &mut Vec<Splat>) -> Rgb {
        self.trace(scene, ray, 0, Rgb::WHITE, counts)
    }
}

impl Whitted {
    /// Radiance along `ray`, which carries the accumulated weight `beta` and is `depth`
    /// bounces from the camera.
    fn trace(&self, scene: &Scene, ray: &Ray, depth: u32, beta: Rgb, counts: &mut RayCounts) -> Rgb {
        let Some(it) = scene.intersect(ray, f32::INFINITY) else {
            return scene.escaped(ray.dir);
        };
        // Local shading sees the side of the surface the ray arrived on; lights are seen
        // from the point pushed off it on that side.
        let sh = Shading::new(&it);
        // One shadow ray per light; an area light shines from one point (its centre), as a
        // point light of intensity L A cos θ_light: the sample divided by its density.
        let centre = LightStrategy {
            sampling: AreaSampling::SolidAngle,
            samples: 1.0,
            mis: None,
        };
        let mut radiance = scene.emitted(&it) + scene.ambient * sh.bsdf.albedo();
        // (The environment is seen through the rays that leave the scene only.)
        for index in (0..scene.lights.len() as u32).filter(|&i| Some(i) != scene.environment) {
            radiance += nee::light_sample(scene, &sh, index, 1.0, Vec2::splat(0.5), &centre)
                .map_or(Rgb::BLACK, |t| t.trace(scene, counts));
        }

        radiance
            + specular_bounces(&self.options, &sh, depth, beta, counts, |next, weight, counts| {
                self.trace(scene, next, depth + 1, weight, counts)
            })
    }
}
