//! A diffuse area light: an [`Emitter`] surface that emits constant radiance from its front
//! side (or both sides), seen by the camera and sampled by the integrators; on a triangle
//! the radiance may vary, scaled by a texture ([`EmissionTexture`], glTF's emissive maps).
//!
//! Native format: `emission = [r, g, b]` (radiance) and optionally `two_sided = true` on a
//! quad, disk, sphere or mesh shape; a mesh emits from every triangle (one light each,
//! grouped as one light for selection).

use super::area_lanes::{sample_at, TriangleByArea};
use super::emitter::Emitter;
use super::lanes::LightKernel;
use super::{EmissionSample, LightModel, LightSample, SceneSphere};
use crate::Texture;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Real, V3};
use penumbra_core::{warp, Frame, Ray, Rgb};
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
    /// Scales `radiance` over a triangle emitter; `None`: constant.
    pub texture: Option<Box<EmissionTexture>>,
}

/// A texture over a triangle light: the radiance at a point is the light's radiance times
/// the texture at the texture coordinates interpolated from the triangle's corners.
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionTexture {
    pub texture: Texture,
    /// At the emitter's three vertices, in its order.
    pub uvs: [Vec2; 3],
    /// The texture's mean luminance over the triangle (for the light's power).
    mean: f32,
}

impl EmissionTexture {
    /// The texture coordinates at barycentric coordinates (b1, b2) of the triangle.
    fn uv_at(&self, b1: f32, b2: f32) -> Vec2 {
        let (u, v) = self.uv_at_lanes(b1, b2);
        Vec2::new(u, v)
    }

    /// [`EmissionTexture::uv_at`] per lane of any [`Real`] type.
    #[inline(always)]
    fn uv_at_lanes<R: Real>(&self, b1: R, b2: R) -> (R, R) {
        let [t0, t1, t2] = self.uvs;
        let b0 = R::splat(1.0) - b1 - b2;
        (
            R::splat(t0.x) * b0 + R::splat(t1.x) * b1 + R::splat(t2.x) * b2,
            R::splat(t0.y) * b0 + R::splat(t1.y) * b1 + R::splat(t2.y) * b2,
        )
    }

    /// Estimates the mean over the triangle from the texture at the 45 points of a
    /// barycentric lattice of step 1/8 (it only weighs the choice of lights, so an estimate
    /// costs variance, never bias).
    pub fn new(texture: Texture, uvs: [Vec2; 3]) -> Self {
        const K: usize = 8;
        let mut t = EmissionTexture {
            texture,
            uvs,
            mean: 0.0,
        };
        let (mut sum, mut n) = (0.0, 0);
        for i in 0..=K {
            for j in 0..=K - i {
                let uv = t.uv_at(i as f32 / K as f32, j as f32 / K as f32);
                sum += t.texture.eval(uv).luminance().max(0.0);
                n += 1;
            }
        }
        t.mean = sum / n as f32;
        t
    }
}

impl AreaLight {
    /// Radiance leaving the point `point`, of normal `normal`, in direction `w`.
    pub fn le(&self, point: Vec3, normal: Vec3, w: Vec3) -> Rgb {
        self.le_lanes(point.into(), normal.into(), w.into()).into()
    }

    /// [`AreaLight::le`] per lane of any [`Real`] type, for points of this light: its
    /// radiance (times the texture at each point, if textured) where the emitting side
    /// faces `w`, looked up only where some lane needs it.
    #[inline(always)]
    pub fn le_lanes<R: Real>(&self, point: V3<R>, normal: V3<R>, w: V3<R>) -> V3<R> {
        let emits = emits_towards(normal, w, R::splat_mask(self.two_sided));
        penumbra_core::choose_lanes!(R, emits, self.radiance_at_lanes(point), V3::splat(0.0))
    }

    /// Light arriving at `p` from a point chosen by `strategy` from `u` (an untextured
    /// triangle by area: the one-lane instance of [`TriangleByArea`]).
    pub fn sample_li(&self, p: Vec3, u: Vec2, strategy: AreaSampling) -> Option<LightSample> {
        let strategy = self.resolve(p, strategy);
        if let Some(k) = self.triangle_kernel(strategy) {
            return k.sample_li(p.into(), (u.x, u.y)).one(false);
        }
        let s = match strategy {
            AreaSampling::Area => self.emitter.sample_uniform(p, u),
            _ => self.emitter.sample_solid_angle(p, u),
        }?;
        let point = V3::from(s.point);
        sample_at(
            p.into(),
            point,
            s.normal.into(),
            (s.pdf, true),
            || self.radiance_at_lanes(point),
            self.two_sided,
        )
        .one(false)
    }

    /// The radiance the light's emitting side sends from `point`, per lane of any [`Real`]
    /// type: the texture's scale looked up there, if textured (untextured lights, nearly
    /// all, do not look at the point).
    #[inline(always)]
    fn radiance_at_lanes<R: Real>(&self, point: V3<R>) -> V3<R> {
        let radiance = V3::splat_rgb(self.radiance);
        let Some(t) = &self.texture else {
            return radiance;
        };
        match self.emitter.triangle_parts() {
            Some((v, _, _)) => {
                let (b1, b2) = barycentric_lanes(v.map(V3::splat_vec), point);
                let (u, v) = t.uv_at_lanes(b1, b2);
                radiance.mul_each(t.texture.eval_lanes(u, v))
            }
            None => radiance,
        }
    }

    /// The solid-angle density `strategy` gives the direction from `p` to `point` (a point
    /// of this light with normal `normal`).
    pub fn pdf(&self, p: Vec3, point: Vec3, normal: Vec3, strategy: AreaSampling) -> f32 {
        match self.resolve(p, strategy) {
            AreaSampling::Area => self.emitter.area_pdf_to_solid_angle(p, point, normal).unwrap_or(0.0),
            _ => self.emitter.solid_angle_pdf(p, point, normal),
        }
    }

    /// This light's one-lane [`TriangleByArea`] kernel if it is an untextured triangle that
    /// `strategy` samples by area at `p`.
    pub fn triangle_by_area(&self, p: Vec3, strategy: AreaSampling) -> Option<TriangleByArea<f32>> {
        self.triangle_kernel(self.resolve(p, strategy))
    }

    /// [`AreaLight::triangle_by_area`] for a strategy already resolved at the point.
    fn triangle_kernel(&self, resolved: AreaSampling) -> Option<TriangleByArea<f32>> {
        if self.texture.is_some() || resolved != AreaSampling::Area {
            return None;
        }
        let (v, normal, _) = self.emitter.triangle_parts()?;
        Some(TriangleByArea {
            v: v.map(V3::from),
            normal: normal.into(),
            area: self.emitter.area(),
            radiance: self.radiance.into(),
            two_sided: self.two_sided,
        })
    }

    /// What `strategy` means at `p`: `Adaptive` becomes area or solid angle.
    fn resolve(&self, p: Vec3, strategy: AreaSampling) -> AreaSampling {
        match strategy {
            AreaSampling::Adaptive if self.emitter.looks_small(p) => AreaSampling::Area,
            AreaSampling::Adaptive => AreaSampling::SolidAngle,
            s => s,
        }
    }

    /// A ray leaving a point uniform by area in a cosine-distributed direction about the
    /// normal (a two-sided light: on either side, each with probability 1/2).
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2) -> Option<EmissionSample> {
        let (point, n) = self.emitter.sample_area(u_pos);
        let (mut u, mut normal, mut side_pdf) = (u_dir, n, 1.0);
        if self.two_sided {
            // The first coordinate picks the side and is stretched back over [0, 1).
            (u.x, side_pdf) = (2.0 * u.x, 0.5);
            if u.x >= 1.0 {
                (u.x, normal) = (u.x - 1.0, -n);
            }
        }
        let local = warp::cosine_hemisphere(u);
        let dir = Frame::from_normal(normal).to_world(local);
        Some(EmissionSample {
            // (Pushed off the surface, so that the ray does not meet the light itself.)
            ray: Ray::spawn(point, n, dir),
            normal: n,
            le: self.le(point, n, dir),
            pdf_pos: 1.0 / self.emitter.area(),
            pdf_dir: side_pdf * warp::cosine_hemisphere_pdf(local),
        })
    }

    /// The densities (per area, per solid angle) of [`AreaLight::sample_le`] for the ray
    /// leaving along `dir` from a point of front normal `normal`.
    pub fn pdf_le(&self, dir: Vec3, normal: Vec3) -> (f32, f32) {
        let cos = normal.dot(dir);
        let pdf_dir = if self.two_sided {
            0.5 * cos.abs() * std::f32::consts::FRAC_1_PI
        } else {
            cos.max(0.0) * std::f32::consts::FRAC_1_PI
        };
        (1.0 / self.emitter.area(), pdf_dir)
    }

    /// Emitted power (luminance): π L A per emitting side.
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        let texture = self.texture.as_ref().map_or(1.0, |t| t.mean);
        sides * PI * self.emitter.area() * self.radiance.luminance() * texture
    }
}

/// Whether an area light of normal `normal` (two-sided or not) emits in direction `w`,
/// per lane of any [`Real`] type.
#[inline(always)]
pub fn emits_towards<R: Real>(normal: V3<R>, w: V3<R>, two_sided: R::Mask) -> R::Mask {
    R::or(two_sided, normal.dot(w).cmp_gt(R::splat(0.0)))
}

/// The unit direction from `p` towards `point` (a point of an area light sampled with
/// solid-angle density `pdf`), the distance, and where these make a light sample (distance
/// and density positive and finite), per lane of any [`Real`] type; part of every area
/// light's sample (`area_lanes::sample_at`).
#[inline(always)]
pub fn towards_point_lanes<R: Real>(p: V3<R>, point: V3<R>, pdf: R) -> (V3<R>, R, R::Mask) {
    let (zero, inf) = (R::splat(0.0), R::splat(f32::INFINITY));
    let d = point - p;
    let dist = d.dot(d).sqrt();
    let ok = R::and(
        R::and(dist.cmp_gt(zero), dist.cmp_lt(inf)),
        R::and(pdf.cmp_lt(inf), pdf.cmp_gt(zero)),
    );
    (d.div_by(dist), dist, ok)
}

/// The barycentric coordinates (b1, b2) of `p`'s projection onto the plane of triangle `v`
/// (p = (1 - b1 - b2) v0 + b1 v1 + b2 v2).
#[cfg(test)]
fn barycentric(v: [Vec3; 3], p: Vec3) -> (f32, f32) {
    barycentric_lanes(v.map(V3::from), p.into())
}

/// [`barycentric`] per lane of any [`Real`] type ((0, 0) for a degenerate triangle).
#[inline(always)]
fn barycentric_lanes<R: Real>(v: [V3<R>; 3], p: V3<R>) -> (R, R) {
    let (e1, e2, d) = (v[1] - v[0], v[2] - v[0], p - v[0]);
    let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d20, d21) = (d.dot(e1), d.dot(e2));
    let den = d00 * d11 - d01 * d01;
    let (zero, degenerate) = (R::splat(0.0), den.cmp_le(R::splat(0.0)));
    (
        R::select(degenerate, zero, (d11 * d20 - d01 * d21) / den),
        R::select(degenerate, zero, (d00 * d21 - d01 * d20) / den),
    )
}

impl LightModel for AreaLight {
    fn sample_li(&self, p: Vec3, u: Vec2, strategy: AreaSampling) -> Option<LightSample> {
        AreaLight::sample_li(self, p, u, strategy)
    }
    fn pdf_li(&self, p: Vec3, wi: Vec3, strategy: AreaSampling) -> f32 {
        self.emitter
            .intersect(p, wi)
            .map_or(0.0, |(point, normal)| self.pdf(p, point, normal, strategy))
    }
    fn emitted(&self, point: Vec3, w: Vec3) -> Rgb {
        self.le(point, self.emitter.normal_at(point), w)
    }
    fn surface_normal(&self, point: Vec3) -> Option<Vec3> {
        Some(self.emitter.normal_at(point))
    }
    fn pdf_from_infinity(&self, _dir: Vec3) -> f32 {
        0.0
    }
    fn connectible(&self) -> bool {
        true
    }
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, _sphere: SceneSphere) -> Option<EmissionSample> {
        AreaLight::sample_le(self, u_pos, u_dir)
    }
    fn pdf_le(&self, dir: Vec3, normal: Vec3, _sphere: SceneSphere) -> (f32, f32) {
        AreaLight::pdf_le(self, dir, normal)
    }
    fn is_infinite(&self) -> bool {
        false
    }
    fn is_delta(&self) -> bool {
        false
    }
    fn power(&self, _scene_radius: f32) -> f32 {
        AreaLight::power(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::lanes::F8;

    /// A triangle light over the origin, facing it, its radiance scaled (when `uvs` are
    /// given) by a 2x2 image texture of `pixels` at those corner coordinates; and the texture.
    fn triangle_light(
        pixels: [Rgb; 4],
        uvs: Option<[Vec2; 3]>,
        radiance: Rgb,
        two_sided: bool,
    ) -> (AreaLight, Texture) {
        let image = TextureImage {
            wrap: Default::default(),
            width: 2,
            height: 2,
            pixels: pixels.to_vec(),
        };
        let texture = Texture::Image(crate::texture::ImageTexture {
            image: Arc::new(image),
            scale: 1.0,
        });
        let v = [
            Vec3::new(-0.3, -0.2, 1.0),
            Vec3::new(-0.2, 0.9, 1.2),
            Vec3::new(0.8, -0.1, 0.9),
        ];
        let light = AreaLight {
            emitter: Emitter::new(EmitterShape::Triangle { v }).unwrap(),
            radiance,
            two_sided,
            texture: uvs.map(|uvs| Box::new(EmissionTexture::new(texture.clone(), uvs))),
        };
        (light, texture)
    }

    /// Eight points of a triangle light, textured and not, one- and two-sided, seen from
    /// random directions (half from behind): each lane of [`AreaLight::le_lanes`] is the
    /// scalar emission's bits (the texture's scale at the point included).
    #[test]
    fn emission_in_lanes_is_the_scalar_emission() {
        let pixels = [
            Rgb::new(0.5, 1.0, 2.0),
            Rgb::splat(4.0),
            Rgb::splat(0.1),
            Rgb::new(1.0, 0.0, 3.0),
        ];
        let uvs = [Vec2::new(0.1, 0.2), Vec2::new(0.3, 0.9), Vec2::new(0.8, 0.4)];
        let mut rng = Uniforms::new(5);
        for (textured, two_sided) in [(true, false), (true, true), (false, false), (false, true)] {
            let (light, _) = triangle_light(pixels, textured.then_some(uvs), Rgb::new(2.0, 1.0, 0.5), two_sided);
            let normal = light.emitter.normal_at(Vec3::ZERO);
            for _ in 0..500 {
                let points: [Vec3; 8] = std::array::from_fn(|_| light.emitter.sample_area(rng.next_vec2()).0);
                let dirs: [Vec3; 8] = std::array::from_fn(|_| penumbra_core::warp::uniform_sphere(rng.next_vec2()));
                let lanes = light.le_lanes::<F8>(V3::from_lanes(&points), V3::splat_vec(normal), V3::from_lanes(&dirs));
                for (k, le) in lanes.to_lanes().into_iter().enumerate() {
                    let one = light.le(points[k], normal, dirs[k]);
                    let bits = |c: Vec3| [c.x, c.y, c.z].map(f32::to_bits);
                    assert_eq!(bits(le), bits(Vec3::new(one.r, one.g, one.b)), "lane {k}");
                }
            }
        }
    }

    use crate::lights::emitter::EmitterShape;
    use crate::texture::TextureImage;
    use penumbra_testkit::{assert_within_se, integrate_2d, MeanEstimate, Uniforms};
    use std::sync::Arc;

    /// A textured triangle light over the origin, facing it: irradiance at the origin by
    /// light sampling (by area and by solid angle) and by sampling the hemisphere (the
    /// texture looked up where the rays land) agree with the integral by quadrature, each
    /// within 4 standard errors (200,000 samples: about 0.1%). Texture coordinates
    /// interpolated from the wrong corners miss by 58 standard errors.
    #[test]
    fn textured_light_sampling_agrees_with_hitting_the_light() {
        // Dark at the first corner's texture coordinates, bright at the far ones.
        let pixels = [Rgb::splat(0.5), Rgb::splat(4.0), Rgb::splat(0.1), Rgb::splat(1.0)];
        let uvs = [Vec2::new(0.25, 0.25), Vec2::new(0.25, 0.75), Vec2::new(0.75, 0.25)];
        let (light, texture) = triangle_light(pixels, Some(uvs), Rgb::splat(2.0), false);
        let (v, _, _) = light.emitter.triangle_parts().expect("a triangle light");
        let normal = light.emitter.normal_at(v[0]);
        assert!(normal.z < 0.0, "the light faces the origin");
        // The integral of L cos(theta) cos(theta') / r^2 over the triangle, by quadrature
        // over (b1, b2) = (s, t (1 - s)) with Jacobian 2 A (1 - s).
        let area = light.emitter.area() as f64;
        let exact = integrate_2d(
            &|[s, t]| {
                let (b1, b2) = (s as f32, (t * (1.0 - s)) as f32);
                let x = v[0] * (1.0 - b1 - b2) + v[1] * b1 + v[2] * b2;
                let uv = uvs[0] * (1.0 - b1 - b2) + uvs[1] * b1 + uvs[2] * b2;
                let l = 2.0 * texture.eval(uv).r as f64;
                let r2 = x.length_squared() as f64;
                let w = x.normalize();
                l * w.z as f64 * (-w.dot(normal)) as f64 / r2 * 2.0 * area * (1.0 - s)
            },
            [0.0, 0.0],
            [1.0, 1.0],
        );
        let n = 200_000;
        let mut rng = Uniforms::new(11);
        for strategy in [AreaSampling::Area, AreaSampling::SolidAngle] {
            let mut e = MeanEstimate::default();
            for _ in 0..n {
                let x = light
                    .sample_li(Vec3::ZERO, rng.next_vec2(), strategy)
                    .map_or(0.0, |s| (s.li.r * s.wi.z.max(0.0) / s.pdf) as f64);
                e.push(x);
            }
            assert_within_se(&format!("{strategy:?}"), e.mean(), e.standard_error(), exact, 0.0, 4.0);
        }
        let mut e = MeanEstimate::default();
        for _ in 0..n {
            // Uniform over the upper hemisphere, density 1 / (2 pi).
            let u = rng.next_vec2();
            let z = u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let w = Vec3::new(r * (2.0 * PI * u.y).cos(), r * (2.0 * PI * u.y).sin(), z);
            // Where the ray meets the light's plane, and whether inside the triangle.
            let t = v[0].dot(normal) / w.dot(normal);
            let mut x = 0.0;
            if t > 0.0 && t.is_finite() {
                let p = w * t;
                let (b1, b2) = barycentric(v, p);
                if b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 {
                    x = (light.le(p, normal, -w).r * z * 2.0 * PI) as f64;
                }
            }
            e.push(x);
        }
        assert_within_se("hemisphere", e.mean(), e.standard_error(), exact, 0.0, 4.0);
        // The power's mean texture lies between the smallest and largest texel.
        let mean = light.texture.as_ref().unwrap().mean;
        assert!((0.1..4.0).contains(&mean), "{mean}");
    }
}
