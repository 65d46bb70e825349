//! Conductors (metals): Fresnel reflection with a complex index of refraction η + ik per
//! colour channel. Smooth: a perfect mirror. Rough: the GGX microfacet BRDF
//! f = F(wo·m) D(m) G2(wo, wi) / (4 cos θo cos θi) (Walter et al. 2007), sampled by visible
//! normals (Heitz 2018), whose weight is F G2 / G1(wo). Single scattering only: rough
//! metals lose the energy of light that would bounce between microfacets, never gain any.
//! glTF's metals give their reflectance at normal incidence instead of an index: their F
//! is Schlick's approximation (Schlick 1994, eq. 24), as the glTF 2.0 specification's
//! appendix B defines it.
//!
//! The arithmetic is written once, over the lane type ([`ConductorLanes`]): the scalar
//! [`Conductor`] is its one-lane instance, and eight conductors shade in one pass of
//! eight-lane instructions with the same floats per lane.

use super::microfacet::Ggx;
use super::Role;
use super::{one_lane_methods, BsdfModel, BsdfSample, Gather, LaneKernel, LaneSample, SpecularRays, TransportMode};
use crate::optics::{clamp_unit, fresnel_conductor};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::Rgb;

/// How a metal's reflectance varies with the angle of incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MetalFresnel {
    /// The exact Fresnel equations for the complex index `eta + i k`.
    Complex { eta: Rgb, k: Rgb },
    /// Schlick's F0 + (1 - F0)(1 - cos)^5 with F0 the conductor's `specular` tint.
    Schlick,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub fresnel: MetalFresnel,
    /// A tint on the reflection (1 for physical metals).
    pub specular: Rgb,
    /// The microfacet distribution; `None` for a smooth mirror.
    pub alpha: Option<Ggx>,
}

/// A conductor in lanes of any [`Real`] type: each lane its own metal, roughness and
/// Fresnel form; the index, absorption and tint per channel of the payload `S`.
#[derive(Clone, Copy, Debug)]
pub struct ConductorLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub eta: S,
    pub k: S,
    /// Lanes with Schlick's Fresnel term (`eta` and `k` unused there).
    pub schlick: R::Mask,
    pub specular: S,
    /// The microfacet distribution (any positive roughness where `rough` does not hold).
    pub ggx: Ggx<R>,
    pub rough: R::Mask,
}

impl Conductor {
    /// The one-lane instance of the conductor's arithmetic.
    #[inline(always)]
    pub fn lanes(&self, _mode: TransportMode) -> ConductorLanes<f32> {
        let (eta, k, schlick) = match self.fresnel {
            MetalFresnel::Complex { eta, k } => (eta, k, false),
            MetalFresnel::Schlick => (Rgb::WHITE, Rgb::BLACK, true),
        };
        ConductorLanes {
            eta: eta.into(),
            k: k.into(),
            schlick,
            specular: self.specular.into(),
            ggx: self.alpha.unwrap_or(Ggx { ax: 1.0, ay: 1.0 }),
            rough: self.alpha.is_some(),
        }
    }

    /// F(cos) per channel, tinted by `specular`.
    pub(crate) fn fresnel(&self, cos: f32) -> Rgb {
        self.lanes(TransportMode::Radiance).fresnel(cos).into()
    }
}

impl<R: Real, S: Spectrum<R>> ConductorLanes<R, S> {
    /// The same BSDF carrying the payload `T`, its colours (index, absorption, tint)
    /// converted by `to` (as a spectral renderer turns RGB parameters into values at a
    /// path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(Role, S) -> T) -> ConductorLanes<R, T> {
        ConductorLanes {
            eta: to(Role::Eta, self.eta),
            k: to(Role::K, self.k),
            schlick: self.schlick,
            specular: to(Role::Specular, self.specular),
            ggx: self.ggx,
            rough: self.rough,
        }
    }

    /// F(cos) per channel, tinted by `specular`.
    #[inline(always)]
    pub fn fresnel(&self, cos: R) -> S {
        let mut exact = self.eta;
        for i in 0..S::CHANNELS {
            *exact.channel_mut(i) = fresnel_conductor(cos, self.eta.channel(i), self.k.channel(i));
        }
        let exact = exact.mul_each(self.specular);
        let f0 = self.specular;
        let x = R::splat(1.0) - clamp_unit(cos);
        let x2 = x * x;
        let schlick = f0 + (S::splat(1.0) - f0).scale(x2 * x2 * x);
        S::select(self.schlick, schlick, exact)
    }
}

impl Gather for ConductorLanes<f32> {
    type Lanes<L: Lane8> = ConductorLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> ConductorLanes<L> {
        ConductorLanes {
            eta: V3::gather(one, |c| c.eta),
            k: V3::gather(one, |c| c.k),
            schlick: L::mask_of(one.map(|c| c.schlick)),
            specular: V3::gather(one, |c| c.specular),
            ggx: Ggx {
                ax: L::from_array(one.map(|c| c.ggx.ax)),
                ay: L::from_array(one.map(|c| c.ggx.ay)),
            },
            rough: L::mask_of(one.map(|c| c.rough)),
        }
    }
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for ConductorLanes<R, S> {
    /// f(wo, wi) of the rough part, without the cosine.
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        if !R::any(self.rough) {
            return S::splat(0.0);
        }
        let (m, ok) = Ggx::half_vector_lanes(wo, wi);
        let f = self.fresnel(wo.dot(m)).scale(self.ggx.reflection(wo, wi, m));
        S::select(R::and(ok, self.rough), f, S::splat(0.0))
    }

    /// Density with which [`ConductorLanes::sample`] gives the rough direction `wi`.
    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        if !R::any(self.rough) {
            return R::splat(0.0);
        }
        let (m, ok) = Ggx::half_vector_lanes(wo, wi);
        R::select(R::and(ok, self.rough), self.ggx.reflection_pdf(wo, m), R::splat(0.0))
    }

    /// A reflected direction: mirror (delta) lanes where the metal is smooth, visible
    /// normals elsewhere.
    #[inline(always)]
    fn sample(&self, wo: V3<R>, _u_lobe: R, u: (R, R)) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let front = wo.z.cmp_gt(zero);
        penumbra_core::choose_lanes!(
            R,
            self.rough,
            {
                let (wi, m, ok) = self.ggx.sample_reflection_lanes(wo, u);
                LaneSample {
                    wi,
                    weight: self.fresnel(wo.dot(m)).scale(self.ggx.g2(wo, wi) / self.ggx.g1(wo)),
                    pdf: self.ggx.reflection_pdf(wo, m),
                    delta: R::splat_mask(false),
                    eta: one,
                    ok: R::and(front, ok),
                }
            },
            LaneSample {
                wi: super::reflect_z_lanes(wo),
                weight: self.fresnel(wo.z),
                pdf: one,
                delta: R::splat_mask(true),
                eta: one,
                ok: front,
            }
        )
    }
}

impl BsdfModel for Conductor {
    one_lane_methods!();

    fn specular_rays(&self, wo: Vec3, _mode: TransportMode, rays: &mut SpecularRays) {
        if self.alpha.is_none() && wo.z > 0.0 {
            rays.push(super::reflect_z(wo), self.fresnel(wo.z));
        }
    }

    fn has_smooth(&self) -> bool {
        self.alpha.is_some()
    }

    fn albedo(&self) -> Rgb {
        self.specular
    }
}
