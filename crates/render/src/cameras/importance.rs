//! The perspective camera seen as a sensor, for paths that reach it from the lights
//! (bidirectional path tracing's light tracing, Veach 1997 section 10.2; pbrt-v4 section
//! 5.4's `We`, `PDF_We` and `SampleWi`).
//!
//! Everything is in world space, so that a camera transform with a mirror or a scale is
//! handled as it is in ray generation. The image plane at camera-space depth 1 is the
//! parallelogram `eye + c + a hx + b hy`, a, b in [-1, 1] (ndc x = a, ndc y = -b), at
//! distance `h` from the eye along its unit normal `n`. A uniform film position gives a
//! direction of density h² / (A cos³θ) (A the plane's area, θ the angle to `n`), the same
//! for a pinhole and for any point of a thin lens (the plane of focus is the image plane
//! scaled by the focus distance). The importance is that density over cos θ and the lens
//! area: We = h² / (A A_lens cos⁴θ), normalised over the whole film, so that one light path
//! per camera sample splatted to its pixel estimates the pixel's value (see `film.rs`).

use glam::{Vec2, Vec3};
use penumbra_core::{warp, Transform};
use std::f32::consts::PI;

/// The world-space geometry of a perspective camera's film and lens.
#[derive(Clone, Debug, PartialEq)]
pub struct ImagePlane {
    eye: Vec3,
    /// The lens axes (camera x and y in the world), which the lens disk is spanned by.
    lens_x: Vec3,
    lens_y: Vec3,
    /// Unit normal of the film and lens, towards the scene.
    n: Vec3,
    /// The image plane's centre relative to the eye, and its distance along `n`.
    c: Vec3,
    h: f32,
    /// The dual basis of (hx, hy) within the plane: a = du · (q - c), b = dv · (q - c).
    du: Vec3,
    dv: Vec3,
    /// Area of the image plane.
    area: f32,
    resolution: Vec2,
    /// Lens radius (camera units), focus distance (camera units) and lens area (world);
    /// a pinhole has radius 0, focus 1 and area 1 (its position is a delta).
    lens_radius: f32,
    focus: f32,
    lens_area: f32,
}

/// A point on the lens that sees a given scene point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// The point on the lens (the eye for a pinhole).
    pub point: Vec3,
    /// Unit direction from the scene point to `point`, and the distance.
    pub wi: Vec3,
    pub dist: f32,
    /// Importance of the ray from `point` towards the scene point.
    pub we: f32,
    /// Solid-angle density of `wi` at the scene point.
    pub pdf: f32,
    /// Where on the film the ray lands (pixels).
    pub film: Vec2,
}

impl ImagePlane {
    /// `tan_half`: half-extent of the image plane at depth 1 in camera x and y.
    pub fn new(to_world: &Transform, tan_half: Vec2, resolution: Vec2) -> Self {
        let (lens_x, lens_y) = (to_world.vector(Vec3::X), to_world.vector(Vec3::Y));
        let c = to_world.vector(Vec3::NEG_Z);
        let (hx, hy) = (lens_x * tan_half.x, lens_y * tan_half.y);
        let mut n = hx.cross(hy).normalize_or_zero();
        if n.dot(c) < 0.0 {
            n = -n;
        }
        let du = hy.cross(n) / hx.dot(hy.cross(n));
        let dv = n.cross(hx) / hy.dot(n.cross(hx));
        ImagePlane {
            eye: to_world.point(Vec3::ZERO),
            lens_x,
            lens_y,
            n,
            c,
            h: n.dot(c),
            du,
            dv,
            area: 4.0 * hx.cross(hy).length(),
            resolution,
            lens_radius: 0.0,
            focus: 1.0,
            lens_area: 1.0,
        }
    }

    /// The plane with a thin lens of `radius` focused at `focus` (camera units).
    pub fn with_lens(mut self, radius: f32, focus: f32) -> Self {
        if radius > 0.0 {
            self.lens_radius = radius;
            self.focus = focus;
            self.lens_area = PI * radius * radius * self.lens_x.cross(self.lens_y).length();
        }
        self
    }

    /// Unit normal of the lens, towards the scene.
    pub fn normal(&self) -> Vec3 {
        self.n
    }

    /// The importance of the ray leaving lens point `origin` along unit `dir`, and the film
    /// position it comes from; `None` outside the film or behind the camera.
    pub fn we(&self, origin: Vec3, dir: Vec3) -> Option<(f32, Vec2)> {
        let cos = dir.dot(self.n);
        if cos <= 0.0 {
            return None;
        }
        // Through the plane of focus, back through the eye onto the image plane.
        let q = (origin - self.eye + dir * (self.focus * self.h / cos)) / self.focus;
        let (a, b) = (self.du.dot(q - self.c), self.dv.dot(q - self.c));
        let film = Vec2::new(a + 1.0, 1.0 - b) * 0.5 * self.resolution;
        let inside = film.x >= 0.0 && film.y >= 0.0 && film.x < self.resolution.x && film.y < self.resolution.y;
        let cos2 = cos * cos;
        inside.then(|| (self.h * self.h / (self.area * self.lens_area * cos2 * cos2), film))
    }

    /// The densities (per lens area, per solid angle) with which ray generation from a
    /// uniform film position and lens point produces a ray along unit `dir`; zero outside
    /// the film.
    pub fn pdf_we(&self, origin: Vec3, dir: Vec3) -> (f32, f32) {
        if self.we(origin, dir).is_none() {
            return (0.0, 0.0);
        }
        let cos = dir.dot(self.n);
        (1.0 / self.lens_area, self.h * self.h / (self.area * cos * cos * cos))
    }

    /// A point on the lens, drawn from `u`, that sees scene point `p`, with its importance
    /// and density; `None` when it sees `p` from outside the film.
    pub fn sample_wi(&self, p: Vec3, u: Vec2) -> Option<CameraSample> {
        let d = warp::uniform_disk(u) * self.lens_radius;
        let point = self.eye + self.lens_x * d.x + self.lens_y * d.y;
        let to = point - p;
        let dist = to.length();
        if !(dist > 0.0 && dist.is_finite()) {
            return None;
        }
        let wi = to / dist;
        let (we, film) = self.we(point, -wi)?;
        let pdf = dist * dist / (self.n.dot(-wi) * self.lens_area);
        Some(CameraSample {
            point,
            wi,
            dist,
            we,
            pdf,
            film,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cameras::{FovAxis, Perspective};
    use penumbra_testkit::Uniforms;

    /// Rays generated through film positions map back to those positions, for a pinhole,
    /// a thin lens and a mirrored, scaled camera transform.
    #[test]
    fn importance_finds_the_film_position_of_generated_rays() {
        let eye = Transform::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 0.5, -1.0), Vec3::Y).unwrap();
        let mirrored = Transform::scale(Vec3::new(-2.0, 2.0, 2.0)).unwrap().then(eye);
        let mut u = Uniforms::new(5);
        for to_world in [eye, mirrored] {
            for lens in [0.0, 0.3] {
                let cam = Perspective::new(to_world, 50.0, FovAxis::X, 64, 48).with_lens(lens, 3.0);
                for _ in 0..1000 {
                    let film = u.next_vec2() * Vec2::new(64.0, 48.0);
                    let ray = cam.generate_ray(film, u.next_vec2());
                    let (we, back) = cam.plane().we(ray.origin, ray.dir).unwrap();
                    assert!((back - film).length() < 2e-3, "{back} vs {film}");
                    assert!(we > 0.0);
                }
            }
        }
    }

    /// The importance integrates to one over the film: ∫ We cos θ dω over the directions
    /// that reach the film (from the eye) is 1 / A_lens = 1 for a pinhole; by Monte Carlo
    /// over the sphere (200,000 directions: standard error about 0.4%).
    #[test]
    fn pinhole_importance_integrates_to_one() {
        let eye = Transform::look_at(Vec3::ZERO, Vec3::new(0.2, 0.1, -1.0), Vec3::Y).unwrap();
        let cam = Perspective::new(eye, 70.0, FovAxis::Y, 40, 30);
        let plane = cam.plane();
        let mut u = Uniforms::new(9);
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let w = warp::uniform_sphere(u.next_vec2());
            let x = plane.we(Vec3::ZERO, w).map_or(0.0, |(we, _)| {
                (we * w.dot(plane.normal()) / warp::UNIFORM_SPHERE_PDF) as f64
            });
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!((mean - 1.0).abs() < 4.0 * se, "{mean} ± {se}");
    }
}
