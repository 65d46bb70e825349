//! A diffuse area light: an [`Emitter`] surface that emits constant radiance from its front
//! side (or both sides), seen by the camera and sampled by the integrators.
//!
//! Native format: `emission = [r, g, b]` (radiance) and optionally `two_sided = true` on a
//! quad, disk, sphere or mesh shape; a mesh emits from every triangle (one light each,
//! grouped as one light for selection).

use super::emitter::{Emitter, EmitterSample};
use super::LightSample;
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;
use std::f32::consts::PI;

/// How a point on an area light is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AreaSampling {
    /// Uniformly by area.
    Area,
    /// Uniformly by the solid angle the light subtends, where the shape allows it.
    SolidAngle,
    /// By solid angle, except flat lights that look small from the shading point, by area
    /// (the path tracer's choice: nearly as good there, and much cheaper).
    Adaptive,
}

#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    pub emitter: Emitter,
    pub radiance: Rgb,
    pub two_sided: bool,
}

impl AreaLight {
    /// Radiance leaving the point of normal `normal` in direction `w`.
    pub fn le(&self, normal: Vec3, w: Vec3) -> Rgb {
        if self.two_sided || normal.dot(w) > 0.0 {
            self.radiance
        } else {
            Rgb::BLACK
        }
    }

    /// Light arriving at `p` from a point chosen by `strategy` from `u`.
    pub fn sample_li(&self, p: Vec3, u: Vec2, strategy: AreaSampling) -> Option<LightSample> {
        let s = match self.resolve(p, strategy) {
            AreaSampling::Area => self.emitter.sample_uniform(p, u),
            _ => self.emitter.sample_solid_angle(p, u),
        }?;
        self.to_light_sample(p, &s)
    }

    fn to_light_sample(&self, p: Vec3, s: &EmitterSample) -> Option<LightSample> {
        let d = s.point - p;
        let dist = d.length();
        if !(dist > 0.0 && dist.is_finite() && s.pdf.is_finite() && s.pdf > 0.0) {
            return None;
        }
        let wi = d / dist;
        Some(LightSample {
            wi,
            li: self.le(s.normal, -wi),
            dist,
            pdf: s.pdf,
            delta: false,
        })
    }

    /// The solid-angle density `strategy` gives the direction from `p` to `point` (a point
    /// of this light with normal `normal`).
    pub fn pdf(&self, p: Vec3, point: Vec3, normal: Vec3, strategy: AreaSampling) -> f32 {
        match self.resolve(p, strategy) {
            AreaSampling::Area => self.emitter.area_pdf_to_solid_angle(p, point, normal).unwrap_or(0.0),
            _ => self.emitter.solid_angle_pdf(p, point, normal),
        }
    }

    /// What `strategy` means at `p`: `Adaptive` becomes area or solid angle.
    fn resolve(&self, p: Vec3, strategy: AreaSampling) -> AreaSampling {
        match strategy {
            AreaSampling::Adaptive if self.emitter.looks_small(p) => AreaSampling::Area,
            AreaSampling::Adaptive => AreaSampling::SolidAngle,
            s => s,
        }
    }

    /// Emitted power (luminance): π L A per emitting side.
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        sides * PI * self.emitter.area() * self.radiance.luminance()
    }
}
