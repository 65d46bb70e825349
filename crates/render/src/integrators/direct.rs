//! Monte Carlo direct lighting: the light reflected from every light, with no indirect
//! bounces except through perfect mirrors and glass (as in [`super::Whitted`]). The
//! reflected radiance at a point is the integral over the lights of
//! f(wo, wi) L cos θ / pdf, estimated with the strategy [`LightSampling`] names:
//!
//! - `grid`: k x k fixed points on each light (the course's grid of point lights), the
//!   estimator (A / k²) Σ f L V cos θ cos θ_l / |p - q|²; the same points in every pixel.
//! - `uniform`: points uniform by area; `stratified`: jittered in k x k strata of the light;
//!   `solid-angle`: uniform in the solid angle the light subtends (cone, spherical
//!   triangle and rectangle; see [`crate::lights::emitter`]).
//! - `bsdf`: directions drawn from the BSDF, counting the light their ray reaches.
//! - `mis`: solid-angle light samples and BSDF samples combined by the balance or power
//!   heuristic (Veach and Guibas 1995, "Optimally Combining Sampling Techniques for Monte
//!   Carlo Rendering", eq. 9 and 10, with sample counts).
//!
//! Each pixel sample takes `light_samples` shadow rays (and, for `bsdf` and `mis`, as many
//! BSDF rays): for every light object with [`LightSelection::All`], else in total, each for
//! a light picked by power or uniformly. Delta lights (point, spot, directional) can only be
//! reached by light sampling: every strategy samples them, once per selection.

use super::nee::{self, LightStrategy, Shading};
use super::{specular_bounces, Integrator, IntegratorOptions, MisHeuristic, RayCounts, Splat};
use crate::lights::{AreaSampling, LightSelection};
use crate::Scene;
use glam::Vec2;
use penumbra_core::{PixelSampler, Ray, Rgb};

/// How the direct-lighting integral over each light is estimated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSampling {
    Grid,
    Uniform,
    Stratified,
    SolidAngle,
    Bsdf,
    #[default]
    Mis,
}

impl LightSampling {
    pub const NAMES: [&'static str; 6] = ["mis", "grid", "uniform", "stratified", "solid-angle", "bsdf"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "grid" => Some(LightSampling::Grid),
            "uniform" => Some(LightSampling::Uniform),
            "stratified" => Some(LightSampling::Stratified),
            "solid-angle" => Some(LightSampling::SolidAngle),
            "bsdf" => Some(LightSampling::Bsdf),
            "mis" => Some(LightSampling::Mis),
            _ => None,
        }
    }

    /// How points on area lights are drawn, or `None` if area lights are not light-sampled.
    fn area_sampling(self) -> Option<AreaSampling> {
        match self {
            LightSampling::Grid | LightSampling::Uniform | LightSampling::Stratified => Some(AreaSampling::Area),
            LightSampling::SolidAngle | LightSampling::Mis => Some(AreaSampling::SolidAngle),
            LightSampling::Bsdf => None,
        }
    }
}

/// The direct-lighting settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DirectOptions {
    pub sampling: LightSampling,
    /// Shadow rays per light (per light object with `All`, else in total) per pixel sample;
    /// at least 1, a square for `grid`.
    pub light_samples: u32,
    pub heuristic: MisHeuristic,
    pub selection: LightSelection,
}

impl Default for DirectOptions {
    fn default() -> Self {
        DirectOptions {
            sampling: LightSampling::default(),
            light_samples: 1,
            heuristic: MisHeuristic::default(),
            selection: LightSelection::default(),
        }
    }
}

impl DirectOptions {
    /// What is wrong with these settings, if anything.
    pub fn check(&self) -> Result<(), String> {
        let n = self.light_samples;
        if n == 0 {
            return Err("`light_samples` must be at least 1".into());
        }
        if self.sampling == LightSampling::Grid && n.isqrt() * n.isqrt() != n {
            return Err(format!(
                "`grid` light sampling takes a square number of light samples (k x k points), found {n}; e.g. 1, 4, 9, 16"
            ));
        }
        Ok(())
    }
}

pub struct Direct {
    pub options: IntegratorOptions,
}

impl Integrator for Direct {
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        _: &mut Vec<Splat>,
    ) -> Rgb {
        self.trace(scene, ray, 0, Rgb::WHITE, sampler, counts)
    }
}

impl Direct {
    fn trace(
        &self,
        scene: &Scene,
        ray: &Ray,
        depth: u32,
        beta: Rgb,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> Rgb {
        let Some(it) = scene.intersect(ray, f32::INFINITY) else {
            return scene.escaped(ray.dir);
        };
        let sh = Shading::new(&it);
        let mut radiance = scene.emitted(&it) + scene.ambient * sh.bsdf.albedo();
        if sh.bsdf.has_smooth() {
            radiance += self.direct(scene, &sh, sampler, counts);
        }
        radiance
            + specular_bounces(&self.options, &sh, depth, beta, counts, |next, weight, counts| {
                self.trace(scene, next, depth + 1, weight, sampler, counts)
            })
    }

    /// The estimate of reflected direct light at `sh`.
    fn direct(&self, scene: &Scene, sh: &Shading, sampler: &mut PixelSampler, counts: &mut RayCounts) -> Rgb {
        let o = &self.options.direct;
        // (Settings from the library API skip `DirectOptions::check`: stay safe anyway.)
        let n = o.light_samples.max(1);
        let lights = &scene.lights;
        let mut sum = Rgb::BLACK;
        match (o.sampling, o.selection) {
            (LightSampling::Grid, _) => {
                // Every light (every triangle of a mesh light) with the same k x k points.
                let k = n.isqrt();
                for (index, light) in lights.lights().iter().enumerate() {
                    let points = if light.is_delta() { 1 } else { k * k };
                    for j in 0..points {
                        let u = Vec2::new((j % k) as f32 + 0.5, (j / k) as f32 + 0.5) / k as f32;
                        sum += self.light_sample(scene, sh, index as u32, 1.0, u, points, counts);
                    }
                }
            }
            (LightSampling::Bsdf, _) => {
                for (index, light) in lights.lights().iter().enumerate() {
                    if light.is_delta() {
                        sum += self.light_sample(scene, sh, index as u32, 1.0, Vec2::ZERO, 1, counts);
                    }
                }
            }
            (_, LightSelection::All) => {
                for group in 0..lights.groups() {
                    let first = lights.group_lights(group).start as usize;
                    let batch = if lights.lights()[first].is_delta() { 1 } else { n };
                    for j in 0..batch {
                        let u_pick = sampler.next_1d();
                        let u = self.point_sample(j, sampler);
                        if let Some((index, p_pick)) = lights.pick_in_group(group, u_pick) {
                            sum += self.light_sample(scene, sh, index, p_pick, u, batch, counts);
                        }
                    }
                }
            }
            (_, selection) => {
                for j in 0..n {
                    let u_pick = sampler.next_1d();
                    let u = self.point_sample(j, sampler);
                    if let Some((index, p_pick)) = lights.pick(selection, u_pick) {
                        sum += self.light_sample(scene, sh, index, p_pick, u, n, counts);
                    }
                }
            }
        }
        if matches!(o.sampling, LightSampling::Bsdf | LightSampling::Mis) {
            for _ in 0..n {
                sum += self.bsdf_sample(scene, sh, n, sampler, counts);
            }
        }
        sum
    }

    /// The 2D sample for point `j` of a batch: jittered in its stratum for `stratified`.
    fn point_sample(&self, j: u32, sampler: &mut PixelSampler) -> Vec2 {
        let u = sampler.next_2d();
        let o = &self.options.direct;
        if o.sampling != LightSampling::Stratified {
            return u;
        }
        // nx x ny strata, nx the largest divisor of n not above its square root.
        let n = o.light_samples.max(1);
        let nx = (1..=n.isqrt()).rev().find(|d| n.is_multiple_of(*d)).unwrap_or(1);
        let ny = n / nx;
        Vec2::new(((j % nx) as f32 + u.x) / nx as f32, ((j / nx) as f32 + u.y) / ny as f32)
    }

    /// One light-sampling estimate for light `index`, picked with probability `p_pick`, from
    /// a batch of `batch` samples of it: f L cos θ V / (p_pick pdf batch), MIS-weighted
    /// against BSDF sampling in `mis` mode.
    #[allow(clippy::too_many_arguments)]
    fn light_sample(
        &self,
        scene: &Scene,
        sh: &Shading,
        index: u32,
        p_pick: f32,
        u: Vec2,
        batch: u32,
        counts: &mut RayCounts,
    ) -> Rgb {
        let o = &self.options.direct;
        let strategy = LightStrategy {
            sampling: o.sampling.area_sampling().unwrap_or(AreaSampling::Area),
            samples: batch as f32,
            mis: (o.sampling == LightSampling::Mis).then_some((o.heuristic, o.light_samples.max(1) as f32)),
        };
        nee::light_sample(scene, sh, index, p_pick, u, &strategy).map_or(Rgb::BLACK, |t| t.trace(scene, counts))
    }

    /// One BSDF-sampling estimate: a direction from the BSDF and the light its ray
    /// reaches, if any, MIS-weighted against light sampling in `mis` mode.
    fn bsdf_sample(
        &self,
        scene: &Scene,
        sh: &Shading,
        n: u32,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> Rgb {
        let o = &self.options.direct;
        let u = (sampler.next_1d(), sampler.next_2d());
        let n = n as f32;
        let mis = (o.sampling == LightSampling::Mis).then_some(nee::BsdfMis {
            selection: o.selection,
            sampling: AreaSampling::SolidAngle,
            heuristic: o.heuristic,
            n_bsdf: n,
            n_light: n,
        });
        nee::bsdf_light_sample(scene, sh, u, mis, false, counts) * (1.0 / n)
    }
}
