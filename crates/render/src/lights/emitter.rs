//! The shapes an area light can have, and the ways to pick a point on one: uniformly by
//! area (pbrt-v4 section 6.2 for each shape), or uniformly by the solid angle the shape
//! subtends from the shading point: the cone of directions for a sphere (pbrt-v4 section
//! 6.2.4), spherical triangles (Arvo 1995) and spherical rectangles (Ureña et al. 2013,
//! see [`penumbra_core::spherical`]). Densities are per unit solid angle at the shading
//! point, so every strategy plugs into the same estimator
//! L cos θ / pdf(ω).

use glam::{Vec2, Vec3};
use penumbra_core::{spherical, warp, Frame};
use std::f32::consts::PI;

/// An emitting surface in world space.
#[derive(Clone, Debug, PartialEq)]
pub enum Emitter {
    /// `corner + s e1 + t e2`, s, t in [0, 1]; front side `e1 x e2`.
    Quad { corner: Vec3, e1: Vec3, e2: Vec3 },
    /// `center + x a1 + y a2`, x² + y² <= 1 (an ellipse under shear); front side `a1 x a2`.
    Disk { center: Vec3, a1: Vec3, a2: Vec3 },
    /// Front side `(v1 - v0) x (v2 - v0)`.
    Triangle { v: [Vec3; 3] },
    /// Emits outwards.
    Sphere { center: Vec3, radius: f32 },
}

/// A point on an emitter and the density of the direction towards it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitterSample {
    pub point: Vec3,
    /// Unit normal on the front side.
    pub normal: Vec3,
    /// Density of the direction from the shading point, per unit solid angle.
    pub pdf: f32,
}

impl Emitter {
    pub fn area(&self) -> f32 {
        match self {
            Emitter::Quad { e1, e2, .. } => e1.cross(*e2).length(),
            Emitter::Disk { a1, a2, .. } => PI * a1.cross(*a2).length(),
            Emitter::Triangle { v } => 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length(),
            Emitter::Sphere { radius, .. } => 4.0 * PI * radius * radius,
        }
    }

    /// A point uniform by area, and its unit normal; density 1 / area per unit area.
    pub fn sample_area(&self, u: Vec2) -> (Vec3, Vec3) {
        match self {
            Emitter::Quad { corner, e1, e2 } => (*corner + u.x * *e1 + u.y * *e2, e1.cross(*e2).normalize()),
            Emitter::Disk { center, a1, a2 } => {
                let d = warp::uniform_disk(u);
                (*center + d.x * *a1 + d.y * *a2, a1.cross(*a2).normalize())
            }
            Emitter::Triangle { v } => {
                let b = warp::uniform_triangle(u);
                let p = (1.0 - b.x - b.y) * v[0] + b.x * v[1] + b.y * v[2];
                (p, (v[1] - v[0]).cross(v[2] - v[0]).normalize())
            }
            Emitter::Sphere { center, radius } => {
                let n = warp::uniform_sphere(u);
                (*center + *radius * n, n)
            }
        }
    }

    /// The solid-angle density at `p` of reaching `point` (normal `normal`) by area sampling:
    /// dist² / (|cos θ_light| area). Infinite (returned as `None`) for a grazing point.
    pub fn area_pdf_to_solid_angle(&self, p: Vec3, point: Vec3, normal: Vec3) -> Option<f32> {
        let d = point - p;
        let dist2 = d.length_squared();
        let cos = (normal.dot(d) / dist2.sqrt()).abs();
        (cos > 0.0 && dist2 > 0.0).then(|| dist2 / (cos * self.area()))
    }

    /// A point uniform by area, with the solid-angle density of its direction from `p`.
    pub fn sample_uniform(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        let (point, normal) = self.sample_area(u);
        let pdf = self.area_pdf_to_solid_angle(p, point, normal)?;
        Some(EmitterSample { point, normal, pdf })
    }

    /// A point whose direction from `p` is uniform over the solid angle the emitter
    /// subtends (for a sphere: over the cone of directions to its visible cap). Shapes
    /// with no such method (disks) and polygons too small or far for it fall back to
    /// [`Emitter::sample_uniform`].
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        match self {
            Emitter::Sphere { center, radius } => {
                let to_center = *center - p;
                let dist2 = to_center.length_squared();
                if dist2 <= radius * radius {
                    // Inside the sphere every direction reaches it: fall back to area.
                    return self.sample_uniform(p, u);
                }
                let dist = dist2.sqrt();
                let sin_max2 = radius * radius / dist2;
                let cos_max = (1.0 - sin_max2).max(0.0).sqrt();
                let frame = Frame::from_normal(to_center / dist);
                let w = frame.to_world(warp::uniform_cone(u, cos_max));
                // The nearer intersection of the ray p + t w with the sphere (pbrt-v4's
                // form, stable for small caps): distance along w to the closest point minus
                // half the chord.
                let along = w.dot(to_center);
                let chord = (radius * radius - (dist2 - along * along)).max(0.0).sqrt();
                let point = p + (along - chord) * w;
                let normal = (point - *center).normalize();
                let pdf = 1.0 / (2.0 * PI * (1.0 - cos_max));
                (pdf.is_finite() && cos_max < 1.0).then_some(EmitterSample { point, normal, pdf })
            }
            Emitter::Triangle { v } => {
                let (w, pdf) = match spherical::sample_triangle(p, *v, u) {
                    Some(s) => s,
                    None => return self.sample_uniform(p, u),
                };
                let normal = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
                let t = (v[0] - p).dot(normal) / w.dot(normal);
                Some(EmitterSample {
                    point: p + t * w,
                    normal,
                    pdf,
                })
            }
            Emitter::Quad { corner, e1, e2 } if e1.dot(*e2).abs() <= 1e-5 * e1.length() * e2.length() => {
                match spherical::sample_rectangle(p, *corner, *e1, *e2, u) {
                    Some((point, pdf)) => Some(EmitterSample {
                        point,
                        normal: e1.cross(*e2).normalize(),
                        pdf,
                    }),
                    None => self.sample_uniform(p, u),
                }
            }
            _ => self.sample_uniform(p, u),
        }
    }

    /// The density [`Emitter::sample_solid_angle`] gives the direction from `p` to `point`
    /// (a point of the emitter, normal `normal`): what multiple importance sampling needs
    /// for a direction found another way.
    pub fn solid_angle_pdf(&self, p: Vec3, point: Vec3, normal: Vec3) -> f32 {
        match self {
            Emitter::Sphere { center, radius } => {
                let dist2 = (*center - p).length_squared();
                if dist2 <= radius * radius {
                    return self.area_pdf_to_solid_angle(p, point, normal).unwrap_or(0.0);
                }
                let cos_max = (1.0 - radius * radius / dist2).max(0.0).sqrt();
                1.0 / (2.0 * PI * (1.0 - cos_max))
            }
            Emitter::Triangle { v } => {
                let omega = spherical::triangle_solid_angle(p, *v);
                if omega >= spherical::MIN_SOLID_ANGLE {
                    1.0 / omega
                } else {
                    self.area_pdf_to_solid_angle(p, point, normal).unwrap_or(0.0)
                }
            }
            Emitter::Quad { corner, e1, e2 } if e1.dot(*e2).abs() <= 1e-5 * e1.length() * e2.length() => {
                match spherical::sample_rectangle(p, *corner, *e1, *e2, Vec2::splat(0.5)) {
                    Some((_, pdf)) => pdf,
                    None => self.area_pdf_to_solid_angle(p, point, normal).unwrap_or(0.0),
                }
            }
            _ => self.area_pdf_to_solid_angle(p, point, normal).unwrap_or(0.0),
        }
    }
}
