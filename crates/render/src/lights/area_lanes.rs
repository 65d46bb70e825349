//! A triangle light sampled by area, in lanes that each hold their own triangle:
//! [`TriangleByArea`], the arithmetic of `Emitter::sample_uniform` (a point uniform over
//! the triangle, pbrt-v4 section 6.5.1, and its solid-angle density dist² / (|cos θ| A))
//! followed by the area light's sample (direction, distance, radiance of the emitting
//! side), written once over the lane type. The scalar area light's sample of an
//! untextured triangle by area is its one-lane instance; the wavefront's light stage and
//! the path tracer's eight-lane Lambertian bounce run it eight lanes at a time.

use super::area::{emits_towards, towards_point_lanes};
use super::emitter::{area_to_solid_angle, triangle_point};
use super::lanes::{LaneLightSample, LightGather, LightKernel};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::warp::uniform_triangle_lanes;

/// An untextured triangle light per lane, sampled uniformly by area.
#[derive(Clone, Copy)]
pub struct TriangleByArea<R: Real, S: Spectrum<R> = V3<R>> {
    pub v: [V3<R>; 3],
    /// The unit normal of the emitting (front) side.
    pub normal: V3<R>,
    pub area: R,
    pub radiance: S,
    pub two_sided: R::Mask,
}

impl<R: Real, S: Spectrum<R>> LightKernel<R, S> for TriangleByArea<R, S> {
    /// A sample where the density is defined (not grazing, not at the light's point) and
    /// the distance positive and finite; black where the emitting side faces away.
    #[inline(always)]
    fn sample_li(&self, p: V3<R>, u: (R, R)) -> LaneLightSample<R, S> {
        let (b1, b2) = uniform_triangle_lanes(u.0, u.1);
        let point = triangle_point(self.v, b1, b2);
        let (pdf, defined) = area_to_solid_angle(p, point, self.normal, self.area);
        sample_at(p, point, self.normal, (pdf, defined), || self.radiance, self.two_sided)
    }
}

/// The sample at `p` of `point`, a point of an area light of normal `normal` drawn with
/// solid-angle density `pdf.0` (defined where `pdf.1`), whose emitting side (or sides)
/// sends `radiance()` there: the direction and distance to it, and the radiance arriving
/// (black where the emitting side faces away; `radiance` is called only if some lane's
/// side faces `p`, so a textured light skips its lookup otherwise), per lane of any
/// [`Real`] type. Every area light's sample ends here, whatever drew the point.
#[inline(always)]
pub(super) fn sample_at<R: Real, S: Spectrum<R>>(
    p: V3<R>,
    point: V3<R>,
    normal: V3<R>,
    pdf: (R, R::Mask),
    radiance: impl FnOnce() -> S,
    two_sided: R::Mask,
) -> LaneLightSample<R, S> {
    let (pdf, defined) = pdf;
    let (wi, dist, sane) = towards_point_lanes(p, point, pdf);
    let emits = emits_towards(normal, -wi, two_sided);
    LaneLightSample {
        wi,
        li: penumbra_core::choose_lanes!(R, emits, radiance(), S::splat(0.0)),
        dist,
        pdf,
        ok: R::and(defined, sane),
    }
}

impl LightGather for TriangleByArea<f32> {
    type Lanes<L: Lane8> = TriangleByArea<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> TriangleByArea<L> {
        TriangleByArea {
            v: std::array::from_fn(|i| V3::gather(one, |l| l.v[i])),
            normal: V3::gather(one, |l| l.normal),
            area: L::from_array(one.map(|l| l.area)),
            radiance: V3::gather(one, |l| l.radiance),
            two_sided: L::mask_of(one.map(|l| l.two_sided)),
        }
    }
}
