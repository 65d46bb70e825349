//! The path tracer's bounce at a Lambertian surface lit by triangle lights or the
//! environment, written once for lanes of any [`Real`] type, so that eight paths take it in
//! one pass of AVX instructions ([`F8`](penumbra_core::lanes::F8)): the shading frame, a
//! light sample (a triangle's point by area, or the environment's direction by
//! [`EnvironmentLanes`]) with its MIS weight (power heuristic against the cosine-weighted
//! BSDF density, Veach and Guibas 1995), and the cosine-weighted continuation (Malley's
//! method).
//!
//! Every step performs the IEEE operations of the scalar path ([`super::nee::Shading`],
//! [`super::nee::light_sample`], `Bsdf::sample` of a [`Diffuse`](crate::bsdfs::Diffuse)
//! BSDF and [`super::path`]'s continuation) in their order, branches turned into masks, so
//! each lane's result is bit for bit what the scalar code gives that path.
//! `diffuse_lanes_equal_the_scalar_bounce` in `tests/path.rs` holds it to that.

use super::{nee, MisHeuristic};
use crate::bsdfs::{DiffuseLanes, LaneKernel};
use crate::lights::emitter::SMALL_SOLID_ANGLE;
use crate::lights::{EnvironmentLanes, LaneLightSample, LightKernel, TriangleByArea};
use penumbra_core::frame::Basis;
use penumbra_core::lanes::{Real, V3};

/// A path at a Lambertian surface.
#[derive(Clone, Copy)]
pub(super) struct DiffuseHit<R: Real> {
    pub p: V3<R>,
    /// The geometric normal as the surface gives it (not yet turned towards `wo`).
    pub ng: V3<R>,
    pub ns: V3<R>,
    pub dpdu: V3<R>,
    /// Unit direction back along the ray, world space.
    pub wo: V3<R>,
    pub reflectance: V3<R>,
    /// Mitsuba's `twosided`: the back reflects like the front.
    pub two_sided: R::Mask,
    /// The path throughput up to this surface.
    pub beta: V3<R>,
}

/// The triangle light a path picked, with its probability.
#[derive(Clone, Copy)]
pub(super) struct TriangleLight<R: Real> {
    pub triangle: TriangleByArea<R>,
    pub centroid: V3<R>,
    pub p_pick: R,
}

/// A light sample: where its shadow ray may go, and what it brings (the throughput
/// included) if nothing blocks it.
pub(super) struct LightOut<R: Real> {
    /// The light looks small from the shading point, so the scalar path samples it by
    /// area as this does, or it is the environment; elsewhere (`false`) the lane's sample
    /// must be taken by [`super::nee::light_sample`], by solid angle.
    pub by_area: R::Mask,
    /// A sample that brings light if unblocked (only meaningful where `by_area`).
    pub ok: R::Mask,
    pub origin: V3<R>,
    /// Shadow ray direction: from `origin` to the point on the light (not unit).
    pub dir: V3<R>,
    pub value: V3<R>,
}

/// The continuation: the next ray and what the path carries along it.
pub(super) struct ContinuationOut<R: Real> {
    pub ok: R::Mask,
    pub origin: V3<R>,
    pub dir: V3<R>,
    /// Solid-angle density of `dir` (for MIS at the emitter it reaches).
    pub pdf: R,
    /// The throughput times f cos θ / pdf (the reflectance).
    pub beta: V3<R>,
}

/// [`super::nee::Shading`] of a Lambertian surface: its geometry
/// ([`nee::ShadingGeometry`]: frame, `wo` in it, the geometric normal on `wo`'s side, the
/// offset origin), the point, and the sidedness.
struct Shading<R: Real> {
    frame: Basis<R>,
    wo: V3<R>,
    ng: V3<R>,
    origin: V3<R>,
    p: V3<R>,
    /// The BSDF works on directions mirrored to the front (two-sided, seen from behind).
    mirrored: R::Mask,
}

impl<R: Real> Shading<R> {
    #[inline(always)]
    fn new(h: &DiffuseHit<R>) -> Self {
        // A plain Lambertian material has no normal map: `Material::shading_frame`'s frame.
        let g = nee::ShadingGeometry::new(h.p, h.ng, h.wo, Basis::from_normal_tangent(h.ns, h.dpdu));
        Shading {
            frame: g.frame,
            wo: g.wo,
            ng: g.ng,
            origin: g.origin,
            p: h.p,
            mirrored: R::and(h.two_sided, g.wo.z.cmp_lt(R::splat(0.0))),
        }
    }

    /// [`super::nee::Shading::agrees`].
    #[inline(always)]
    fn agrees(&self, wi: V3<R>, l: V3<R>) -> R::Mask {
        nee::agrees(self.ng, self.wo.z, wi, l)
    }

    /// [`super::nee::Shading::origin_towards`].
    #[inline(always)]
    fn origin_towards(&self, wi: V3<R>) -> V3<R> {
        nee::origin_towards(self.ng, self.origin, self.p, wi)
    }

    /// A local direction as the (mirrored) BSDF sees it, and back: z flipped where the
    /// surface is two-sided and seen from behind.
    #[inline(always)]
    fn bsdf_dir(&self, w: V3<R>) -> V3<R> {
        V3::new(w.x, w.y, R::select(self.mirrored, -w.z, w.z))
    }
}

/// Where every component is finite.
#[inline(always)]
fn is_finite<R: Real>(v: V3<R>) -> R::Mask {
    let inf = R::splat(f32::INFINITY);
    R::and(
        R::and(v.x.abs().cmp_lt(inf), v.y.abs().cmp_lt(inf)),
        v.z.abs().cmp_lt(inf),
    )
}

/// One bounce: the light sample from `u_light` on `light` (area sampling, MIS weight
/// against the BSDF), or where `env`'s lanes say so on the environment, and the
/// continuation from `u_dir`.
#[inline(always)]
pub(super) fn bounce<R: Real>(
    h: &DiffuseHit<R>,
    light: &TriangleLight<R>,
    env: Option<(&EnvironmentLanes, R::Mask)>,
    u_light: (R, R),
    u_dir: (R, R),
) -> (LightOut<R>, ContinuationOut<R>) {
    let sh = Shading::new(h);
    let mut lo = light_sample(h, &sh, light, u_light);
    // (No closure here: one would be compiled apart from the kernel's SIMD level.)
    if let Some((env, lanes)) = env {
        if R::any(lanes) {
            let e = environment_sample(h, &sh, env, light.p_pick, u_light);
            lo = LightOut {
                by_area: R::select_mask(lanes, e.by_area, lo.by_area),
                ok: R::select_mask(lanes, e.ok, lo.ok),
                origin: V3::select(lanes, e.origin, lo.origin),
                dir: V3::select(lanes, e.dir, lo.dir),
                value: V3::select(lanes, e.value, lo.value),
            };
        }
    }
    (lo, continuation(h, &sh, u_dir))
}

#[inline(always)]
fn light_sample<R: Real>(h: &DiffuseHit<R>, sh: &Shading<R>, light: &TriangleLight<R>, u: (R, R)) -> LightOut<R> {
    let to_centroid = light.centroid - sh.origin;
    let by_area = light
        .triangle
        .area
        .cmp_lt(R::splat(SMALL_SOLID_ANGLE) * to_centroid.dot(to_centroid));

    // The scalar area light's sample by area (`AreaLight::sample_li`'s one-lane instance).
    let sample = light.triangle.sample_li(sh.origin, u);
    let (wi, dist) = (sample.wi, sample.dist);
    let out = lit_by(h, sh, &sample, light.p_pick);
    // The shadow ray runs to the light's point.
    let target = out.origin + wi.scale(dist);
    LightOut {
        by_area,
        dir: target - out.origin,
        ..out
    }
}

/// The light sample of the environment `env`, picked with probability `p_pick`
/// (`Environment::sample_li`'s arithmetic, [`EnvironmentLanes`]); `by_area` is set.
#[inline(always)]
fn environment_sample<R: Real>(
    h: &DiffuseHit<R>,
    sh: &Shading<R>,
    env: &EnvironmentLanes,
    p_pick: R,
    u: (R, R),
) -> LightOut<R> {
    let sample = env.sample_li(V3::splat(0.0), u);
    LightOut {
        by_area: R::splat_mask(true),
        ..lit_by(h, sh, &sample, p_pick)
    }
}

/// What the light `s` (picked with probability `p_pick`) brings to `h` if unblocked:
/// `nee::light_sample`'s steps, the BSDF's value and density towards it (in the frame the
/// BSDF sees: mirrored where two-sided from behind) and the MIS weight, and its shadow
/// ray along `wi` (as for a light at infinity; a light at a finite distance sets its own
/// `dir`, to its point).
#[inline(always)]
fn lit_by<R: Real>(h: &DiffuseHit<R>, sh: &Shading<R>, s: &LaneLightSample<R>, p_pick: R) -> LightOut<R> {
    let one = R::splat(1.0);
    let (wi, li) = (s.wi, s.li);
    let l = sh.frame.to_local(wi);
    let (bwo, bl) = (sh.bsdf_dir(sh.wo), sh.bsdf_dir(l));
    let bsdf = DiffuseLanes::new(h.reflectance);
    let f_cos = bsdf.eval(bwo, bl).scale(l.z.abs());
    let origin = sh.origin_towards(wi);
    let p_bsdf = bsdf.pdf(bwo, bl);
    let mis = Some((MisHeuristic::Power, one, p_bsdf));
    let value = nee::light_value_lanes(f_cos, li, (p_pick, s.pdf, one), mis);

    let ok = R::and(
        R::and(s.ok, R::and(R::not(li.is_black()), is_finite(wi))),
        R::and(sh.agrees(wi, l), R::not(f_cos.is_black())),
    );
    LightOut {
        by_area: R::splat_mask(false),
        ok,
        origin,
        dir: wi,
        value: h.beta.mul_each(value),
    }
}

#[inline(always)]
fn continuation<R: Real>(h: &DiffuseHit<R>, sh: &Shading<R>, u: (R, R)) -> ContinuationOut<R> {
    // `Diffuse::sample` on the mirrored side, then flipped back.
    let bsdf = DiffuseLanes::new(h.reflectance);
    let s = bsdf.sample(sh.bsdf_dir(sh.wo), R::splat(0.0), u);
    let local = sh.bsdf_dir(s.wi);
    let wi = sh.frame.to_world(local);
    ContinuationOut {
        ok: R::and(s.ok, sh.agrees(wi, local)),
        origin: sh.origin_towards(wi),
        dir: wi,
        pdf: s.pdf,
        beta: h.beta.mul_each(s.weight),
    }
}
