//! A blend of two materials, f = (1 - w) f_a + w f_b (Mitsuba's `blendbsdf`). Sampling
//! picks one by its weight; a smooth direction is then weighted by the whole mixture's f
//! and density, so that multiple importance sampling sees one BSDF.
//!
//! The arithmetic is written once over the lane type ([`MixtureLanes`], any two lane
//! kernels of any payload): the scalar [`Blend`] is its one-lane instance over the two
//! materials' BSDFs ([`OneBsdf`]), and lanes of two lane kinds mix in lanes with the
//! same floats per lane.

use super::{Bsdf, BsdfModel, BsdfSample, Gather, LaneKernel, LaneSample, SpecularRays, TransportMode};
use crate::Material;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::samplers::ONE_MINUS_EPSILON;
use penumbra_core::spectrum::Spectrum;
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug)]
pub struct Blend<'a> {
    pub a: &'a Material,
    pub b: &'a Material,
    /// Weight of `b`, in [0, 1].
    pub weight: f32,
    /// Where the two materials' textures are looked up.
    pub uv: Vec2,
}

/// Two BSDFs mixed per lane: `a` with weight 1 - `weight`, `b` with `weight`; a part of
/// weight 0 (or less) is left out, as if absent.
#[derive(Clone, Copy, Debug)]
pub struct MixtureLanes<R: Real, A, B> {
    pub a: A,
    pub b: B,
    pub weight: R,
}

/// One BSDF of one path in one transport mode, as a one-lane kernel (a blend's part; its
/// own sidedness and sample checks included, as [`Bsdf`] answers).
#[derive(Clone, Copy, Debug)]
pub struct OneBsdf<'a> {
    pub bsdf: Bsdf<'a>,
    pub mode: TransportMode,
}

impl LaneKernel<f32> for OneBsdf<'_> {
    #[inline(always)]
    fn eval(&self, wo: V3<f32>, wi: V3<f32>) -> V3<f32> {
        self.bsdf.eval(wo.into(), wi.into(), self.mode).into()
    }

    #[inline(always)]
    fn pdf(&self, wo: V3<f32>, wi: V3<f32>) -> f32 {
        self.bsdf.pdf(wo.into(), wi.into(), self.mode)
    }

    #[inline(always)]
    fn sample(&self, wo: V3<f32>, u_lobe: f32, u: (f32, f32)) -> LaneSample<f32> {
        match self.bsdf.sample(wo.into(), u_lobe, u.into(), self.mode) {
            Some(s) => LaneSample {
                wi: s.wi.into(),
                weight: s.weight.into(),
                pdf: s.pdf,
                delta: s.delta,
                eta: s.eta,
                ok: true,
            },
            None => LaneSample {
                wi: V3::splat(0.0),
                weight: V3::splat(0.0),
                pdf: 0.0,
                delta: false,
                eta: 1.0,
                ok: false,
            },
        }
    }
}

impl<'a> Blend<'a> {
    fn parts(&self) -> [(f32, Bsdf<'a>); 2] {
        [
            (1.0 - self.weight, self.a.bsdf(self.uv)),
            (self.weight, self.b.bsdf(self.uv)),
        ]
    }

    /// The one-lane instance of the arithmetic, for transport `mode`.
    #[inline(always)]
    pub fn lanes(&self, mode: TransportMode) -> MixtureLanes<f32, OneBsdf<'a>, OneBsdf<'a>> {
        MixtureLanes {
            a: OneBsdf {
                bsdf: self.a.bsdf(self.uv),
                mode,
            },
            b: OneBsdf {
                bsdf: self.b.bsdf(self.uv),
                mode,
            },
            weight: self.weight,
        }
    }
}

/// Eight mixtures of the same two kinds make an eight-lane mixture of the two kinds'
/// eight-lane kernels (parts of one-sided BSDFs: a part's own sidedness is the scalar
/// [`OneBsdf`]'s business).
impl<A: Gather, B: Gather> Gather for MixtureLanes<f32, A, B> {
    type Lanes<L: Lane8> = MixtureLanes<L, A::Lanes<L>, B::Lanes<L>>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> Self::Lanes<L> {
        MixtureLanes {
            a: A::gather(&one.map(|m| m.a)),
            b: B::gather(&one.map(|m| m.b)),
            weight: L::from_array(one.map(|m| m.weight)),
        }
    }
}

impl<R: Real, A, B> MixtureLanes<R, A, B> {
    /// The parts' weights, 1 - w and w.
    #[inline(always)]
    fn weights(&self) -> (R, R) {
        (R::splat(1.0) - self.weight, self.weight)
    }
}

/// `u_lobe` rescaled to [0, 1) within the part it chose: `u / wa` for part a, `(u - wa) /
/// wb` for part b, kept below one per lane (NaN gives the bound, as `f32::min`). The
/// wavefront's blend rounds rescale with it too (`integrators/bsdf_lanes/blends.rs`).
#[inline(always)]
pub(crate) fn part_lobe<R: Real>(u_lobe: R, (wa, wb): (R, R), part_a: bool) -> R {
    let u = if part_a { u_lobe / wa } else { (u_lobe - wa) / wb };
    let cap = R::splat(ONE_MINUS_EPSILON);
    R::select(u.cmp_lt(cap), u, cap)
}

/// Where a part's sample may be followed (`BsdfSample::usable`: a positive density, a
/// finite weight and direction), per lane.
#[inline(always)]
fn usable<R: Real, S: Spectrum<R>>(s: &LaneSample<R, S>) -> R::Mask {
    let mut finite = R::and(R::and(s.wi.x.is_finite(), s.wi.y.is_finite()), s.wi.z.is_finite());
    for i in 0..S::CHANNELS {
        finite = R::and(finite, s.weight.channel(i).is_finite());
    }
    R::and(s.ok, R::and(s.pdf.cmp_gt(R::splat(0.0)), finite))
}

impl<R: Real, S: Spectrum<R>, A: LaneKernel<R, S>, B: LaneKernel<R, S>> LaneKernel<R, S> for MixtureLanes<R, A, B> {
    /// (1 - w) f_a + w f_b, summed from black over the parts of positive weight (a part
    /// no lane weighs is not evaluated).
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        let (wa, wb) = self.weights();
        let (zero, black) = (R::splat(0.0), S::splat(0.0));
        let (in_a, in_b) = (wa.cmp_gt(zero), wb.cmp_gt(zero));
        let fa = penumbra_core::choose_lanes!(R, in_a, self.a.eval(wo, wi).scale(wa), black);
        let fb = penumbra_core::choose_lanes!(R, in_b, self.b.eval(wo, wi).scale(wb), black);
        (black + fa) + fb
    }

    /// (1 - w) pdf_a + w pdf_b, summed as `Iterator::sum` adds (from -0) over the parts of
    /// positive weight (a part no lane weighs is not evaluated).
    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let (wa, wb) = self.weights();
        let zero = R::splat(0.0);
        let (in_a, in_b) = (wa.cmp_gt(zero), wb.cmp_gt(zero));
        let sum = R::splat(-0.0);
        let sum = penumbra_core::choose_lanes!(R, in_a, sum + wa * self.a.pdf(wo, wi), sum);
        penumbra_core::choose_lanes!(R, in_b, sum + wb * self.b.pdf(wo, wi), sum)
    }

    /// A part chosen by its weight (`u_lobe` rescaled for it), then: a delta sample keeps
    /// its weight, its density times the choice's probability; a smooth one takes the
    /// whole mixture's value and density (none where that density is 0). Each step runs
    /// only where some lane needs it, so a one-lane instance stops where the part's
    /// sample fails.
    #[inline(always)]
    fn sample(&self, wo: V3<R>, u_lobe: R, u: (R, R)) -> LaneSample<R, S> {
        let (wa, wb) = self.weights();
        let take_a = u_lobe.cmp_lt(wa);
        let s = penumbra_core::choose_lanes!(
            R,
            take_a,
            {
                let s = self.a.sample(wo, part_lobe(u_lobe, (wa, wb), true), u);
                LaneSample { ok: usable(&s), ..s }
            },
            {
                let s = self.b.sample(wo, part_lobe(u_lobe, (wa, wb), false), u);
                LaneSample { ok: usable(&s), ..s }
            }
        );
        // Lanes done with their part's answer: a delta sample, or none.
        let done = R::or(s.delta, R::not(s.ok));
        penumbra_core::choose_lanes!(
            R,
            done,
            LaneSample {
                pdf: s.pdf * R::select(take_a, wa, wb),
                ..s
            },
            {
                let pdf = self.pdf(wo, s.wi);
                let positive = pdf.cmp_gt(R::splat(0.0));
                penumbra_core::choose_lanes!(
                    R,
                    positive,
                    LaneSample {
                        weight: self.eval(wo, s.wi).scale(s.wi.z.abs() / pdf),
                        pdf,
                        ..s
                    },
                    LaneSample {
                        pdf,
                        ok: R::splat_mask(false),
                        ..s
                    }
                )
            }
        )
    }
}

impl BsdfModel for Blend<'_> {
    super::one_lane_methods!();

    fn specular_rays(&self, wo: Vec3, mode: TransportMode, rays: &mut SpecularRays) {
        for (w, b) in self.parts() {
            if w > 0.0 {
                rays.extend_scaled(&b.specular_rays(wo, mode), w);
            }
        }
    }

    fn has_smooth(&self) -> bool {
        self.parts().iter().any(|(w, b)| *w > 0.0 && b.has_smooth())
    }

    fn albedo(&self) -> Rgb {
        self.parts().iter().fold(Rgb::BLACK, |a, (w, b)| a + b.albedo() * *w)
    }
}
