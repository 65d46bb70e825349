//! Next-event estimation, shared by the `direct` and `path` integrators: a shadow ray to a
//! point chosen on a light, and the multiple-importance weights (Veach and Guibas 1995)
//! that combine it with BSDF sampling.

use super::{shadow_ray, MisHeuristic, RayCounts};
use crate::bsdfs::{Bsdf, TransportMode};
use crate::lights::environment::MapPoint;
use crate::lights::{AreaLight, AreaSampling, Environment, LightSample, LightSelection};
use crate::{Interaction, Scene};
use glam::{Vec2, Vec3};
use penumbra_core::frame::Basis;
use penumbra_core::lanes::{Real, V3};
use penumbra_core::ray::offset_origin_lanes;
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{Frame, Ray, Rgb};

/// A shading point: the surface, its BSDF in the shading frame, and where rays leave from.
pub(super) struct Shading<'a> {
    pub it: &'a Interaction<'a>,
    pub bsdf: Bsdf<'a>,
    /// The shading frame (z = the shading normal, unflipped).
    pub frame: Frame,
    /// The direction towards the viewer in the shading frame.
    pub wo: Vec3,
    /// The geometric normal on the side of `wo`.
    pub ng: Vec3,
    /// Where lights are seen from: the surface point pushed off the surface on the side of
    /// `wo`, the origin of every shadow and reflected ray. Sampling lights from the raw hit
    /// point would let a point on an emitter (its back, say) land on the emitting side by
    /// rounding and be lit by its own surface at full strength.
    pub origin: Vec3,
}

/// What a shading point's geometry gives, per lane of any [`Real`] type: the shading
/// frame, `wo` in it, the geometric normal turned to `wo`'s side and the offset origin of
/// rays leaving it (see [`Shading`]); the scalar [`Shading`] and the path tracer's
/// eight-lane bounce both take theirs from [`ShadingGeometry::new`].
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadingGeometry<R: Real> {
    pub frame: Basis<R>,
    pub wo: V3<R>,
    pub ng: V3<R>,
    pub origin: V3<R>,
}

impl<R: Real> ShadingGeometry<R> {
    /// The geometry at point `p` of geometric normal `ng` (either side), seen along the
    /// world direction `wo`, in the shading frame `frame`.
    #[inline(always)]
    pub fn new(p: V3<R>, ng: V3<R>, wo: V3<R>, frame: Basis<R>) -> Self {
        let ng = V3::select(ng.dot(wo).cmp_lt(R::splat(0.0)), -ng, ng);
        ShadingGeometry {
            frame,
            wo: frame.to_local(wo),
            ng,
            origin: offset_origin_lanes(p, ng),
        }
    }
}

impl<'a> Shading<'a> {
    pub fn new(it: &'a Interaction<'a>) -> Self {
        let sf = &it.surface;
        let frame = it
            .material
            .shading_frame_lanes(sf.ns.into(), sf.dpdu.into(), sf.uv.x, sf.uv.y);
        let g = ShadingGeometry::new(it.surface.p.into(), it.surface.ng.into(), it.wo.into(), frame);
        Shading {
            it,
            bsdf: it.material.bsdf(it.surface.uv),
            frame: g.frame.into(),
            wo: g.wo.into(),
            ng: g.ng.into(),
            origin: g.origin.into(),
        }
    }

    /// Whether the geometric and the shading normal agree on whether `wi` (world; `l` in
    /// the shading frame) is reflected or transmitted (else light would leak through).
    pub fn agrees(&self, wi: Vec3, l: Vec3) -> bool {
        agrees(self.ng.into(), self.wo.z, wi.into(), l.into())
    }

    /// `wi` in the shading frame, when the normals agree on it (see [`Shading::agrees`]).
    pub fn local(&self, wi: Vec3) -> Option<Vec3> {
        let l = self.frame.to_local(wi);
        self.agrees(wi, l).then_some(l)
    }

    /// Where a ray in direction `wi` leaves from: the point pushed off the surface on `wi`'s side.
    pub fn origin_towards(&self, wi: Vec3) -> Vec3 {
        origin_towards(self.ng.into(), self.origin.into(), self.it.surface.p.into(), wi.into()).into()
    }
}

/// [`Shading::agrees`] for lanes of any [`Real`] type: `ng` the geometric normal on the
/// side of `wo`, `wo_z` the z of `wo` in the shading frame.
#[inline(always)]
pub(super) fn agrees<R: Real>(ng: V3<R>, wo_z: R, wi: V3<R>, l: V3<R>) -> R::Mask {
    let zero = R::splat(0.0);
    let (reflected, local_reflected) = (ng.dot(wi).cmp_gt(zero), (l.z * wo_z).cmp_gt(zero));
    let same = R::or(
        R::and(reflected, local_reflected),
        R::and(R::not(reflected), R::not(local_reflected)),
    );
    R::and(R::not(l.z.cmp_eq(zero)), same)
}

/// [`Shading::origin_towards`] for lanes of any [`Real`] type: `origin` is the surface
/// point `p` pushed off along `ng` (the normal on the side of `wo`).
#[inline(always)]
pub(super) fn origin_towards<R: Real>(ng: V3<R>, origin: V3<R>, p: V3<R>, wi: V3<R>) -> V3<R> {
    let front = R::splat(0.0).cmp_le(ng.dot(wi));
    V3::select(front, origin, offset_origin_lanes(p, -ng))
}

/// How the light samples of one shading point are drawn and weighted.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightStrategy {
    pub sampling: AreaSampling,
    /// Light samples taken for the light's strategy (the batch).
    pub samples: f32,
    /// MIS against this many BSDF samples, or no MIS.
    pub mis: Option<(MisHeuristic, f32)>,
}

/// A light sample whose visibility is still to be tested: the shadow ray, and what the
/// sample brings if nothing blocks it.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadowTest {
    pub ray: Ray,
    pub t_max: f32,
    pub value: Rgb,
}

impl ShadowTest {
    /// The sample's value with its shadow ray traced (and counted).
    pub fn trace(&self, scene: &Scene, counts: &mut RayCounts) -> Rgb {
        counts.shadow += 1;
        if scene.occluded(&self.ray, self.t_max) {
            Rgb::BLACK
        } else {
            self.value
        }
    }
}

/// One light-sampling estimate for light `index`, picked with probability `p_pick`:
/// f L cos θ V / (p_pick pdf samples), MIS-weighted against BSDF sampling when asked, with
/// the visibility V still to be tested ([`ShadowTest::trace`]); `None` when the sample
/// brings nothing whatever the visibility. [`light_point`], the BSDF's value and
/// density towards it, then [`LightPoint::finish`].
pub(super) fn light_sample(
    scene: &Scene,
    sh: &Shading,
    index: u32,
    p_pick: f32,
    u: Vec2,
    strategy: &LightStrategy,
) -> Option<ShadowTest> {
    let lp = light_point(scene, sh, (index, p_pick), u, strategy.sampling)?;
    let f = sh.bsdf.eval(sh.wo, lp.l, TransportMode::Radiance);
    let p_bsdf = || sh.bsdf.pdf(sh.wo, lp.l, TransportMode::Radiance);
    lp.finish(f, p_bsdf, strategy)
}

/// A light sample before the BSDF is asked about it: the direction in the shading frame,
/// the light's sample, the shadow ray.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightPoint {
    /// The direction to the light in the shading frame.
    pub l: Vec3,
    pub ls: LightSample,
    pub p_pick: f32,
    pub ray: Ray,
    pub t_max: f32,
}

/// The first half of [`light_sample`]: the point on light `index` (picked with
/// probability `p_pick`), where it brings light and the normals agree on its side.
pub(super) fn light_point(
    scene: &Scene,
    sh: &Shading,
    (index, p_pick): (u32, f32),
    u: Vec2,
    sampling: AreaSampling,
) -> Option<LightPoint> {
    let light = &scene.lights.lights()[index as usize];
    LightPoint::new(sh, light.sample_li(sh.origin, u, sampling)?, p_pick)
}

impl LightPoint {
    /// [`light_point`] from the light's sample `ls` at `sh.origin`, however it was taken.
    pub fn new(sh: &Shading, ls: LightSample, p_pick: f32) -> Option<LightPoint> {
        if ls.li.is_black() || !ls.wi.is_finite() {
            return None;
        }
        let l = sh.local(ls.wi)?;
        let (ray, t_max) = shadow_ray(sh.origin_towards(ls.wi), &ls);
        Some(LightPoint {
            l,
            ls,
            p_pick,
            ray,
            t_max,
        })
    }

    /// The second half of [`light_sample`], given the BSDF's value `f` towards the light
    /// and its density (asked for only when weighed).
    pub fn finish(&self, f: Rgb, p_bsdf: impl FnOnce() -> f32, strategy: &LightStrategy) -> Option<ShadowTest> {
        let (ls, p_pick) = (&self.ls, self.p_pick);
        let f_cos = f * self.l.z.abs();
        if f_cos.is_black() {
            return None;
        }
        let mis = match strategy.mis {
            Some((heuristic, n_bsdf)) if !ls.delta => Some((heuristic, n_bsdf, p_bsdf())),
            _ => None,
        };
        let odds = (p_pick, ls.pdf, strategy.samples);
        Some(ShadowTest {
            ray: self.ray,
            t_max: self.t_max,
            value: light_value_lanes(V3::from(f_cos), V3::from(ls.li), odds, mis).into(),
        })
    }
}

/// [`LightPoint::finish`]'s value per lane of any [`Real`] type and payload: f |cos θ|
/// (`f_cos`) times the light `li` over the sample's probability (`p_pick` × `pdf` ×
/// `samples`, the odds), weighted by `mis` (heuristic, BSDF sample count, BSDF density)
/// against BSDF sampling, or not weighted. The scalar estimate is its one-lane instance;
/// the path tracer's eight-lane bounce computes its light samples' values by it.
#[inline(always)]
pub(super) fn light_value_lanes<R: Real, S: Spectrum<R>>(
    f_cos: S,
    li: S,
    (p_pick, pdf, samples): (R, R, R),
    mis: Option<(MisHeuristic, R, R)>,
) -> S {
    let weight = match mis {
        Some((heuristic, n_bsdf, p_bsdf)) => heuristic.weight_lanes(samples * p_pick * pdf, n_bsdf * p_bsdf),
        None => R::splat(1.0),
    };
    f_cos.mul_each(li).scale(weight / (p_pick * pdf * samples))
}

/// The MIS weight of a BSDF sample (density `n_bsdf` x `p_bsdf`) that left the scene in
/// direction `dir` and met the environment light `index`, against `n_light` light samples
/// per shading point with lights chosen by `selection`.
pub(super) fn environment_weight(
    scene: &Scene,
    (selection, heuristic): (LightSelection, MisHeuristic),
    (index, env): (u32, &Environment),
    at: &MapPoint,
    (n_bsdf, p_bsdf): (f32, f32),
    n_light: f32,
) -> f32 {
    let p_light = scene.lights.pmf(selection, index) * env.pdf_at(at);
    heuristic.weight(n_bsdf * p_bsdf, n_light * p_light)
}

/// The MIS weight of a BSDF sample from `p` (density `n_bsdf` x `p_bsdf`) that reached
/// `point` (normal `normal`) on area light `index`, against the light strategy of
/// `n_light` samples by `sampling` per shading point with lights chosen by `selection`.
#[allow(clippy::too_many_arguments)]
pub(super) fn emitter_weight(
    scene: &Scene,
    (selection, sampling): (LightSelection, AreaSampling),
    heuristic: MisHeuristic,
    p: Vec3,
    (index, light): (u32, &AreaLight),
    point: Vec3,
    normal: Vec3,
    (n_bsdf, p_bsdf): (f32, f32),
    n_light: f32,
) -> f32 {
    let p_pick = scene.lights.pmf(selection, index);
    let p_light = light.pdf(p, point, normal, sampling);
    heuristic.weight(n_bsdf * p_bsdf, n_light * p_pick * p_light)
}

/// How a BSDF sample that reaches a light is weighted against light sampling: lights
/// picked by `selection`, area lights sampled by `sampling`, `n_bsdf` BSDF and `n_light`
/// light samples per shading point, combined by `heuristic`.
#[derive(Clone, Copy, Debug)]
pub(super) struct BsdfMis {
    pub selection: LightSelection,
    pub sampling: AreaSampling,
    pub heuristic: MisHeuristic,
    pub n_bsdf: f32,
    pub n_light: f32,
}

/// One BSDF-sampling estimate of direct light at `sh` (delta lobes left to the specular
/// rays): f cos / pdf times the radiance of the area light or environment its ray meets,
/// weighted by `mis` when given (else 1); a ray that leaves a scene without an environment
/// brings the background when `background`.
pub(super) fn bsdf_light_sample(
    scene: &Scene,
    sh: &Shading,
    (u_lobe, u): (f32, Vec2),
    mis: Option<BsdfMis>,
    background: bool,
    counts: &mut RayCounts,
) -> Rgb {
    let Some(bs) = sh
        .bsdf
        .sample(sh.wo, u_lobe, u, TransportMode::Radiance)
        .filter(|s| !s.delta)
    else {
        return Rgb::BLACK;
    };
    let wi = sh.frame.to_world(bs.wi);
    if !sh.agrees(wi, bs.wi) {
        return Rgb::BLACK;
    }
    counts.secondary += 1;
    let origin = sh.origin_towards(wi);
    let Some(hit) = scene.intersect(&Ray::new(origin, wi), f32::INFINITY) else {
        let Some(env) = scene.environment() else {
            return if background {
                bs.weight * scene.background
            } else {
                Rgb::BLACK
            };
        };
        let at = env.1.lookup(wi);
        let weight = mis.map_or(1.0, |m| {
            environment_weight(
                scene,
                (m.selection, m.heuristic),
                env,
                &at,
                (m.n_bsdf, bs.pdf),
                m.n_light,
            )
        });
        return bs.weight * env.1.le_at(&at) * weight;
    };
    let Some((index, light)) = scene.emitter_at(&hit) else {
        return Rgb::BLACK;
    };
    let normal = light.emitter.normal_at(hit.surface.p);
    let le = light.le(hit.surface.p, normal, -wi);
    if le.is_black() {
        return Rgb::BLACK;
    }
    let weight = mis.map_or(1.0, |m| {
        emitter_weight(
            scene,
            (m.selection, m.sampling),
            m.heuristic,
            origin,
            (index, light),
            hit.surface.p,
            normal,
            (m.n_bsdf, bs.pdf),
            m.n_light,
        )
    });
    bs.weight * le * weight
}
