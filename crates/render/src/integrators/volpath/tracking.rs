//! `volpath`'s walks through media in the path's payload: free flights by delta tracking
//! ([`fly`]) and shadow rays' transmittance by ratio tracking ([`transmittance`]), both
//! against the media's majorants drawn in the hero channel.

use super::{beyond, over_mean, Flight, PathSampling, Weights, MAX_CROSSINGS};
use crate::bsdfs::Role;
use crate::integrators::RayCounts;
use crate::media::{attenuation_in, Medium, MediumPoint, Step, Tracker};
use crate::spectral::Tint;
use crate::Scene;
use glam::Vec3;
use penumbra_core::ray::SHADOW_EPSILON;
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{Ray, Rgb};

/// A medium's σt and σs at a point in the tint's payload: σt as an unbounded quantity and
/// the albedo σs/σt as a reflectance (so that σs ≤ σt at every wavelength, as Mitsuba
/// models its media's spectra).
pub(super) fn coefficients<T: Tint>(tint: &T, mp: &MediumPoint) -> (T::S, T::S) {
    let t = tint.unbounded(mp.sigma_t());
    (t, tint.param(None, Role::Reflectance, mp.albedo().into()).mul_each(t))
}

/// Delta tracking of `ray` (unit direction) through `medium` up to `t_max`: each tentative
/// collision is real with the hero channel's probability σt/σ_maj, else null. A real
/// collision always scatters, its throughput weighted by σs (the albedo, where pbrt-v4
/// draws absorption as an event that ends the path: the weight, as Mitsuba's `volpath`
/// uses it, keeps the paths that absorption would end and leaves them to Russian roulette,
/// which costs less variance); its density σt T_maj goes into r_u. A null collision
/// weights β and r_u by σn T_maj over its density and r_l by σ_maj T_maj (pbrt-v4).
pub(super) fn fly<T: Tint>(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    w: &mut Weights<T::S>,
    s: &mut PathSampling<T>,
) -> Flight {
    let hero = s.hero;
    let tint = &s.tint;
    let convert = |c: Rgb| tint.unbounded(c);
    let mut walk = Tracker::new_in(medium, (ray.origin, ray.dir, t_max), hero, s.segments, &convert);
    loop {
        match walk.step(&mut s.rng) {
            Step::End { t_maj } => {
                let Some(ratio) = over_hero(t_maj, hero) else {
                    return Flight::Absorbed;
                };
                for x in [&mut w.beta, &mut w.r_u, &mut w.r_l] {
                    *x = x.mul_each(ratio);
                }
                return Flight::Through;
            }
            Step::Collision { t, sigma_maj, t_maj } => {
                let p = ray.at(t);
                let mp = medium.at(p);
                let (sigma_t, sigma_s) = coefficients(tint, &mp);
                let t_hero = t_maj.channel(hero);
                if s.rng.next_f32() * sigma_maj.channel(hero) < sigma_t.channel(hero) {
                    let pdf = t_hero * sigma_t.channel(hero);
                    w.beta = w.beta.mul_each(t_maj.mul_each(sigma_s).div_by(pdf));
                    w.r_u = w.r_u.mul_each(t_maj.mul_each(sigma_t).div_by(pdf));
                    if Spectrum::is_black(w.beta) {
                        return Flight::Absorbed;
                    }
                    return Flight::Scattered { p, phase: mp.phase };
                }
                let sigma_n = clamp_positive(sigma_maj - sigma_t);
                let pdf = t_hero * sigma_n.channel(hero);
                if pdf == 0.0 {
                    return Flight::Absorbed;
                }
                w.beta = w.beta.mul_each(t_maj.mul_each(sigma_n).div_by(pdf));
                w.r_u = w.r_u.mul_each(t_maj.mul_each(sigma_n).div_by(pdf));
                w.r_l = w.r_l.mul_each(t_maj.mul_each(sigma_maj).div_by(pdf));
                if Spectrum::is_black(w.beta) || Spectrum::is_black(w.r_u) {
                    return Flight::Absorbed;
                }
            }
        }
    }
}

/// Each channel of `v`, negatives made 0.
fn clamp_positive<S: Spectrum<f32>>(mut v: S) -> S {
    for i in 0..S::CHANNELS {
        *v.channel_mut(i) = v.channel(i).max(0.0);
    }
    v
}

/// A shadow ray's transmittance estimate `t` and the factors it brings to the rescaled
/// probabilities of the light-sampled path (`r_l`) and of the same path sampled
/// unidirectionally (`r_u`).
pub(super) struct Transmittance<S> {
    pub t: S,
    pub r_l: S,
    pub r_u: S,
}

/// Ratio tracking (Novák et al. 2014, pbrt-v4's `SampleLd` loop) from `origin` along the
/// unit `dir` to the light's point at distance `dist` (infinite for lights at infinity),
/// starting in `medium`: through every medium met, stepping over boundaries
/// ([`crate::Material::null`]) and switching media there; `None` where a surface blocks the
/// ray or the estimate is zero. The estimate is cut by Russian roulette (kept with
/// probability 1/4) where it falls below 0.05.
///
/// After each boundary the ray is aimed again from where it now starts (pushed off the
/// boundary) at the light's point, and ends short of it by [`SHADOW_EPSILON`] of the whole
/// distance (pbrt-v4's `SpawnRayTo`): going on along the old direction from the pushed-off
/// point, or shortening the extent by the boundary's hit distance, carried the ray onto the
/// light itself where the light lies just beyond a boundary (it was then taken as blocked).
pub(super) fn transmittance<T: Tint>(
    scene: &Scene,
    (mut origin, dir, dist): (Vec3, Vec3, f32),
    mut medium: Option<u32>,
    s: &mut PathSampling<T>,
    counts: &mut RayCounts,
) -> Option<Transmittance<T::S>> {
    let hero = s.hero;
    let target = origin + dir * dist;
    let margin = dist * SHADOW_EPSILON;
    let one = T::S::splat(1.0);
    let mut tr = Transmittance {
        t: one,
        r_l: one,
        r_u: one,
    };
    let mut dir = dir;
    for _ in 0..=MAX_CROSSINGS {
        let reach = if dist.is_finite() {
            let to_target = target - origin;
            dir = to_target.normalize_or(dir);
            to_target.length() - margin
        } else {
            f32::INFINITY
        };
        if reach <= 0.0 {
            return Some(tr);
        }
        counts.shadow += 1;
        let ray = Ray::new(origin, dir);
        let hit = scene.accel.intersect(&ray, reach);
        let it = hit.map(|h| scene.interaction(&ray, &h));
        if it.as_ref().is_some_and(|it| !scene.is_boundary(it.surface.object)) {
            return None;
        }
        if let Some(m) = medium {
            let m = &scene.media[m as usize];
            let end = hit.map_or(reach, |h| h.t);
            if m.is_homogeneous() {
                // The expectation of ratio tracking's estimate, which is binary here (no
                // null collisions): passing, with the hero channel's probability T, it
                // weighs T/T_hero into the estimate and the two r's.
                let (sigma_t, _) = coefficients(&s.tint, &m.at(origin));
                let t = attenuation_in(sigma_t, end);
                let ratio = over_hero(t, hero)?;
                tr.t = tr.t.mul_each(t);
                tr.r_l = tr.r_l.mul_each(ratio);
                tr.r_u = tr.r_u.mul_each(ratio);
            } else if !ratio_tracking(m, &ray, end, s, &mut tr) {
                return None;
            }
        }
        let Some(it) = it else {
            return Some(tr);
        };
        if let Some(mi) = scene.media_of(it.surface.object) {
            medium = mi.towards(it.surface.ng, dir);
        }
        origin = beyond(it.surface.p, it.surface.ng, dir);
    }
    None
}

/// Ratio tracking of `ray` (unit direction) through `m` over `[0, end)` into `tr`, as
/// pbrt-v4's `SampleLd`; whether the estimate is still above zero.
fn ratio_tracking<T: Tint>(
    m: &Medium,
    ray: &Ray,
    end: f32,
    s: &mut PathSampling<T>,
    tr: &mut Transmittance<T::S>,
) -> bool {
    let hero = s.hero;
    let tint = &s.tint;
    let convert = |c: Rgb| tint.unbounded(c);
    let mut walk = Tracker::new_in(m, (ray.origin, ray.dir, end), hero, s.segments, &convert);
    loop {
        match walk.step(&mut s.rng) {
            Step::Collision { t, sigma_maj, t_maj } => {
                let (sigma_t, _) = coefficients(tint, &m.at(ray.at(t)));
                let sigma_n = clamp_positive(sigma_maj - sigma_t);
                let pdf = t_maj.channel(hero) * sigma_maj.channel(hero);
                tr.t = tr.t.mul_each(t_maj.mul_each(sigma_n).div_by(pdf));
                tr.r_l = tr.r_l.mul_each(t_maj.mul_each(sigma_maj).div_by(pdf));
                tr.r_u = tr.r_u.mul_each(t_maj.mul_each(sigma_n).div_by(pdf));
                let estimate = over_mean(tint, tr.t, tr.r_l + tr.r_u);
                if estimate.max_channel() < 0.05 {
                    tr.t = if s.rng.next_f32() < 0.75 {
                        T::S::splat(0.0)
                    } else {
                        tr.t.scale(4.0)
                    };
                }
                if Spectrum::is_black(tr.t) {
                    return false;
                }
            }
            Step::End { t_maj } => {
                let Some(ratio) = over_hero(t_maj, hero) else {
                    return false;
                };
                for x in [&mut tr.t, &mut tr.r_l, &mut tr.r_u] {
                    *x = x.mul_each(ratio);
                }
                return true;
            }
        }
    }
}

/// A transmittance `t` over its hero channel's (the probability with which the hero
/// channel's tracking passed); `None` where that is zero.
fn over_hero<S: Spectrum<f32>>(t: S, hero: usize) -> Option<S> {
    let p = t.channel(hero);
    (p > 0.0).then(|| t.div_by(p))
}
