//! The BSDF of the classic ray-tracing material (see [`crate::materials::Phong`]): Lambertian
//! diffuse plus the energy-normalised Phong lobe f = ks (n + 2) / (2π) cos^n α (Lafortune
//! and Willems 1994), on both sides of the surface, plus perfect mirror reflection and a
//! Fresnel-weighted dielectric interface as delta lobes. `sample` chooses among the smooth
//! part and the delta rays in proportion to their albedos' luminance, and within the smooth
//! part between the cosine hemisphere and the Phong lobe likewise.
//!
//! Written once over the lane type ([`PhongLanes`]): the scalar [`PhongBsdf`] (its
//! `eval`, `pdf`, `sample` and the Whitted integrator's `specular_rays`) is the one-lane
//! instance.

use super::Role;
use super::{
    one_lane_methods, reflect_z_lanes, BsdfModel, BsdfSample, Gather, LaneKernel, LaneSample, SpecularRays,
    TransportMode,
};
use crate::optics::{fresnel_dielectric, refract_lanes};
use glam::{Vec2, Vec3};
use penumbra_core::frame::Basis;
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{warp, Rgb};
use std::f32::consts::{FRAC_1_PI, PI};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongBsdf {
    pub diffuse: Rgb,
    pub specular: Rgb,
    pub exponent: f32,
    pub mirror: Rgb,
    pub transmission: Rgb,
    /// Interior over exterior index of refraction.
    pub eta: f32,
}

/// The Phong BSDF in lanes of any [`Real`] type, for one transport mode.
#[derive(Clone, Copy, Debug)]
pub struct PhongLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub diffuse: S,
    pub specular: S,
    pub exponent: R,
    pub mirror: S,
    pub transmission: S,
    pub eta: R,
    /// Radiance (refraction into a denser medium scaled by 1/η²), else importance.
    pub radiance: bool,
}

/// The delta rays seen from `wo`: the reflection (the mirror's and the interface's, one
/// direction, weights added) and the refraction, each with where it exists, in the order
/// [`SpecularRays`] lists them.
struct DeltaRays<R: Real, S: Spectrum<R>> {
    reflected: V3<R>,
    reflected_weight: S,
    reflects: R::Mask,
    refracted: V3<R>,
    refracted_weight: S,
    refracts: R::Mask,
    /// The relative index of refraction crossed by the refraction.
    eta: R,
    /// The sum of the rays' brightnesses (luminances in RGB), as `Iterator::sum` adds them
    /// (from -0).
    luminance: R,
}

/// `w` turned to the upper side (both-sided lobes are evaluated above).
#[inline(always)]
fn upper<R: Real>(w: V3<R>) -> V3<R> {
    V3::new(w.x, w.y, w.z.abs())
}

impl PhongBsdf {
    /// The one-lane instance of the arithmetic, for transport mode `mode`.
    #[inline(always)]
    pub fn lanes(&self, mode: TransportMode) -> PhongLanes<f32> {
        PhongLanes {
            diffuse: self.diffuse.into(),
            specular: self.specular.into(),
            exponent: self.exponent,
            mirror: self.mirror.into(),
            transmission: self.transmission.into(),
            eta: self.eta,
            radiance: mode == TransportMode::Radiance,
        }
    }
}

impl Gather for PhongLanes<f32> {
    type Lanes<L: Lane8> = PhongLanes<L>;
    /// Eight Phong BSDFs of one transport mode (the first's).
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> PhongLanes<L> {
        PhongLanes {
            diffuse: V3::gather(one, |b| b.diffuse),
            specular: V3::gather(one, |b| b.specular),
            exponent: L::from_array(one.map(|b| b.exponent)),
            mirror: V3::gather(one, |b| b.mirror),
            transmission: V3::gather(one, |b| b.transmission),
            eta: L::from_array(one.map(|b| b.eta)),
            radiance: one[0].radiance,
        }
    }
}

impl<R: Real, S: Spectrum<R>> PhongLanes<R, S> {
    /// The same BSDF carrying the payload `T`, its colours converted by `to` (as a
    /// spectral renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(Role, S) -> T) -> PhongLanes<R, T> {
        PhongLanes {
            diffuse: to(Role::Reflectance, self.diffuse),
            specular: to(Role::Specular, self.specular),
            exponent: self.exponent,
            mirror: to(Role::Mirror, self.mirror),
            transmission: to(Role::Transmittance, self.transmission),
            eta: self.eta,
            radiance: self.radiance,
        }
    }

    /// Luminance of the diffuse and glossy albedos together.
    #[inline(always)]
    fn smooth_albedo(&self) -> R {
        let zero = R::splat(0.0);
        self.diffuse.brightness().max(zero) + self.specular.brightness().max(zero)
    }

    /// The share of the cosine hemisphere in the smooth part's sampling.
    #[inline(always)]
    fn diffuse_share(&self, smooth: R) -> R {
        self.diffuse.brightness().max(R::splat(0.0)) / smooth
    }

    /// Density of the smooth part's sampling, both directions above.
    #[inline(always)]
    fn smooth_pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let smooth = self.smooth_albedo();
        let pd = self.diffuse_share(smooth);
        let pdf = pd * (wi.z.max(zero) * R::splat(FRAC_1_PI));
        let glossy = pd.cmp_lt(one);
        let pdf = if R::any(glossy) {
            let lobe = Basis::from_normal(reflect_z_lanes(wo)).to_local(wi);
            let with_lobe = pdf + (one - pd) * warp::phong_lobe_pdf_lanes(lobe, self.exponent);
            R::select(glossy, with_lobe, pdf)
        } else {
            pdf
        };
        R::select(smooth.cmp_le(zero), zero, pdf)
    }

    /// The delta rays: mirror reflection, and for a transmissive material the
    /// Fresnel-weighted reflection and refraction, radiance crossing into a denser medium
    /// scaled by 1/η².
    #[inline(always)]
    fn delta_rays(&self, wo: V3<R>) -> DeltaRays<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let grazing = wo.z.cmp_eq(zero);
        let transmits = R::not(self.transmission.is_black());
        let eta = R::select(wo.z.cmp_gt(zero), self.eta, one / self.eta);
        // The interface's reflection and refraction, where some lane transmits.
        let (interface, refracted, refracted_weight, refracts) = if R::any(transmits) {
            let f = fresnel_dielectric(wo.z.abs(), eta);
            let side = one.copysign(wo.z);
            let (refracted, exists) = refract_lanes(wo, V3::new(zero * side, zero * side, side), eta);
            let scale = if self.radiance { one / (eta * eta) } else { one };
            let refracted_weight = self.transmission.scale((one - f) * scale);
            let refracts = R::and(
                R::and(R::not(grazing), transmits),
                R::and(R::and(f.cmp_lt(one), exists), R::not(refracted_weight.is_black())),
            );
            let interface = S::select(transmits, self.transmission.scale(f), S::splat(0.0));
            (interface, refracted, refracted_weight, refracts)
        } else {
            (S::splat(0.0), wo, S::splat(0.0), R::splat_mask(false))
        };
        let reflected_weight = self.mirror + interface;
        let reflects = R::and(R::not(grazing), R::not(reflected_weight.is_black()));
        let sum = R::splat(-0.0);
        let sum = R::select(reflects, sum + reflected_weight.brightness(), sum);
        let sum = R::select(refracts, sum + refracted_weight.brightness(), sum);
        DeltaRays {
            reflected: reflect_z_lanes(wo),
            reflected_weight,
            reflects,
            refracted,
            refracted_weight,
            refracts,
            eta,
            luminance: sum,
        }
    }
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for PhongLanes<R, S> {
    /// Diffuse plus the Phong lobe about the mirror direction, where both directions are
    /// on one side (the lobe zero outside its hemisphere, also for exponent 0).
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        let zero = R::splat(0.0);
        let diffuse = self.diffuse.scale(R::splat(1.0 / PI));
        let cos_alpha = reflect_z_lanes(upper(wi)).dot(upper(wo));
        let glossy = R::and(R::not(self.specular.is_black()), cos_alpha.cmp_gt(zero));
        let f = if R::any(glossy) {
            let norm = (self.exponent + R::splat(2.0)) / R::splat(2.0 * PI);
            let lobe = self.specular.scale(norm * cos_alpha.powf(self.exponent));
            S::select(glossy, diffuse + lobe, diffuse)
        } else {
            diffuse
        };
        S::select((wo.z * wi.z).cmp_gt(zero), f, S::splat(0.0))
    }

    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let zero = R::splat(0.0);
        let smooth = self.smooth_albedo();
        let total = smooth + self.delta_rays(wo).luminance;
        let share = R::select(total.cmp_gt(zero), smooth / total, zero);
        let pdf = share * self.smooth_pdf(upper(wo), upper(wi));
        R::select((wo.z * wi.z).cmp_gt(zero), pdf, zero)
    }

    /// The smooth part or a delta ray, by their shares of the albedo: the smooth part by
    /// the cosine hemisphere or the lobe (u rescaled); a delta ray by walking the rays'
    /// luminances (rounding may leave u at the very end: then the last ray).
    #[inline(always)]
    fn sample(&self, wo: V3<R>, u: R, u2: (R, R)) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let smooth = self.smooth_albedo();
        let rays = self.delta_rays(wo);
        let total = smooth + rays.luminance;
        let valid = R::and(total.cmp_gt(zero), R::not(wo.z.cmp_eq(zero)));
        let x = u * total;
        let take_smooth = x.cmp_lt(smooth);

        // The smooth part.
        let side = one.copysign(wo.z);
        let up = V3::new(wo.x, wo.y, wo.z * side);
        let cosine = (x / smooth).cmp_lt(self.diffuse_share(smooth));
        let cosine_wi = warp::cosine_hemisphere_lanes(u2.0, u2.1);
        let wi = if R::any(R::and(take_smooth, R::not(cosine))) {
            let lobe = warp::phong_lobe_lanes(u2.0, u2.1, self.exponent);
            V3::select(
                cosine,
                cosine_wi,
                Basis::from_normal(reflect_z_lanes(up)).to_world(lobe),
            )
        } else {
            cosine_wi
        };
        let above = wi.z.cmp_gt(zero);
        let wi = V3::new(wi.x, wi.y, wi.z * side);
        let smooth_pdf = smooth / total * self.smooth_pdf(up, upper(wi));
        let smooth_ok = R::and(above, smooth_pdf.cmp_gt(zero));
        let smooth_weight = self.eval(wo, wi).scale(wi.z.abs() / smooth_pdf);

        // A delta ray.
        let (reflected_luminance, refracted_luminance) =
            (rays.reflected_weight.brightness(), rays.refracted_weight.brightness());
        let past = x - smooth - reflected_luminance;
        let reflect = R::and(rays.reflects, R::or(past.cmp_lt(zero), R::not(rays.refracts)));
        let chosen = R::or(reflect, rays.refracts);
        let delta_wi = V3::select(reflect, rays.reflected, rays.refracted);
        let weight = S::select(reflect, rays.reflected_weight, rays.refracted_weight);
        let p = R::select(reflect, reflected_luminance, refracted_luminance) / total;
        let crossed = R::not((wo.z * delta_wi.z).cmp_gt(zero));

        LaneSample {
            wi: V3::select(take_smooth, wi, delta_wi),
            weight: S::select(take_smooth, smooth_weight, weight.scale(one / p)),
            pdf: R::select(take_smooth, smooth_pdf, p),
            delta: R::not(take_smooth),
            eta: R::select(R::or(take_smooth, R::not(crossed)), one, rays.eta),
            ok: R::and(
                valid,
                R::select_mask(take_smooth, smooth_ok, R::and(chosen, p.cmp_gt(zero))),
            ),
        }
    }
}

impl BsdfModel for PhongBsdf {
    one_lane_methods!();

    /// Mirror reflection, and for a transmissive material the Fresnel-weighted reflection
    /// and refraction, radiance crossing into a denser medium scaled by 1/η².
    fn specular_rays(&self, wo: Vec3, mode: TransportMode, rays: &mut SpecularRays) {
        let r = self.lanes(mode).delta_rays(wo.into());
        if r.reflects {
            rays.push(r.reflected.into(), r.reflected_weight.into());
        }
        if r.refracts {
            rays.push(r.refracted.into(), r.refracted_weight.into());
        }
    }

    fn has_smooth(&self) -> bool {
        self.smooth_albedo() > 0.0
    }

    fn albedo(&self) -> Rgb {
        self.diffuse
    }
}

impl PhongBsdf {
    /// Luminance of the diffuse and glossy albedos together.
    fn smooth_albedo(&self) -> f32 {
        self.lanes(TransportMode::Radiance).smooth_albedo()
    }
}
