//! The vertices of bidirectional subpaths and the densities multiple importance sampling
//! needs of them (Veach 1997 chapter 10; pbrt-v4 section 13.3's `Vertex`). Each vertex
//! keeps the area density with which its own subpath produced it (`pdf_fwd`) and the one
//! with which the other subpath's walk would have (`pdf_rev`), both per unit area at the
//! vertex, except at lights at infinity, where they are per unit solid angle.

use crate::bsdfs::{Bsdf, TransportMode};
use crate::lights::{disk_pdf, Light, LightSelection};
use crate::Scene;
use glam::Vec3;
use penumbra_core::ray::offset_origin;
use penumbra_core::{Frame, Ray, Rgb};

/// What a vertex is.
#[derive(Clone, Copy, Debug)]
pub(super) enum Kind<'a> {
    /// A point of the camera's lens (the eye of a pinhole).
    Camera,
    /// Light `index`: where a light path starts, the point a light sample chose, or the
    /// environment a camera path escaped to.
    Light { index: u32 },
    /// A scattering surface, emitting if `light` is its area light.
    Surface {
        bsdf: Bsdf<'a>,
        frame: Frame,
        /// Unit direction towards the previous vertex of the vertex's own subpath.
        wo: Vec3,
        light: Option<u32>,
    },
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex<'a> {
    pub kind: Kind<'a>,
    pub p: Vec3,
    /// The geometric normal of a surface or an area light's point (its front); for the
    /// camera its lens normal; zero for point lights; for lights at infinity, the direction
    /// light travels.
    pub ng: Vec3,
    /// The subpath's throughput up to and including this vertex.
    pub beta: Rgb,
    pub pdf_fwd: f32,
    pub pdf_rev: f32,
    /// Scattered by a delta lobe (or, for the camera, a camera no path can reach).
    pub delta: bool,
    /// At a light at infinity; on a surface (area densities carry a cosine there). Set by
    /// [`Vertex::new`].
    infinite: bool,
    on_surface: bool,
}

impl<'a> Vertex<'a> {
    pub fn new(scene: &Scene, kind: Kind<'a>, p: Vec3, ng: Vec3, beta: Rgb) -> Self {
        let infinite = match kind {
            Kind::Light { index } => scene.lights.lights()[index as usize].is_infinite(),
            _ => false,
        };
        let on_surface = match kind {
            Kind::Surface { .. } => true,
            Kind::Light { .. } => ng != Vec3::ZERO && !infinite,
            Kind::Camera => false,
        };
        Vertex {
            kind,
            p,
            ng,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            infinite,
            on_surface,
        }
    }

    /// The light this vertex is on, if any.
    pub fn light<'s>(&self, scene: &'s Scene) -> Option<(u32, &'s Light)> {
        let index = match self.kind {
            Kind::Light { index } => index,
            Kind::Surface { light: Some(index), .. } => index,
            _ => return None,
        };
        Some((index, &scene.lights.lights()[index as usize]))
    }

    /// At a light at infinity (directional, environment).
    pub fn is_infinite(&self) -> bool {
        self.infinite
    }

    /// On a surface (area densities there carry a cosine).
    pub fn is_on_surface(&self) -> bool {
        self.on_surface
    }

    /// Whether a deterministic connection can be made to this vertex.
    pub fn is_connectible(&self, scene: &Scene) -> bool {
        match self.kind {
            Kind::Camera => !self.delta,
            Kind::Light { .. } => self.light(scene).is_none_or(|(_, l)| l.connectible()),
            Kind::Surface { bsdf, .. } => bsdf.has_smooth(),
        }
    }

    /// The shading normal (the geometric one off surfaces).
    pub fn ns(&self) -> Vec3 {
        match self.kind {
            Kind::Surface { frame, .. } => frame.n,
            _ => self.ng,
        }
    }

    /// Unit direction to `other`, and the squared distance (1 when either is at infinity,
    /// where the direction is the one stored, not rebuilt from far-apart points).
    fn towards(&self, other: &Vertex) -> Option<(Vec3, f32)> {
        if self.infinite {
            return Some((self.ng, 1.0));
        }
        if other.infinite {
            return Some((-other.ng, 1.0));
        }
        let d = other.p - self.p;
        let d2 = d.length_squared();
        (d2 > 0.0 && d2.is_finite()).then(|| (d / d2.sqrt(), d2))
    }

    /// The BSDF value for scattering from the previous vertex towards `next`, times the
    /// shading-normal correction when importance is carried (Veach 1997 section 5.3.6):
    /// zero where the geometric and shading normals disagree about a direction's side.
    pub fn f(&self, next: &Vertex, mode: TransportMode) -> Rgb {
        let Kind::Surface { bsdf, frame, wo, .. } = self.kind else {
            return Rgb::BLACK;
        };
        let Some((wi, _)) = self.towards(next) else {
            return Rgb::BLACK;
        };
        self.scatter(bsdf, &frame, wo, wi, mode)
    }

    /// f(wo, wi) with the correction, for world directions at this surface.
    pub fn scatter(&self, bsdf: Bsdf, frame: &Frame, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        if !(sides_agree(self.ng, frame.n, wo) && sides_agree(self.ng, frame.n, wi)) {
            return Rgb::BLACK;
        }
        let f = bsdf.eval(frame.to_local(wo), frame.to_local(wi), mode);
        match mode {
            TransportMode::Radiance => f,
            TransportMode::Importance => f * shading_correction(self.ng, frame.n, wo, wi),
        }
    }

    /// `pdf` (per unit solid angle at this vertex) as a density per unit area at `next`.
    pub fn convert_density(&self, pdf: f32, next: &Vertex) -> f32 {
        if next.is_infinite() {
            return pdf;
        }
        let Some((w, d2)) = self.towards(next) else {
            return 0.0;
        };
        let cos = if next.is_on_surface() {
            next.ng.dot(w).abs()
        } else {
            1.0
        };
        pdf * cos / d2
    }

    /// The area density at `next` of sampling it from this vertex, arrived at from `prev`,
    /// by a walk carrying `mode` (which some BSDFs' lobe choice depends on).
    pub fn pdf(&self, scene: &Scene, prev: Option<&Vertex>, next: &Vertex, mode: TransportMode) -> f32 {
        if let Kind::Light { .. } = self.kind {
            return self.pdf_light(scene, next);
        }
        let Some((wn, _)) = self.towards(next) else {
            return 0.0;
        };
        let pdf = match self.kind {
            Kind::Camera => scene.camera.image_plane().map_or(0.0, |c| c.pdf_we(self.p, wn).1),
            Kind::Surface { bsdf, frame, .. } => {
                let Some((wp, _)) = prev.and_then(|prev| self.towards(prev)) else {
                    return 0.0;
                };
                bsdf.pdf(frame.to_local(wp), frame.to_local(wn), mode)
            }
            Kind::Light { .. } => unreachable!("handled above"),
        };
        self.convert_density(pdf, next)
    }

    /// The area density at `v` of a light path leaving this vertex's light towards it.
    pub fn pdf_light(&self, scene: &Scene, v: &Vertex) -> f32 {
        let (Some((_, light)), Some((w, d2))) = (self.light(scene), self.towards(v)) else {
            return 0.0;
        };
        let pdf = if self.is_infinite() {
            disk_pdf(scene.sphere)
        } else {
            light.pdf_le(w, self.light_normal(light), scene.sphere).1 / d2
        };
        if v.is_on_surface() {
            pdf * v.ng.dot(w).abs()
        } else {
            pdf
        }
    }

    /// The density with which a light path starts at this vertex (choosing its light, then
    /// the point; for lights at infinity, the direction towards `v`).
    pub fn pdf_light_origin(&self, scene: &Scene, v: &Vertex) -> f32 {
        let (Some((index, light)), Some((w, _))) = (self.light(scene), self.towards(v)) else {
            return 0.0;
        };
        let pick = scene.lights.pmf(LightSelection::Power, index);
        if self.is_infinite() {
            return pick * light.pdf_from_infinity(w);
        }
        pick * light.pdf_le(w, self.light_normal(light), scene.sphere).0
    }

    /// The light's front normal at this vertex.
    fn light_normal(&self, light: &Light) -> Vec3 {
        light.surface_normal(self.p).unwrap_or(self.ng)
    }

    /// Radiance this vertex's light sends towards `v`.
    pub fn le(&self, scene: &Scene, v: &Vertex) -> Rgb {
        let (Some((_, light)), Some((w, _))) = (self.light(scene), self.towards(v)) else {
            return Rgb::BLACK;
        };
        light.emitted(self.p, w)
    }

    /// Where rays towards `target` leave this vertex: pushed off a surface on its side.
    fn origin_towards(&self, target: Vec3) -> Vec3 {
        if !self.is_on_surface() {
            return self.p;
        }
        let n = if self.ng.dot(target - self.p) < 0.0 {
            -self.ng
        } else {
            self.ng
        };
        offset_origin(self.p, n)
    }
}

/// Whether nothing blocks the segment between `a` and `b` (`b` may lie at infinity).
pub(super) fn unoccluded(scene: &Scene, a: &Vertex, b: &Vertex) -> bool {
    if b.infinite {
        // Towards a light at infinity: along its stored direction, without end.
        let dir = -b.ng;
        return !scene.occluded(&Ray::new(a.origin_towards(a.p + dir), dir), f32::INFINITY);
    }
    let from = a.origin_towards(b.p);
    let to = b.origin_towards(a.p);
    !scene.occluded(&Ray::new(from, to - from), super::super::SHADOW_T_MAX)
}

/// The geometry term |cos θa| |cos θb| / d² between two finite vertices (shading normals),
/// without visibility.
pub(super) fn geometry(a: &Vertex, b: &Vertex) -> f32 {
    let Some((w, d2)) = a.towards(b) else {
        return 0.0;
    };
    let mut g = 1.0 / d2;
    for v in [a, b] {
        if v.is_on_surface() {
            g *= v.ns().dot(w).abs();
        }
    }
    g
}

/// Whether `w` lies on the same side of the geometric normal `ng` as of the shading normal
/// `ns` (else light would leak through the surface).
pub(super) fn sides_agree(ng: Vec3, ns: Vec3, w: Vec3) -> bool {
    let (a, b) = (ng.dot(w), ns.dot(w));
    a * b > 0.0
}

/// The factor that makes scattering of importance at shading normals symmetric (Veach
/// 1997, eq. 5.19): |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|).
pub(crate) fn shading_correction(ng: Vec3, ns: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    let den = wo.dot(ng).abs() * wi.dot(ns).abs();
    if den == 0.0 {
        return 0.0;
    }
    wo.dot(ns).abs() * wi.dot(ng).abs() / den
}
