//! A dielectric interface (glass, water) between the exterior and an interior of relative
//! index `eta`. Smooth: Fresnel-weighted mirror reflection and Snell refraction, one chosen
//! with probability F. Rough: the GGX microfacet BSDF of Walter et al., "Microfacet Models
//! for Refraction through Rough Surfaces" (EGSR 2007), eqs. 20-21, with the generalized
//! half vector m ∝ -(η_i wi + η_o wo), as pbrt-v4's `DielectricBxDF` writes it; normals
//! sampled by visibility (Heitz 2018) and the lobe chosen by F(wo·m).
//!
//! Radiance crossing into a denser medium is scaled by 1/η² (pbrt-v4 section 9.5.2); importance is not.

use super::microfacet::Ggx;
use super::Role;
use super::{
    one_lane_methods, reflect_z, reflect_z_lanes, BsdfModel, BsdfSample, Gather, LaneKernel, LaneSample, SpecularRays,
    TransportMode,
};
use crate::optics::{fresnel_dielectric, refract, refract_lanes};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Interior over exterior index of refraction.
    pub eta: f32,
    /// Tints on the reflected and the transmitted light (1 for physical glass).
    pub reflectance: Rgb,
    pub transmittance: Rgb,
    /// The microfacet distribution; `None` for a smooth interface.
    pub alpha: Option<Ggx>,
}

/// One of a dielectric's two lobes, which a layered BSDF's walk asks for alone (pbrt-v4's
/// `BxDFReflTransFlags`): sampled with the Fresnel choice left out of the density.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    Reflection,
    Transmission,
}

/// A dielectric in lanes of any [`Real`] type: each lane its own index, tints and
/// roughness, all in one transport mode.
#[derive(Clone, Copy, Debug)]
pub struct DielectricLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub eta: R,
    pub reflectance: S,
    pub transmittance: S,
    /// The microfacet distribution (any positive roughness where `rough` does not hold).
    pub ggx: Ggx<R>,
    /// Lanes with a rough interface that is not index-matched.
    pub rough: R::Mask,
    /// Light paths (importance): refraction does not scale by 1/η².
    pub importance: bool,
}

impl<R: Real, S: Spectrum<R>> DielectricLanes<R, S> {
    /// The same BSDF carrying the payload `T`, its tints converted by `to` (as a spectral
    /// renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(Role, S) -> T) -> DielectricLanes<R, T> {
        DielectricLanes {
            eta: self.eta,
            reflectance: to(Role::Specular, self.reflectance),
            transmittance: to(Role::Transmittance, self.transmittance),
            ggx: self.ggx,
            rough: self.rough,
            importance: self.importance,
        }
    }

    /// The relative index η_t / η_i for light leaving towards the side of cosine `cos`.
    #[inline(always)]
    fn relative_eta(&self, cos: R) -> R {
        R::select(cos.cmp_gt(R::splat(0.0)), self.eta, R::splat(1.0) / self.eta)
    }

    /// What the carried quantity is scaled by when crossing relative index `eta_rel`.
    #[inline(always)]
    fn transmission_scale(&self, eta_rel: R) -> R {
        if self.importance {
            R::splat(1.0)
        } else {
            R::splat(1.0) / (eta_rel * eta_rel)
        }
    }

    /// The generalized half vector of `wo` and `wi` on the upper side, the relative index
    /// crossed (1 for reflection), F, and where it exists (not where a back-facing
    /// microfacet would be needed).
    #[inline(always)]
    fn half_vector(&self, wo: V3<R>, wi: V3<R>) -> (V3<R>, R, R, R::Mask) {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let (cos_o, cos_i) = (wo.z, wi.z);
        let etap = R::select((cos_o * cos_i).cmp_gt(zero), one, self.relative_eta(cos_o));
        let (m, unit) = (V3::new(wi.x * etap, wi.y * etap, wi.z * etap) + wo).try_normalize();
        let m = V3::select(m.z.cmp_lt(zero), -m, m);
        let back = R::or((m.dot(wi) * cos_i).cmp_le(zero), (m.dot(wo) * cos_o).cmp_le(zero));
        let c = wo.dot(m);
        let f = fresnel_dielectric(c.abs(), self.relative_eta(c));
        let exists = R::and(R::not(R::or(cos_o.cmp_eq(zero), cos_i.cmp_eq(zero))), unit);
        (m, etap, f, R::and(exists, R::not(back)))
    }

    /// The rough lobe's density of `wi` before the Fresnel choice (reflection: the visible
    /// normal's density over 4 |wo·m|; refraction: times the Jacobian |wi·m| / (wi·m +
    /// wo·m / η)²), where the lobe is reflection, F, and where all this exists (rough
    /// lanes, possible pairs).
    #[inline(always)]
    fn lobe_density(&self, wo: V3<R>, wi: V3<R>) -> (R, R::Mask, R, R::Mask) {
        let (m, etap, f, ok) = self.half_vector(wo, wi);
        let visible = self.ggx.visible_pdf(wo, m);
        let reflection = etap.cmp_eq(R::splat(1.0));
        let r = visible / (R::splat(4.0) * wo.dot(m).abs());
        let x = wi.dot(m) + wo.dot(m) / etap;
        let t = visible * wi.dot(m).abs() / (x * x);
        (R::select(reflection, r, t), reflection, f, R::and(ok, self.rough))
    }

    /// The smooth interface's sample: mirror reflection with probability F, else Snell
    /// refraction.
    #[inline(always)]
    fn sample_smooth(&self, wo: V3<R>, u: R) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let eta_rel = self.relative_eta(wo.z);
        let f = fresnel_dielectric(wo.z.abs(), eta_rel);
        let s = wo.z / wo.z.abs();
        let (refracted, crosses) = refract_lanes(wo, V3::new(zero * s, zero * s, one * s), eta_rel);
        let reflect = u.cmp_lt(f);
        LaneSample {
            wi: V3::select(reflect, reflect_z_lanes(wo), refracted),
            weight: S::select(
                reflect,
                self.reflectance,
                self.transmittance.scale(self.transmission_scale(eta_rel)),
            ),
            pdf: R::select(reflect, f, one - f),
            delta: one.cmp_eq(one),
            eta: R::select(reflect, one, eta_rel),
            ok: R::or(reflect, crosses),
        }
    }

    /// The rough interface's sample: a visible normal, then reflection with probability
    /// F(wo·m), else refraction through it.
    #[inline(always)]
    fn sample_rough(&self, wo: V3<R>, u: R, u2: (R, R)) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let m = self.ggx.sample_visible(wo, u2);
        let c = wo.dot(m);
        let eta_rel = self.relative_eta(c);
        let f = fresnel_dielectric(c.abs(), eta_rel);
        let reflect = u.cmp_lt(f);
        let (refracted, crosses) = refract_lanes(wo, V3::select(c.cmp_gt(zero), m, -m), eta_rel);
        let wi = V3::select(reflect, m.scale(R::splat(2.0) * c) - wo, refracted);
        let same_side = (wo.z * wi.z).cmp_gt(zero);
        // Reflection must stay on wo's side and refraction cross.
        let consistent = R::or(R::and(reflect, same_side), R::and(R::not(reflect), R::not(same_side)));
        let pdf = self.pdf(wo, wi);
        LaneSample {
            wi,
            weight: self.eval(wo, wi).scale(wi.z.abs() / pdf),
            pdf,
            delta: R::splat_mask(false),
            eta: R::select(reflect, one, eta_rel),
            ok: R::and(R::and(R::or(reflect, crosses), consistent), pdf.cmp_gt(zero)),
        }
    }

    /// The same interface carrying the other quantity (a layered walk's estimates out
    /// towards wi trace the adjoint).
    #[inline(always)]
    pub fn adjoint(self) -> Self {
        DielectricLanes {
            importance: !self.importance,
            ..self
        }
    }

    /// Density with which [`DielectricLanes::sample_lobe`] gives `wi` for `lobe` (0 where
    /// smooth).
    #[inline(always)]
    pub fn pdf_lobe(&self, wo: V3<R>, wi: V3<R>, lobe: Lobe) -> R {
        let (density, reflection, _, ok) = self.lobe_density(wo, wi);
        let wanted = if lobe == Lobe::Reflection {
            reflection
        } else {
            R::not(reflection)
        };
        R::select(R::and(ok, wanted), density, R::splat(0.0))
    }

    /// A direction from `lobe` alone: the mirror or refracted direction (smooth), or about
    /// a visible microfacet normal (rough); its weight f |cos θi| / pdf carries F or 1 - F.
    /// No sample where the lobe has nothing (total internal reflection for refraction),
    /// nor where its density or weight vanishes.
    #[inline(always)]
    pub fn sample_lobe(&self, wo: V3<R>, u: (R, R), lobe: Lobe) -> LaneSample<R, S> {
        let reflection = lobe == Lobe::Reflection;
        let mut s = penumbra_core::choose_lanes!(
            R,
            self.rough,
            self.sample_lobe_rough(wo, u, reflection),
            self.sample_lobe_smooth(wo, reflection)
        );
        s.ok = R::and(R::not(wo.z.cmp_eq(R::splat(0.0))), s.ok);
        s
    }

    #[inline(always)]
    fn sample_lobe_smooth(&self, wo: V3<R>, reflection: bool) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let eta_rel = self.relative_eta(wo.z);
        let f = fresnel_dielectric(wo.z.abs(), eta_rel);
        let (wi, weight, eta, ok) = if reflection {
            (reflect_z_lanes(wo), self.reflectance.scale(f), one, f.cmp_gt(zero))
        } else {
            let s = wo.z / wo.z.abs();
            let (wi, crosses) = refract_lanes(wo, V3::new(zero * s, zero * s, one * s), eta_rel);
            let weight = self.transmittance.scale((one - f) * self.transmission_scale(eta_rel));
            (wi, weight, eta_rel, R::and(crosses, f.cmp_lt(one)))
        };
        LaneSample {
            wi,
            weight,
            pdf: one,
            delta: R::splat_mask(true),
            eta,
            ok,
        }
    }

    #[inline(always)]
    fn sample_lobe_rough(&self, wo: V3<R>, u: (R, R), reflection: bool) -> LaneSample<R, S> {
        let zero = R::splat(0.0);
        let m = self.ggx.sample_visible(wo, u);
        let c = wo.dot(m);
        let eta_rel = self.relative_eta(c);
        let (wi, eta, exists) = if reflection {
            (m.scale(R::splat(2.0) * c) - wo, R::splat(1.0), R::splat_mask(true))
        } else {
            let (wi, crosses) = refract_lanes(wo, V3::select(c.cmp_gt(zero), m, -m), eta_rel);
            (wi, eta_rel, crosses)
        };
        let same_side = (wo.z * wi.z).cmp_gt(zero);
        let side_ok = if reflection { same_side } else { R::not(same_side) };
        let lobe = if reflection {
            Lobe::Reflection
        } else {
            Lobe::Transmission
        };
        let pdf = self.pdf_lobe(wo, wi, lobe);
        let weight = self.eval(wo, wi).scale(wi.z.abs() / pdf);
        let ok = R::and(
            R::and(exists, side_ok),
            R::and(pdf.cmp_gt(zero), R::not(weight.is_black())),
        );
        LaneSample {
            wi,
            weight,
            pdf,
            delta: R::splat_mask(false),
            eta,
            ok,
        }
    }
}

impl Gather for DielectricLanes<f32> {
    type Lanes<L: Lane8> = DielectricLanes<L>;
    /// Eight dielectrics of one transport mode (the first's).
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> DielectricLanes<L> {
        DielectricLanes {
            eta: L::from_array(one.map(|d| d.eta)),
            reflectance: V3::gather(one, |d| d.reflectance),
            transmittance: V3::gather(one, |d| d.transmittance),
            ggx: Ggx {
                ax: L::from_array(one.map(|d| d.ggx.ax)),
                ay: L::from_array(one.map(|d| d.ggx.ay)),
            },
            rough: L::mask_of(one.map(|d| d.rough)),
            importance: one[0].importance,
        }
    }
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for DielectricLanes<R, S> {
    /// Walter et al.'s eqs. 20 (reflection) and 21 (refraction); black where smooth.
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        if !R::any(self.rough) {
            return S::splat(0.0);
        }
        let (m, etap, f, ok) = self.half_vector(wo, wi);
        let (cos_o, cos_i) = (wo.z, wi.z);
        let dg = self.ggx.d(m) * self.ggx.g2(wo, wi);
        let reflected = self.reflectance.scale(dg * f / (R::splat(4.0) * cos_i * cos_o).abs());
        let x = wi.dot(m) + wo.dot(m) / etap;
        let denom = x * x * cos_i * cos_o;
        let ft = dg * (R::splat(1.0) - f) * (wi.dot(m) * wo.dot(m) / denom).abs();
        let transmitted = self.transmittance.scale(ft * self.transmission_scale(etap));
        let f = S::select(etap.cmp_eq(R::splat(1.0)), reflected, transmitted);
        S::select(R::and(ok, self.rough), f, S::splat(0.0))
    }

    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        if !R::any(self.rough) {
            return R::splat(0.0);
        }
        let (density, reflection, f, ok) = self.lobe_density(wo, wi);
        let p = density * R::select(reflection, f, R::splat(1.0) - f);
        R::select(ok, p, R::splat(0.0))
    }

    #[inline(always)]
    fn sample(&self, wo: V3<R>, u_lobe: R, u: (R, R)) -> LaneSample<R, S> {
        let mut s = penumbra_core::choose_lanes!(
            R,
            self.rough,
            self.sample_rough(wo, u_lobe, u),
            self.sample_smooth(wo, u_lobe)
        );
        s.ok = R::and(R::not(wo.z.cmp_eq(R::splat(0.0))), s.ok);
        s
    }
}

impl Dielectric {
    /// The one-lane instance of the arithmetic, for transport `mode`.
    #[inline(always)]
    pub fn lanes(&self, mode: TransportMode) -> DielectricLanes<f32> {
        DielectricLanes {
            eta: self.eta,
            reflectance: self.reflectance.into(),
            transmittance: self.transmittance.into(),
            ggx: self.alpha.unwrap_or(Ggx { ax: 1.0, ay: 1.0 }),
            rough: self.rough().is_some(),
            importance: mode == TransportMode::Importance,
        }
    }

    /// The rough BSDF's distribution, unless the interface is smooth or index-matched.
    pub(crate) fn rough(&self) -> Option<Ggx> {
        self.alpha.filter(|_| self.eta != 1.0)
    }
}

impl BsdfModel for Dielectric {
    one_lane_methods!();

    fn specular_rays(&self, wo: Vec3, mode: TransportMode, rays: &mut SpecularRays) {
        if self.rough().is_some() || wo.z == 0.0 {
            return;
        }
        let lanes = self.lanes(mode);
        let eta_rel = lanes.relative_eta(wo.z);
        let f = fresnel_dielectric(wo.z.abs(), eta_rel);
        rays.push(reflect_z(wo), self.reflectance * f);
        if let Some(wi) = refract(wo, Vec3::Z * wo.z.signum(), eta_rel) {
            rays.push(wi, self.transmittance * ((1.0 - f) * lanes.transmission_scale(eta_rel)));
        }
    }

    fn has_smooth(&self) -> bool {
        self.rough().is_some()
    }

    fn albedo(&self) -> Rgb {
        self.transmittance
    }
}
