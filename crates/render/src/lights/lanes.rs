//! Light sampling written once over the lane type, as the BSDFs are (`bsdfs/mod.rs`'s
//! [`LaneKernel`](crate::bsdfs::LaneKernel)): a kind's `sample_li` arithmetic is a
//! [`LightKernel`] generic over [`Real`], its scalar `sample_li` the one-lane instance
//! ([`LaneLightSample::one`]), and eight lights of a kind (or one light for eight shading
//! points) make an eight-lane kernel by [`LightGather`].

use super::LightSample;
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;

/// [`LightSample`] in lanes of any [`Real`] type, with the lanes where a sample exists
/// (whether it is a delta sample is the kind's, not the lane's); the light in the path's
/// payload `S` (RGB by default, see [`Spectrum`]).
#[derive(Clone, Copy, Debug)]
pub struct LaneLightSample<R: Real, S: Spectrum<R> = V3<R>> {
    pub wi: V3<R>,
    pub li: S,
    pub dist: R,
    pub pdf: R,
    pub ok: R::Mask,
}

impl LaneLightSample<f32> {
    /// The one lane's sample, if it exists; `delta` from the kind.
    #[inline(always)]
    pub fn one(self, delta: bool) -> Option<LightSample> {
        self.ok.then(|| LightSample {
            wi: self.wi.into(),
            li: self.li.into(),
            dist: self.dist,
            pdf: self.pdf,
            delta,
        })
    }
}

/// A light kind's `sample_li` over the lane type `R`: light arriving at the points `p`,
/// each lane's point on the light (for lights with an extent) drawn from `u`.
pub trait LightKernel<R: Real, S: Spectrum<R> = V3<R>> {
    fn sample_li(&self, p: V3<R>, u: (R, R)) -> LaneLightSample<R, S>;
}

/// A kind's one-lane kernel that eight of make an eight-lane one.
pub trait LightGather: Copy {
    type Lanes<L: Lane8>: LightKernel<L>;
    fn gather<L: Lane8>(one: &[Self; 8]) -> Self::Lanes<L>;
}

/// Light from a point source of `intensity` at `position`, seen from `p`, per lane:
/// inverse-square falloff; none where `p` is the source or the intensity is black.
#[inline(always)]
pub(crate) fn delta_sample_lanes<R: Real, S: Spectrum<R>>(
    p: V3<R>,
    position: V3<R>,
    intensity: S,
) -> LaneLightSample<R, S> {
    let zero = R::splat(0.0);
    let to_light = position - p;
    let dist2 = to_light.dot(to_light);
    let dist = dist2.sqrt();
    LaneLightSample {
        wi: to_light.div_by(dist),
        li: intensity.scale(R::splat(1.0) / dist2),
        dist,
        pdf: R::splat(1.0),
        ok: R::and(R::not(dist2.cmp_eq(zero)), R::not(intensity.is_black())),
    }
}

/// Up to eight light samples of one kind's lights `one` (lanes past `n` repeat the last)
/// at points `p` from numbers `u`, run in eight lanes at the CPU's SIMD level; `delta`
/// from the kind. Lane `k` is what the kind's scalar `sample_li` gives for input `k`.
pub fn sample_li_lanes<G: LightGather>(
    one: &[G; 8],
    p: &[glam::Vec3; 8],
    u: &[glam::Vec2; 8],
    delta: bool,
) -> [Option<LightSample>; 8] {
    #[inline(always)]
    fn kernel<G: LightGather, L: Lane8>(
        one: &[G; 8],
        p: &[glam::Vec3; 8],
        u: &[glam::Vec2; 8],
        delta: bool,
    ) -> [Option<LightSample>; 8] {
        let s = G::gather::<L>(one).sample_li(
            V3::from_lanes(p),
            (L::from_array(u.map(|u| u.x)), L::from_array(u.map(|u| u.y))),
        );
        let ok = L::bits(s.ok);
        let (wi, li, dist, pdf) = (s.wi.to_lanes(), s.li.to_lanes(), s.dist.to_array(), s.pdf.to_array());
        std::array::from_fn(|k| {
            (ok >> k & 1 != 0).then(|| LightSample {
                wi: wi[k],
                li: penumbra_core::Rgb::new(li[k].x, li[k].y, li[k].z),
                dist: dist[k],
                pdf: pdf[k],
                delta,
            })
        })
    }
    #[cfg(target_arch = "x86_64")]
    penumbra_core::level_fns! {
        unsafe fn [avx2, avx512]<G: LightGather>(one: &[G; 8], p: &[glam::Vec3; 8], u: &[glam::Vec2; 8], delta: bool) -> [Option<LightSample>; 8] {
            kernel::<G, penumbra_core::lanes_avx::F8Avx>(one, p, u, delta)
        }
    }
    penumbra_core::at_level!(
        avx512: avx512(one, p, u, delta),
        avx2: avx2(one, p, u, delta),
        portable: kernel::<G, penumbra_core::lanes::F8>(one, p, u, delta)
    )
}
