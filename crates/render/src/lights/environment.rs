//! Light from infinitely far away in every direction: a constant colour, or an
//! equirectangular (latitude-longitude) image, importance sampled by a piecewise-constant
//! 2D distribution of the pixels' luminance times sin θ (pbrt-v4 section 12.5.2, Mitsuba 3's
//! `envmap`), so that the density over directions follows the radiance.
//!
//! Mapping (Mitsuba's, y up): the direction (sin φ sin θ, cos θ, −cos φ sin θ) is pixel
//! (u, v) = (φ / 2π, θ / π) of the image, u across and v down; `rotation` turns the map.
//! Each pixel is constant over its cell (no filtering), so the sampling density is exactly
//! proportional to the luminance it samples. The map's cells are drawn by inverting the
//! CDFs, or by Walker's alias method when the sampler's numbers are independent
//! ([`penumbra_core::Draw`]).

use super::lanes::{LaneLightSample, LightGather, LightKernel};
use super::{disk_origin, disk_pdf, AreaSampling, EmissionSample, LightModel, LightSample, SceneSphere};
use crate::texture::TextureImage;
use glam::{Mat3, Vec2, Vec3};
use penumbra_core::frame::Basis;
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{trig, warp, Distribution2D, Draw, Ray, Rgb};
use std::f32::consts::PI;

/// What the map holds for a direction (see [`Environment::lookup`]): its radiance and
/// solid-angle density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapPoint {
    le: Rgb,
    pdf: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// The map, and its sampling distribution, each cell carrying its pixel's radiance
    /// (times the map's scale) beside its density: a sample's whole answer in one read.
    image: Option<(TextureImage, Distribution2D<Rgb>)>,
    /// The radiance of a constant environment, or the image's multiplier.
    scale: Rgb,
    /// From the map's frame to the world, and back.
    to_world: Mat3,
    to_local: Mat3,
    /// Mean radiance luminance over the sphere, for choosing among lights.
    mean_luminance: f32,
}

impl Environment {
    /// The same radiance from every direction.
    pub fn constant(radiance: Rgb) -> Self {
        Environment {
            image: None,
            scale: radiance,
            to_world: Mat3::IDENTITY,
            to_local: Mat3::IDENTITY,
            mean_luminance: radiance.luminance().max(0.0),
        }
    }

    /// An equirectangular map (row 0 at the top, θ = 0) times `scale`, turned by the
    /// rotation `to_world`, its cells drawn as `draw` says (by the alias method only for
    /// independent random numbers: it does not keep stratified ones stratified). An error
    /// when a pixel is negative or not finite, or the map is black.
    pub fn image(image: TextureImage, scale: Rgb, to_world: Mat3, draw: Draw) -> Result<Self, String> {
        let (w, h) = (image.width, image.height);
        if w == 0 || h == 0 || image.pixels.len() != w * h {
            return Err(format!("the map has {} pixels, not {w} x {h}", image.pixels.len()));
        }
        if let Some(i) = image
            .pixels
            .iter()
            .position(|p| !(p.is_finite() && p.r >= 0.0 && p.g >= 0.0 && p.b >= 0.0))
        {
            return Err(format!(
                "pixel ({}, {}) is negative or not a finite number",
                i % w,
                i / w
            ));
        }
        let weights: Vec<f32> = image
            .pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let theta = ((i / w) as f32 + 0.5) / h as f32 * PI;
                (p.luminance() * scale.luminance()).max(0.0) * theta.sin()
            })
            .collect();
        let texel = |i: usize| image.pixels[i] * scale;
        let distribution =
            Distribution2D::with_items(&weights, texel, w, h, draw).ok_or("the map is black: it gives no light")?;
        let mean_luminance = (solid_angle_integral(&image, |p| p.luminance() as f64) * scale.luminance() as f64
            / (4.0 * PI as f64)) as f32;
        Ok(Environment {
            image: Some((image, distribution)),
            scale,
            to_world,
            to_local: to_world.transpose(),
            mean_luminance,
        })
    }

    /// What the map holds for the world direction `d`, for [`Environment::le_at`] and
    /// [`Environment::pdf_at`]: a direction's radiance and density share one lookup.
    pub fn lookup(&self, d: Vec3) -> MapPoint {
        let (le, pdf) = self.lookup_lanes(V3::from(d));
        MapPoint { le: le.into(), pdf }
    }

    /// [`Environment::lookup`] of eight directions, in eight lanes at the CPU's SIMD level.
    pub fn lookup8(&self, d: &[Vec3; 8]) -> [MapPoint; 8] {
        #[inline(always)]
        fn kernel<L: Lane8>(env: &Environment, d: &[Vec3; 8]) -> [MapPoint; 8] {
            let (le, pdf) = env.lookup_lanes(V3::<L>::from_lanes(d));
            let (le, pdf) = (le.to_lanes(), pdf.to_array());
            std::array::from_fn(|k| MapPoint {
                le: Rgb::new(le[k].x, le[k].y, le[k].z),
                pdf: pdf[k],
            })
        }
        #[cfg(target_arch = "x86_64")]
        penumbra_core::level_fns! {
            unsafe fn [avx2, avx512](env: &Environment, d: &[Vec3; 8]) -> [MapPoint; 8] {
                kernel::<penumbra_core::lanes_avx::F8Avx>(env, d)
            }
        }
        penumbra_core::at_level!(
            avx512: avx512(self, d),
            avx2: avx2(self, d),
            portable: kernel::<penumbra_core::lanes::F8>(self, d)
        )
    }

    /// [`Environment::lookup`] per lane: the radiance and the density of each direction.
    #[inline(always)]
    fn lookup_lanes<R: Real>(&self, d: V3<R>) -> (V3<R>, R) {
        let Some((_, distribution)) = &self.image else {
            return (V3::splat_rgb(self.scale), R::splat(1.0 / (4.0 * PI)));
        };
        let (u, v, sin_theta) = self.map_coordinates(d);
        // Every lane's cell asked of the caches first, so that the lanes' reads overlap.
        let [] = R::map_lanes([u, v], |_, p| {
            distribution.prefetch_at(p);
            []
        });
        // Each lane's cell: its radiance and 2D density.
        let [r, g, b, density] = R::map_lanes([u, v], |_, [u, v]| {
            let (density, t) = distribution.item_at([u, v]);
            [t.r, t.g, t.b, density]
        });
        let pdf = solid_angle_density_lanes(density, sin_theta);
        (V3::new(r, g, b), pdf)
    }

    /// (u, v) in the map of the world direction `d`, and sin θ there, per lane.
    #[inline(always)]
    fn map_coordinates<R: Real>(&self, d: V3<R>) -> (R, R, R) {
        // `(to_local * d).normalize()` as glam computes it.
        let m = &self.to_local;
        let columns = Basis {
            s: V3::splat_vec(m.x_axis),
            t: V3::splat_vec(m.y_axis),
            n: V3::splat_vec(m.z_axis),
        };
        let d = columns.to_world(d).try_normalize().0;
        let phi = trig::atan2(d.x, -d.z);
        // `rem_euclid(1.0)` of a number in [-1/2, 1/2], and the `min`s below, as `f32`'s.
        let u = phi / R::splat(2.0 * PI);
        let u = R::select(u.cmp_lt(R::splat(0.0)), u + R::splat(1.0), u);
        // θ and sin θ from x and z besides y: accurate near the poles, where 1 - y² is not.
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        let v = trig::atan2(sin_theta, d.y) / R::splat(PI);
        (below(u, 1.0 - f32::EPSILON), below(v, 1.0), sin_theta)
    }

    /// The world direction of map point (u, v), and sin θ there.
    #[cfg(test)]
    fn direction(&self, uv: Vec2) -> (Vec3, f32) {
        let (d, sin_theta) = self.direction_lanes(uv.x, uv.y);
        (d.into(), sin_theta)
    }

    /// The world direction of map point (`u`, `v`), and sin θ there, per lane.
    #[inline(always)]
    fn direction_lanes<R: Real>(&self, u: R, v: R) -> (V3<R>, R) {
        let (sin_phi, cos_phi) = trig::sin_cos_turns(u);
        let (sin_theta, cos_theta) = trig::sin_cos_turns(R::splat(0.5) * v);
        let local = V3::new(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta);
        // `to_world * local` as glam sums it: (x_axis x + y_axis y) + z_axis z.
        let m = &self.to_world;
        let columns = Basis {
            s: V3::splat_vec(m.x_axis),
            t: V3::splat_vec(m.y_axis),
            n: V3::splat_vec(m.z_axis),
        };
        (columns.to_world(local), sin_theta)
    }

    /// The one-lane instance of the light-sampling arithmetic.
    #[inline(always)]
    pub fn lanes(&self) -> EnvironmentLanes<'_> {
        EnvironmentLanes { env: self }
    }

    /// Radiance arriving from direction `d` (pointing away from the scene).
    pub fn le(&self, d: Vec3) -> Rgb {
        self.le_at(&self.lookup(d))
    }

    /// Radiance arriving from the direction that `at` looked up.
    pub fn le_at(&self, at: &MapPoint) -> Rgb {
        at.le
    }

    /// A direction towards the environment, with its radiance and solid-angle density.
    pub fn sample_li(&self, u: Vec2) -> Option<LightSample> {
        self.lanes().sample_li(V3::splat(0.0), (u.x, u.y)).one(false)
    }

    /// Solid-angle density of [`Environment::sample_li`] at direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.pdf_at(&self.lookup(d))
    }

    /// Solid-angle density of [`Environment::sample_li`] at the direction `at` looked up.
    pub fn pdf_at(&self, at: &MapPoint) -> f32 {
        at.pdf
    }

    /// A ray of light coming in from the environment: its direction from `u_dir` as
    /// [`Environment::sample_li`] draws it, its origin on the disk facing that direction.
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
        let s = self.sample_li(u_dir)?;
        let dir = -s.wi;
        Some(EmissionSample {
            ray: Ray::new(disk_origin(sphere, dir, u_pos), dir),
            normal: dir,
            le: s.li,
            pdf_pos: disk_pdf(sphere),
            pdf_dir: s.pdf,
        })
    }

    /// Power reaching a scene of radius `scene_radius`: π r² times ∫ L dω (luminance).
    pub fn power(&self, scene_radius: f32) -> f32 {
        PI * scene_radius * scene_radius * 4.0 * PI * self.mean_luminance
    }
}

/// `x.min(top)` per lane, as `f32::min` gives it (`top` for a NaN).
#[inline(always)]
fn below<R: Real>(x: R, top: f32) -> R {
    R::select(x.cmp_lt(R::splat(top)), x, R::splat(top))
}

/// The solid-angle density of a direction at polar sine `sin_theta` in a cell of 2D
/// density `density`, per lane: the equirectangular map's Jacobian is 2π² sin θ (pbrt-v4
/// section 12.5.2).
#[inline(always)]
fn solid_angle_density_lanes<R: Real>(density: R, sin_theta: R) -> R {
    let zero = R::splat(0.0);
    R::select(
        sin_theta.cmp_le(zero),
        zero,
        density / (R::splat(2.0 * PI * PI) * sin_theta),
    )
}

/// The environment's light sampling in lanes of any [`Real`] type: the map's cells drawn
/// per lane from its distribution (a table walk of each lane's own), the directions and
/// densities in lanes. The scene's one environment serves every lane.
#[derive(Clone, Copy, Debug)]
pub struct EnvironmentLanes<'a> {
    env: &'a Environment,
}

impl<R: Real> LightKernel<R> for EnvironmentLanes<'_> {
    #[inline(always)]
    fn sample_li(&self, _p: V3<R>, u: (R, R)) -> LaneLightSample<R> {
        // (No closure here: one would be compiled apart from the kernel's SIMD level.)
        self.sample_rgb(u)
    }
}

impl EnvironmentLanes<'_> {
    /// [`LightKernel::sample_li`] carrying the payload `S`: the map's RGB radiance at each
    /// lane's direction converted by `to` (as a spectral renderer turns it into values at
    /// a path's wavelengths); the directions and densities do not depend on the payload.
    #[inline(always)]
    pub fn sample_li_with<R: Real, S: Spectrum<R>>(
        &self,
        _p: V3<R>,
        u: (R, R),
        to: impl Fn(V3<R>) -> S,
    ) -> LaneLightSample<R, S> {
        let s = self.sample_rgb(u);
        LaneLightSample {
            wi: s.wi,
            li: to(s.li),
            dist: s.dist,
            pdf: s.pdf,
            ok: s.ok,
        }
    }

    /// The sample in RGB.
    #[inline(always)]
    fn sample_rgb<R: Real>(&self, u: (R, R)) -> LaneLightSample<R> {
        let env = self.env;
        let (wi, le, pdf) = match &env.image {
            None => (
                warp::uniform_sphere_lanes(u.0, u.1),
                V3::splat_rgb(env.scale),
                R::splat(1.0 / (4.0 * PI)),
            ),
            Some((_, distribution)) => {
                // Each lane's cell and point in the map, then the cell's radiance and 2D
                // density, each step's reads made for all lanes together (most of a large
                // map is not in the caches).
                let c = distribution.sample_lanes(u);
                let [] = R::map_lanes([c.x, c.y], |_, [x, y]| {
                    distribution.prefetch_cell(x as usize, y as usize);
                    []
                });
                let [r, g, b, density] = R::map_lanes([c.x, c.y], |_, [x, y]| {
                    let (density, t) = distribution.cell(x as usize, y as usize);
                    [t.r, t.g, t.b, density]
                });
                let [x, y] = c.point;
                let (wi, sin_theta) = env.direction_lanes(x, y);
                // The radiance and density of the sampled point's own pixel (as Mitsuba's
                // `envmap` takes them): no mapping of the direction back to the map. The
                // point stays inside its cell, so it is the pixel the density chose.
                let pdf = solid_angle_density_lanes(density, sin_theta);
                (wi, V3::new(r, g, b), pdf)
            }
        };
        LaneLightSample {
            wi,
            li: le,
            dist: R::splat(f32::INFINITY),
            pdf,
            ok: R::and(pdf.cmp_gt(R::splat(0.0)), pdf.is_finite()),
        }
    }
}

impl<'a> LightGather for EnvironmentLanes<'a> {
    type Lanes<L: Lane8> = EnvironmentLanes<'a>;
    /// The one environment of the eight lanes.
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> EnvironmentLanes<'a> {
        debug_assert!(one.iter().all(|e| std::ptr::eq(e.env, one[0].env)));
        one[0]
    }
}

/// ∫ g(L) dω over the sphere for a map constant over each pixel: each pixel of row y spans
/// 2π/width in φ and cos θ0 − cos θ1 in cos θ.
fn solid_angle_integral(image: &TextureImage, g: impl Fn(Rgb) -> f64) -> f64 {
    let (w, h) = (image.width, image.height);
    image
        .pixels
        .chunks(w)
        .enumerate()
        .map(|(y, row)| {
            let (t0, t1) = (y as f64 / h as f64 * PI as f64, (y + 1) as f64 / h as f64 * PI as f64);
            let band = (t0.cos() - t1.cos()) * 2.0 * PI as f64 / w as f64;
            row.iter().map(|&p| g(p)).sum::<f64>() * band
        })
        .sum()
}

impl LightModel for Environment {
    fn sample_li(&self, _p: Vec3, u: Vec2, _strategy: AreaSampling) -> Option<LightSample> {
        Environment::sample_li(self, u)
    }
    fn pdf_li(&self, _p: Vec3, wi: Vec3, _strategy: AreaSampling) -> f32 {
        self.pdf(wi)
    }
    fn emitted(&self, _point: Vec3, w: Vec3) -> Rgb {
        self.le(-w)
    }
    fn surface_normal(&self, _point: Vec3) -> Option<Vec3> {
        None
    }
    fn pdf_from_infinity(&self, dir: Vec3) -> f32 {
        self.pdf(-dir)
    }
    fn connectible(&self) -> bool {
        true
    }
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, sphere: SceneSphere) -> Option<EmissionSample> {
        Environment::sample_le(self, u_pos, u_dir, sphere)
    }
    fn pdf_le(&self, dir: Vec3, _normal: Vec3, sphere: SceneSphere) -> (f32, f32) {
        (disk_pdf(sphere), self.pdf(-dir))
    }
    fn is_infinite(&self) -> bool {
        true
    }
    fn is_delta(&self) -> bool {
        false
    }
    fn power(&self, scene_radius: f32) -> f32 {
        Environment::power(self, scene_radius)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small map with a bright spot, a dark band and a black corner.
    fn map() -> TextureImage {
        let (width, height) = (16, 8);
        let pixels = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                match (x, y) {
                    (3, 2) => Rgb::new(40.0, 30.0, 20.0),
                    (_, 5) => Rgb::splat(0.05),
                    (0..=2, 7) => Rgb::BLACK,
                    _ => Rgb::new(0.5 + 0.02 * x as f32, 0.4, 0.3),
                }
            })
            .collect();
        TextureImage {
            width,
            height,
            pixels,
            wrap: Default::default(),
        }
    }

    #[test]
    fn sampling_fits_the_density_and_follows_the_map() {
        let rotation = Mat3::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 1.1);
        for (seed, env) in [
            Environment::image(map(), Rgb::WHITE, Mat3::IDENTITY, Draw::Inverted).unwrap(),
            Environment::image(map(), Rgb::splat(2.0), rotation, Draw::Alias).unwrap(),
            Environment::constant(Rgb::splat(0.7)),
        ]
        .iter()
        .enumerate()
        {
            let r = penumbra_testkit::chi2_directions(
                seed as u64,
                400_000,
                |u| env.sample_li(u).map(|s| s.wi),
                |w| env.pdf(w),
            );
            r.assert_fits(&format!("environment {seed}"), 3);
            assert!((r.integral - 1.0).abs() < 2e-3, "{}", r.describe());
            // The estimate of ∫ L dω by sampling the map equals its exact integral over the
            // pixels (for the constant map: 4π L).
            let mut u = penumbra_testkit::Uniforms::new(9);
            let mut mean = penumbra_testkit::MeanEstimate::default();
            for _ in 0..20_000 {
                let s = env.sample_li(u.next_vec2()).unwrap();
                assert!(
                    (env.pdf(s.wi) - s.pdf).abs() <= 1e-3 * s.pdf,
                    "{} vs {}",
                    env.pdf(s.wi),
                    s.pdf
                );
                mean.push((s.li.luminance() / s.pdf) as f64);
            }
            let want = match &env.image {
                Some((image, _)) => {
                    solid_angle_integral(image, |p| p.luminance() as f64) * env.scale.luminance() as f64
                }
                None => 4.0 * PI as f64 * 0.7,
            };
            penumbra_testkit::assert_within_3se(
                &format!("environment {seed}"),
                mean.mean(),
                mean.standard_error(),
                want,
                1e-3 * want,
            );
        }
    }

    #[test]
    fn directions_and_map_coordinates_agree() {
        let env = Environment::image(map(), Rgb::WHITE, Mat3::from_rotation_y(0.7), Draw::Alias).unwrap();
        for (u, v) in [(0.1f32, 0.2f32), (0.5, 0.5), (0.93, 0.81), (0.0, 0.3)] {
            let (d, _) = env.direction(Vec2::new(u, v));
            let (x, y, _) = env.map_coordinates(V3::from(d));
            assert!((x - u).abs() < 1e-5 && (y - v).abs() < 1e-5, "{u}, {v} -> {x}, {y}");
        }
        // Up is the top row; -z is the left edge (φ = 0), +z the centre column.
        let up = Environment::image(map(), Rgb::WHITE, Mat3::IDENTITY, Draw::Inverted).unwrap();
        assert!(up.map_coordinates(V3::from(Vec3::Y)).1 < 1e-6);
        assert!(up.map_coordinates(V3::from(Vec3::NEG_Z)).0 < 1e-6);
    }

    #[test]
    fn bad_maps_are_errors() {
        let mut m = map();
        m.pixels[5] = Rgb::new(f32::NAN, 0.0, 0.0);
        assert!(Environment::image(m, Rgb::WHITE, Mat3::IDENTITY, Draw::Inverted)
            .unwrap_err()
            .contains("(5, 0)"));
        let black = TextureImage {
            wrap: Default::default(),
            width: 2,
            height: 2,
            pixels: vec![Rgb::BLACK; 4],
        };
        assert!(Environment::image(black, Rgb::WHITE, Mat3::IDENTITY, Draw::Alias)
            .unwrap_err()
            .contains("black"));
    }
}
