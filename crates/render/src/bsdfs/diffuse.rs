//! Lambertian reflection: f = ρ / π on the front side, sampled by the cosine-weighted
//! hemisphere (Malley's method), so that the weight f cos θ / pdf is ρ.
//!
//! Written once over the lane type ([`DiffuseLanes`]): the scalar [`Diffuse`] is its
//! one-lane instance, and the path tracer's eight-lane bounce (`diffuse_lanes.rs`) calls
//! the same routines.

use super::Role;
use super::{one_lane_methods, BsdfModel, BsdfSample, Gather, LaneKernel, LaneSample, TransportMode};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{warp, Rgb};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    pub reflectance: Rgb,
}

/// A Lambertian surface in lanes of any [`Real`] type, its reflectance in the payload `S`.
#[derive(Clone, Copy, Debug)]
pub struct DiffuseLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub reflectance: S,
    lanes: std::marker::PhantomData<R>,
}

impl<R: Real, S: Spectrum<R>> DiffuseLanes<R, S> {
    #[inline(always)]
    pub fn new(reflectance: S) -> Self {
        DiffuseLanes {
            reflectance,
            lanes: std::marker::PhantomData,
        }
    }

    /// The same BSDF carrying the payload `T`, its colour converted by `to` (as a spectral
    /// renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(Role, S) -> T) -> DiffuseLanes<R, T> {
        DiffuseLanes::new(to(Role::Reflectance, self.reflectance))
    }
}

impl Diffuse {
    /// The one-lane instance of the arithmetic.
    #[inline(always)]
    pub fn lanes(&self, _mode: TransportMode) -> DiffuseLanes<f32> {
        DiffuseLanes::new(self.reflectance.into())
    }
}

impl Gather for DiffuseLanes<f32> {
    type Lanes<L: Lane8> = DiffuseLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> DiffuseLanes<L> {
        DiffuseLanes::new(V3::gather(one, |d| d.reflectance))
    }
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for DiffuseLanes<R, S> {
    /// f(wo, wi): ρ / π where both directions are above the surface.
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        let zero = R::splat(0.0);
        let front = R::and(wo.z.cmp_gt(zero), wi.z.cmp_gt(zero));
        S::select(front, self.reflectance.scale(R::splat(FRAC_1_PI)), S::splat(0.0))
    }

    /// The cosine-weighted density of `wi`, where `wo` is above the surface.
    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let zero = R::splat(0.0);
        let same_side = R::and(wo.z.cmp_gt(zero), (wo.z * wi.z).cmp_gt(zero));
        R::select(same_side, wi.z.max(zero) * R::splat(FRAC_1_PI), zero)
    }

    /// A cosine-weighted direction (none where `wo` is below the surface).
    #[inline(always)]
    fn sample(&self, wo: V3<R>, _u_lobe: R, u: (R, R)) -> LaneSample<R, S> {
        let zero = R::splat(0.0);
        let wi = warp::cosine_hemisphere_lanes(u.0, u.1);
        let pdf = wi.z.max(zero) * R::splat(FRAC_1_PI);
        LaneSample {
            wi,
            weight: self.reflectance,
            pdf,
            delta: R::splat_mask(false),
            eta: R::splat(1.0),
            ok: R::and(R::not(wo.z.cmp_le(zero)), pdf.cmp_gt(zero)),
        }
    }
}

impl BsdfModel for Diffuse {
    one_lane_methods!();

    fn has_smooth(&self) -> bool {
        !self.reflectance.is_black()
    }

    fn albedo(&self) -> Rgb {
        self.reflectance
    }
}
