//! The shapes an area light can have, and the ways to pick a point on one: uniformly by
//! area (pbrt-v4 section 6.2 for each shape), or uniformly by the solid angle the shape
//! subtends from the shading point: the cone of directions for a sphere (pbrt-v4 section
//! 6.2.4), spherical triangles (Arvo 1995) and spherical rectangles (Ureña et al. 2013,
//! see [`penumbra_core::spherical`]). Densities are per unit solid angle at the shading
//! point, so every strategy plugs into the same estimator
//! L cos θ / pdf(ω).

use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Real, V3};
use penumbra_core::{spherical, warp, Frame};
use std::f32::consts::PI;

/// The geometry of an emitting surface, in world space.
#[derive(Clone, Debug, PartialEq)]
pub enum EmitterShape {
    /// `corner + s e1 + t e2`, s, t in [0, 1]; front side `e1 x e2`.
    Quad { corner: Vec3, e1: Vec3, e2: Vec3 },
    /// `center + x a1 + y a2`, x² + y² <= 1 (an ellipse under shear); front side `a1 x a2`.
    Disk { center: Vec3, a1: Vec3, a2: Vec3 },
    /// Front side `(v1 - v0) x (v2 - v0)`.
    Triangle { v: [Vec3; 3] },
    /// Emits outwards.
    Sphere { center: Vec3, radius: f32 },
}

/// Below this (in steradians, estimated as area / distance²) adaptive sampling takes a flat
/// emitter by area; see [`Emitter::looks_small`].
pub const SMALL_SOLID_ANGLE: f32 = 0.3;

/// An emitting surface with what sampling needs of it worked out once, at scene setup.
#[derive(Clone, Debug, PartialEq)]
pub struct Emitter {
    shape: EmitterShape,
    area: f32,
    /// Unit front normal of a planar shape (zero for a sphere).
    normal: Vec3,
    /// A quad with perpendicular edges, which is sampled as a spherical rectangle.
    rectangle: bool,
    /// Centre of a flat shape, for [`Emitter::looks_small`] (`None` for spheres).
    centroid: Option<Vec3>,
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
    /// `None` for a shape without area (or with non-finite area).
    pub fn new(shape: EmitterShape) -> Option<Self> {
        let (area, front) = match &shape {
            EmitterShape::Quad { e1, e2, .. } => (e1.cross(*e2).length(), e1.cross(*e2)),
            EmitterShape::Disk { a1, a2, .. } => (PI * a1.cross(*a2).length(), a1.cross(*a2)),
            EmitterShape::Triangle { v } => {
                let n = (v[1] - v[0]).cross(v[2] - v[0]);
                (0.5 * n.length(), n)
            }
            EmitterShape::Sphere { radius, .. } => (4.0 * PI * radius * radius, Vec3::ZERO),
        };
        if !(area.is_finite() && area > 0.0) {
            return None;
        }
        let rectangle = matches!(&shape, EmitterShape::Quad { e1, e2, .. }
            if e1.dot(*e2).abs() <= 1e-5 * e1.length() * e2.length());
        let centroid = match &shape {
            EmitterShape::Triangle { v } => Some((v[0] + v[1] + v[2]) / 3.0),
            EmitterShape::Quad { corner, e1, e2 } => Some(*corner + 0.5 * (*e1 + *e2)),
            _ => None,
        };
        Some(Emitter {
            normal: front.normalize_or_zero(),
            shape,
            area,
            rectangle,
            centroid,
        })
    }

    /// The nearest point (either side) where the ray from `p` along `w` meets the surface,
    /// with the front normal there: for densities of directions found by other means.
    pub fn intersect(&self, p: Vec3, w: Vec3) -> Option<(Vec3, Vec3)> {
        // The plane through `o` spanned by `a` and `b`, at coordinates inside `inside`.
        let plane = |o: Vec3, a: Vec3, b: Vec3, inside: &dyn Fn(f32, f32) -> bool| {
            let n = a.cross(b);
            let t = (o - p).dot(n) / w.dot(n);
            if !(t > 0.0 && t.is_finite()) {
                return None;
            }
            let q = p + t * w;
            let d = q - o;
            let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
            let (da, db) = (d.dot(a), d.dot(b));
            let det = aa * bb - ab * ab;
            inside((bb * da - ab * db) / det, (aa * db - ab * da) / det).then(|| (q, n.normalize()))
        };
        match &self.shape {
            EmitterShape::Quad { corner, e1, e2 } => plane(*corner, *e1, *e2, &|s, t| {
                (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)
            }),
            EmitterShape::Disk { center, a1, a2 } => plane(*center, *a1, *a2, &|x, y| x * x + y * y <= 1.0),
            EmitterShape::Triangle { v } => plane(v[0], v[1] - v[0], v[2] - v[0], &|s, t| {
                s >= 0.0 && t >= 0.0 && s + t <= 1.0
            }),
            EmitterShape::Sphere { center, radius } => {
                let oc = p - *center;
                let b = oc.dot(w);
                let disc = b * b - (oc.length_squared() - radius * radius);
                if disc < 0.0 {
                    return None;
                }
                let root = disc.sqrt();
                let t = if -b - root > 0.0 { -b - root } else { -b + root };
                (t > 0.0).then(|| {
                    let q = p + t * w;
                    (q, (q - *center) / *radius)
                })
            }
        }
    }

    pub fn shape(&self) -> &EmitterShape {
        &self.shape
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    /// A triangle's corners, unit front normal and centroid (for the lane kernels, which
    /// sample triangles by area); `None` for other shapes.
    pub fn triangle_parts(&self) -> Option<([Vec3; 3], Vec3, Vec3)> {
        match (&self.shape, self.centroid) {
            (EmitterShape::Triangle { v }, Some(c)) => Some((*v, self.normal, c)),
            _ => None,
        }
    }

    /// The unit front normal at `point`, a point of the emitter.
    pub fn normal_at(&self, point: Vec3) -> Vec3 {
        match &self.shape {
            EmitterShape::Sphere { center, .. } => (point - *center).normalize_or_zero(),
            _ => self.normal,
        }
    }

    /// A point uniform by area, and its unit normal; density 1 / area per unit area.
    pub fn sample_area(&self, u: Vec2) -> (Vec3, Vec3) {
        let (point, normal) = self.sample_area_lanes(u.x, u.y);
        (point.into(), normal.into())
    }

    /// [`Emitter::sample_area`] per lane of any [`Real`] type, for lanes sharing this
    /// emitter (pbrt-v4 section 6.2 for each shape).
    #[inline(always)]
    pub fn sample_area_lanes<R: Real>(&self, ux: R, uy: R) -> (V3<R>, V3<R>) {
        let normal = V3::splat_vec(self.normal);
        match &self.shape {
            EmitterShape::Quad { corner, e1, e2 } => (
                V3::splat_vec(*corner) + V3::splat_vec(*e1).scale(ux) + V3::splat_vec(*e2).scale(uy),
                normal,
            ),
            EmitterShape::Disk { center, a1, a2 } => {
                let (x, y) = warp::uniform_disk_lanes(ux, uy);
                (
                    V3::splat_vec(*center) + V3::splat_vec(*a1).scale(x) + V3::splat_vec(*a2).scale(y),
                    normal,
                )
            }
            EmitterShape::Triangle { v } => {
                let (b1, b2) = warp::uniform_triangle_lanes(ux, uy);
                let corners = [V3::splat_vec(v[0]), V3::splat_vec(v[1]), V3::splat_vec(v[2])];
                (triangle_point(corners, b1, b2), normal)
            }
            EmitterShape::Sphere { center, radius } => {
                let n = warp::uniform_sphere_lanes(ux, uy);
                (V3::splat_vec(*center) + n.scale(R::splat(*radius)), n)
            }
        }
    }

    /// The solid-angle density at `p` of reaching `point` (normal `normal`) by area sampling:
    /// dist² / (|cos θ_light| area). Infinite (returned as `None`) for a grazing point.
    pub fn area_pdf_to_solid_angle(&self, p: Vec3, point: Vec3, normal: Vec3) -> Option<f32> {
        let (pdf, ok) = area_to_solid_angle(p.into(), point.into(), normal.into(), self.area);
        ok.then_some(pdf)
    }

    /// A point uniform by area, with the solid-angle density of its direction from `p`.
    pub fn sample_uniform(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        let (point, normal, pdf, ok) = self.sample_uniform_lanes(p.into(), u.x, u.y);
        ok.then(|| EmitterSample {
            point: point.into(),
            normal: normal.into(),
            pdf,
        })
    }

    /// [`Emitter::sample_uniform`] per lane of any [`Real`] type, for lanes sharing this
    /// emitter: the point, its normal, the density, and where the density is defined.
    #[inline(always)]
    pub fn sample_uniform_lanes<R: Real>(&self, p: V3<R>, ux: R, uy: R) -> (V3<R>, V3<R>, R, R::Mask) {
        let (point, normal) = self.sample_area_lanes(ux, uy);
        let (pdf, ok) = area_to_solid_angle(p, point, normal, R::splat(self.area));
        (point, normal, pdf, ok)
    }

    /// For a sphere seen from outside (not from its surface): the cosine of the half-angle of
    /// the cone it fills.
    fn cone_cos_max(&self, p: Vec3) -> Option<f32> {
        let EmitterShape::Sphere { center, radius } = &self.shape else {
            return None;
        };
        let dist2 = (*center - p).length_squared();
        let cos_max = (1.0 - radius * radius / dist2).max(0.0).sqrt();
        // Points on the surface itself (a shading point on the sphere, inside or out) are
        // not "outside": rounding could put them on either side, and the cone from the
        // surface degenerates to a hemisphere whose nearer intersection is the point itself.
        (dist2 > radius * radius * (1.0 + 1e-3) && cos_max < 1.0).then_some(cos_max)
    }

    /// Whether [`Emitter::sample_solid_angle`] samples the solid angle from `p`, and if so
    /// its (constant) density there; `None` means it falls back to area sampling: disks and
    /// sheared quads, a point inside a sphere, polygons too small or far to sample well.
    fn solid_angle_density(&self, p: Vec3) -> Option<f32> {
        let omega = match &self.shape {
            EmitterShape::Sphere { .. } => 2.0 * PI * (1.0 - self.cone_cos_max(p)?),
            EmitterShape::Triangle { v } => spherical::triangle_solid_angle(p, *v),
            EmitterShape::Quad { corner, e1, e2 } if self.rectangle => {
                spherical::rectangle_solid_angle(p, *corner, *e1, *e2)
            }
            _ => return None,
        };
        (omega >= spherical::MIN_SOLID_ANGLE).then(|| 1.0 / omega)
    }

    /// Whether a flat emitter subtends so little from `p` (area / distance² to its centroid
    /// below [`SMALL_SOLID_ANGLE`]) that spherical sampling, which costs inverse
    /// trigonometry in double precision, would barely beat area sampling: cos θ and 1/r²
    /// hardly vary over it. (Spheres keep their cheap cone sampling.)
    pub fn looks_small(&self, p: Vec3) -> bool {
        self.centroid
            .is_some_and(|c| self.area < SMALL_SOLID_ANGLE * (c - p).length_squared())
    }

    /// A point whose direction from `p` is uniform over the solid angle the emitter
    /// subtends (for a sphere: over the cone of directions to its visible cap), or by area
    /// where the shape or view has no such method (see `solid_angle_density`).
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        // Area sampling only where the density says so; a failed spherical sample is a lost
        // sample, so that `solid_angle_pdf` stays the density of this routine.
        let Some(pdf) = self.solid_angle_density(p) else {
            return self.sample_uniform(p, u);
        };
        match &self.shape {
            EmitterShape::Sphere { center, radius } => {
                let to_center = *center - p;
                let cos_max = self.cone_cos_max(p)?;
                let w = Frame::from_normal(to_center.normalize()).to_world(warp::uniform_cone(u, cos_max));
                // The nearer intersection of p + t w with the sphere: distance along w to
                // the point closest to the centre, minus half the chord.
                let along = w.dot(to_center);
                let chord = (radius * radius - (to_center.length_squared() - along * along))
                    .max(0.0)
                    .sqrt();
                let point = p + (along - chord) * w;
                Some(EmitterSample {
                    point,
                    normal: (point - *center).normalize(),
                    pdf,
                })
            }
            EmitterShape::Triangle { v } => spherical::sample_triangle(p, *v, u).map(|(w, pdf)| {
                let t = (v[0] - p).dot(self.normal) / w.dot(self.normal);
                EmitterSample {
                    point: p + t * w,
                    normal: self.normal,
                    pdf,
                }
            }),
            EmitterShape::Quad { corner, e1, e2 } => {
                spherical::sample_rectangle(p, *corner, *e1, *e2, u).map(|(point, pdf)| EmitterSample {
                    point,
                    normal: self.normal,
                    pdf,
                })
            }
            // Disks have no solid-angle density: handled above.
            EmitterShape::Disk { .. } => None,
        }
    }

    /// The density [`Emitter::sample_solid_angle`] gives the direction from `p` to `point`
    /// (a point of the emitter, normal `normal`): what multiple importance sampling needs
    /// for a direction found another way.
    pub fn solid_angle_pdf(&self, p: Vec3, point: Vec3, normal: Vec3) -> f32 {
        self.solid_angle_density(p)
            .or_else(|| self.area_pdf_to_solid_angle(p, point, normal))
            .unwrap_or(0.0)
    }
}

/// The point of barycentric coordinates `(b1, b2)` on triangle `v`:
/// (1 - b1 - b2) v0 + b1 v1 + b2 v2, for lanes of any [`Real`] type.
#[inline(always)]
pub fn triangle_point<R: Real>(v: [V3<R>; 3], b1: R, b2: R) -> V3<R> {
    v[0].scale(R::splat(1.0) - b1 - b2) + v[1].scale(b1) + v[2].scale(b2)
}

/// The solid-angle density at `p` of reaching `point` (normal `normal`) on an emitter of
/// area `area` sampled uniformly by area: dist² / (|cos θ_light| area), and where it is
/// defined (not at grazing angles or at `p` itself), for lanes of any [`Real`] type.
#[inline(always)]
pub fn area_to_solid_angle<R: Real>(p: V3<R>, point: V3<R>, normal: V3<R>, area: R) -> (R, R::Mask) {
    let d = point - p;
    let dist2 = d.dot(d);
    let cos = (normal.dot(d) / dist2.sqrt()).abs();
    let zero = R::splat(0.0);
    (dist2 / (cos * area), R::and(cos.cmp_gt(zero), dist2.cmp_gt(zero)))
}
