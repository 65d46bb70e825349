//! The layered BSDF's random walks (the model is described in `layered.rs`) written once
//! over lanes of any [`Real`] type: its one-lane instance is the scalar
//! [`super::Layered`]. (Eight lanes at a time it is held to the one-lane bits by the
//! tests; the wavefront's BSDF stage runs it in the portable eight lanes at every SIMD
//! level, as three levels of this kernel cost the build too much.)
//! Each lane walks on its own: its own generator, its own number of events; a lane's
//! branches (scattering in the medium, the coating's underside, the base; a walk ending)
//! are masks, and a lane draws its random numbers exactly when, and in the order, the
//! walk of one path draws them, so lane `k` gives the one-lane floats bit for bit.

use super::{ConductorLanes, DielectricLanes, DiffuseLanes, Gather, LaneKernel, LaneSample, Lobe};
use crate::mis::MisHeuristic;
use crate::phase::{hg, sample_hg};
use penumbra_core::hash::hash_words;
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::Pcg32;
use std::f32::consts::PI;

/// What lies under the coating, per lane: a diffuse or a conductor kernel (both are held,
/// `metal` says which a lane uses, so that one group of lanes may mix them).
#[derive(Clone, Copy)]
pub struct BaseLanes<R: Real, S: Spectrum<R> = V3<R>> {
    pub diffuse: DiffuseLanes<R, S>,
    pub conductor: ConductorLanes<R, S>,
    /// Lanes whose base is the conductor.
    pub metal: R::Mask,
    /// Lanes whose base is a smooth mirror: no density to weigh, nothing for next-event
    /// estimation.
    pub specular: R::Mask,
}

/// `$metal` where the lanes' base is the conductor, else `$diffuse`, evaluating only the
/// sides some lane takes (so that the one-lane instance runs only its own).
macro_rules! by_base {
    ($base:expr, $metal:expr, $diffuse:expr) => {
        penumbra_core::choose_lanes!(R, $base.metal, $metal, $diffuse)
    };
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for BaseLanes<R, S> {
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        by_base!(self, self.conductor.eval(wo, wi), self.diffuse.eval(wo, wi))
    }

    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        by_base!(self, self.conductor.pdf(wo, wi), self.diffuse.pdf(wo, wi))
    }

    /// A bounce, kept only where it carries light (a positive density, off the plane).
    #[inline(always)]
    fn sample(&self, wo: V3<R>, u_lobe: R, u: (R, R)) -> LaneSample<R, S> {
        usable(by_base!(
            self,
            self.conductor.sample(wo, u_lobe, u),
            self.diffuse.sample(wo, u_lobe, u)
        ))
    }
}

/// A coating over a base, `thickness` apart, with a medium of single-scattering `albedo`
/// and Henyey-Greenstein asymmetry `g` between, per lane; estimates average `samples`
/// walks of at most `max_depth` events (both whole numbers, held as floats).
#[derive(Clone, Copy)]
pub struct LayeredLanes<R: Real, S: Spectrum<R> = V3<R>> {
    /// The coating, in the transport mode of the lanes.
    pub coat: DielectricLanes<R, S>,
    pub base: BaseLanes<R, S>,
    pub thickness: R,
    pub albedo: S,
    /// The asymmetry, clamped as [`crate::phase::HenyeyGreenstein::new`] clamps it.
    pub g: R,
    pub max_depth: R,
    /// At least 1.
    pub samples: R,
}

/// The sample where it carries light: a positive density, a direction off the plane and
/// a weight that is not black (the walk drops the others).
#[inline(always)]
fn usable<R: Real, S: Spectrum<R>>(mut s: LaneSample<R, S>) -> LaneSample<R, S> {
    let zero = R::splat(0.0);
    let off_plane = R::not(s.wi.z.cmp_eq(zero));
    s.ok = R::and(
        R::and(s.ok, s.pdf.cmp_gt(zero)),
        R::and(off_plane, R::not(s.weight.is_black())),
    );
    s
}

/// Veach's power heuristic (β = 2) for one sample of each of two strategies.
#[inline(always)]
fn power<R: Real>(a: R, b: R) -> R {
    MisHeuristic::Power.weight_lanes(a, b)
}

/// Transmittance across a height `dz` of the unit-extinction medium along `w`
/// (pbrt-v4's `Tr`).
#[inline(always)]
pub(super) fn transmittance<R: Real>(dz: R, w: V3<R>) -> R {
    let [e] = R::map_lanes([-(dz / w.z).abs()], |_, [x]| [x.exp()]);
    R::select(dz.abs().cmp_le(R::splat(f32::MIN_POSITIVE)), R::splat(1.0), e)
}

/// The height crossed along `w` by a free flight drawn from `u` in the unit-extinction
/// medium: -ln(1 - u) |w.z|.
#[inline(always)]
fn free_flight<R: Real>(u: R, w: V3<R>) -> R {
    let [ln] = R::map_lanes([R::splat(1.0) - u], |_, [x]| [x.ln()]);
    -ln * w.z.abs()
}

/// `x` clamped to `[0, h]` as `f32::clamp` does.
#[inline(always)]
fn clamp_height<R: Real>(x: R, h: R) -> R {
    let zero = R::splat(0.0);
    let x = R::select(x.cmp_lt(zero), zero, x);
    R::select(x.cmp_gt(h), h, x)
}

/// Each lane's random numbers: a generator seeded by hashing the estimate's arguments, so
/// that an estimate is a deterministic function of them (as pbrt-v4 seeds its `RNG`).
struct Walks([Pcg32; 8]);

impl Walks {
    /// Lane `k`'s generator from lane `k` of `a` and of `b`.
    #[inline(always)]
    fn seeded<R: Real>(a: V3<R>, b: [R; 3]) -> Self {
        let mut walks: [Pcg32; 8] = std::array::from_fn(|_| Pcg32::new(0, 0));
        let words = |v: [f32; 3]| hash_words(&v.map(|x| x.to_bits() as u64));
        R::map_lanes([a.x, a.y, a.z, b[0], b[1], b[2]], |k, v| {
            walks[k] = Pcg32::new(words([v[0], v[1], v[2]]), words([v[3], v[4], v[5]]));
            [] as [f32; 0]
        });
        Walks(walks)
    }

    /// `N` numbers for each lane in `on`, in order, from its own generator (zeros elsewhere).
    #[inline(always)]
    fn next<R: Real, const N: usize>(&mut self, on: R::Mask) -> [R; N] {
        let flag = R::select(on, R::splat(1.0), R::splat(0.0));
        R::map_lanes([flag], |k, [flag]| {
            std::array::from_fn(|_| if flag != 0.0 { self.0[k].next_f32() } else { 0.0 })
        })
    }

    #[inline(always)]
    fn next2<R: Real>(&mut self, on: R::Mask) -> (R, R) {
        let [a, b] = self.next(on);
        (a, b)
    }
}

impl<R: Real, S: Spectrum<R>> LayeredLanes<R, S> {
    /// Lanes whose coating is a smooth interface.
    #[inline(always)]
    fn coat_specular(&self) -> R::Mask {
        R::not(self.coat.rough)
    }

    /// Russian roulette on the throughput `beta` after the fourth event (pbrt-v4's rule),
    /// for the lanes `alive`: the survival probabilities (1 where no game is played) and
    /// the lanes still alive.
    #[inline(always)]
    fn roulette(depth: u32, beta: S, alive: R::Mask, walks: &mut Walks) -> (R, R::Mask) {
        let one = R::splat(1.0);
        if depth <= 3 {
            return (one, alive);
        }
        let b = beta.max_channel();
        let play = R::and(alive, R::not(b.cmp_ge(R::splat(0.25))));
        let q = (one - b).max(R::splat(0.0));
        let [u] = walks.next::<R, 1>(play);
        let ends = R::and(play, R::not(u.cmp_ge(q)));
        (R::select(play, one - q, one), R::and(alive, R::not(ends)))
    }

    /// One walk's estimate of f(wo, wi) without the coating's direct reflection, in the
    /// lanes `on` (pbrt-v4's `LayeredBxDF::f` loop body, with the top as the entrance and
    /// exit interface).
    #[inline]
    fn walk_eval(&self, wo: V3<R>, wi: V3<R>, on: R::Mask, walks: &mut Walks) -> S {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let mut f = S::splat(0.0);
        // The walk in from wo, and the direction sampled in from wi for the estimates out
        // along it. When that one fails (a microfacet that totally reflects), only those
        // estimates are lost: the others, out along the walk's own directions, still count.
        let wos = usable(self.coat.sample_lobe(wo, walks.next2(on), Lobe::Transmission));
        let wis = usable(self.coat.adjoint().sample_lobe(wi, walks.next2(on), Lobe::Transmission));
        let h = self.thickness;
        let (scatters, coat_specular) = (R::not(self.albedo.is_black()), self.coat_specular());
        let (mut beta, mut z, mut w) = (wos.weight, h, wos.wi);
        let mut alive = R::and(on, wos.ok);
        // A next-event estimate at event `depth` stands for a walk that leaves at event
        // `depth + 1`: stopping one event early keeps eval's walks as long as sample's
        // (pbrt-v4 runs both to max_depth, so its f counts, behind a medium, walks one
        // event longer than its sampling can make: 0.8% more light, measured).
        let events = (self.max_depth - one).max(zero);
        for depth in 0u32.. {
            alive = R::and(alive, R::splat(depth as f32).cmp_lt(events));
            if !R::any(alive) {
                break;
            }
            let survive;
            (survive, alive) = Self::roulette(depth, beta, alive, walks);
            beta = S::select(alive, beta.scale(one / survive), beta);
            // Through the medium: a free flight where it scatters, else straight across.
            let (plain, scat) = (R::and(alive, R::not(scatters)), R::and(alive, scatters));
            let [u] = walks.next::<R, 1>(scat);
            let dz = free_flight(u, w);
            let zp = R::select(w.z.cmp_gt(zero), z + dz, z - dz);
            let stays = R::and(scat, zp.cmp_eq(z));
            let inside = R::and(R::and(scat, R::not(stays)), R::and(zero.cmp_lt(zp), zp.cmp_lt(h)));
            if R::any(inside) {
                // Scattering in the medium: out along wis, then on by the phase function
                // and out along its direction, the two weighed against each other.
                let out_wis = R::and(inside, wis.ok);
                if R::any(out_wis) {
                    let p = hg((-w).dot(-wis.wi), self.g);
                    let wt = R::select(coat_specular, one, power(wis.pdf, p));
                    let out = transmittance(zp - h, wis.wi) * wt * p / wis.wi.z.abs();
                    let add = beta.mul_each(self.albedo).mul_each(wis.weight).scale(out);
                    f = S::select(out_wis, f + add, f);
                }
                let (next, pdf) = sample_hg(self.g, -w, walks.next2(inside));
                let moved = R::and(inside, R::not(R::or(pdf.cmp_le(zero), next.z.cmp_eq(zero))));
                beta = S::select(moved, beta.mul_each(self.albedo), beta);
                (w, z) = (V3::select(moved, next, w), R::select(moved, zp, z));
                let exits = R::and(R::and(moved, w.z.cmp_gt(zero)), R::not(coat_specular));
                if R::any(exits) {
                    let f_exit = self.coat.eval(-w, wi);
                    let wt = power(pdf, self.coat.pdf_lobe(wi, -w, Lobe::Transmission));
                    let add = beta.mul_each(f_exit).scale(transmittance(zp - h, w) * wt);
                    f = S::select(R::and(exits, R::not(f_exit.is_black())), f + add, f);
                }
            }
            let crossing = R::and(scat, R::not(R::or(stays, inside)));
            z = R::select(crossing, clamp_height(zp, h), z);
            z = R::select(plain, R::select(z.cmp_eq(h), zero, h), z);
            beta = S::select(plain, beta.scale(transmittance(h, w)), beta);
            let at = R::or(plain, crossing);
            let (top, bottom) = (R::and(at, z.cmp_eq(h)), R::and(at, R::not(z.cmp_eq(h))));
            if R::any(top) {
                // Back down off the coating's underside.
                let s = usable(self.coat.sample_lobe(-w, walks.next2(top), Lobe::Reflection));
                let ok = R::and(top, s.ok);
                alive = R::and(alive, R::not(R::and(top, R::not(s.ok))));
                (beta, w) = (S::select(ok, beta.mul_each(s.weight), beta), V3::select(ok, s.wi, w));
            }
            if R::any(bottom) {
                // On the base: out along wis, then a bounce, and out along the bounce's
                // direction.
                let out_wis = R::and(R::and(bottom, wis.ok), R::not(self.base.specular));
                if R::any(out_wis) {
                    let wt = R::select(coat_specular, one, power(wis.pdf, self.base.pdf(-w, -wis.wi)));
                    let fb = self.base.eval(-w, -wis.wi);
                    let add = beta
                        .mul_each(fb)
                        .mul_each(wis.weight)
                        .scale(wt * transmittance(h, wis.wi));
                    f = S::select(out_wis, f + add, f);
                }
                let [u_lobe, u0, u1] = walks.next(bottom);
                let s = self.base.sample(-w, u_lobe, (u0, u1));
                let ok = R::and(bottom, s.ok);
                alive = R::and(alive, R::not(R::and(bottom, R::not(s.ok))));
                (beta, w) = (S::select(ok, beta.mul_each(s.weight), beta), V3::select(ok, s.wi, w));
                let exits = R::and(ok, R::not(coat_specular));
                if R::any(exits) {
                    let f_exit = self.coat.eval(-w, wi);
                    let t_pdf = self.coat.pdf_lobe(wi, -w, Lobe::Transmission);
                    let wt = R::select(self.base.specular, one, power(s.pdf, t_pdf));
                    let add = beta.mul_each(f_exit).scale(transmittance(h, w) * wt);
                    f = S::select(R::and(exits, R::not(f_exit.is_black())), f + add, f);
                }
            }
        }
        f
    }

    /// Lanes whose directions are both above the surface (as `!(z <= 0)`, like the scalar
    /// tests it replaces).
    #[inline(always)]
    fn upper(wo: V3<R>, wi: V3<R>) -> R::Mask {
        let zero = R::splat(0.0);
        R::not(R::or(wo.z.cmp_le(zero), wi.z.cmp_le(zero)))
    }
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for LayeredLanes<R, S> {
    /// The coating's reflection plus the mean of `samples` walks' estimates.
    #[inline]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        let upper = Self::upper(wo, wi);
        if !R::any(upper) {
            return S::splat(0.0);
        }
        let mut walks = Walks::seeded(wo, [wi.x, wi.y, wi.z]);
        let n = self.samples;
        let mut f = self.coat.eval(wo, wi).scale(n);
        for k in 0u32.. {
            let on = R::and(upper, R::splat(k as f32).cmp_lt(n));
            if !R::any(on) {
                break;
            }
            let walk = self.walk_eval(wo, wi, on, &mut walks);
            f = S::select(on, f + walk, f);
        }
        S::select(upper, f.scale(R::splat(1.0) / n), S::splat(0.0))
    }

    /// An estimate proportional to the density (pbrt-v4's `pdfIsProportional`): 0.9 of the
    /// coating's reflection and the base's lobe seen through the coating, 0.1 uniform.
    #[inline]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let upper = Self::upper(wo, wi);
        if !R::any(upper) {
            return R::splat(0.0);
        }
        let mut walks = Walks::seeded(wi, [wo.x, wo.y, wo.z]);
        let n = self.samples;
        let (coat_specular, adjoint) = (self.coat_specular(), self.coat.adjoint());
        let mut sum = n * self.coat.pdf_lobe(wo, wi, Lobe::Reflection);
        for k in 0u32.. {
            let on = R::and(upper, R::splat(k as f32).cmp_lt(n));
            if !R::any(on) {
                break;
            }
            let wos = usable(self.coat.sample_lobe(wo, walks.next2(on), Lobe::Transmission));
            let wis = usable(adjoint.sample_lobe(wi, walks.next2(on), Lobe::Transmission));
            let both = R::and(on, R::and(wos.ok, wis.ok));
            let through = R::and(both, coat_specular);
            if R::any(through) {
                sum = R::select(through, sum + self.base.pdf(-wos.wi, -wis.wi), sum);
            }
            let rest = R::and(both, R::not(coat_specular));
            if !R::any(rest) {
                continue;
            }
            let [u_lobe, u0, u1] = walks.next(rest);
            let rs = self.base.sample(-wos.wi, u_lobe, (u0, u1));
            let ok = R::and(rest, rs.ok);
            let t_pdf = self.coat.pdf(-rs.wi, wi);
            let mirror = R::and(ok, self.base.specular);
            sum = R::select(mirror, sum + t_pdf, sum);
            // The base's density at the pair, and the coating's at the bounce, each weighed
            // against the other strategy for the same direction.
            let smooth = R::and(ok, R::not(self.base.specular));
            if R::any(smooth) {
                let r_pdf = self.base.pdf(-wos.wi, -wis.wi);
                let add = power(wis.pdf, r_pdf) * r_pdf + power(rs.pdf, t_pdf) * t_pdf;
                sum = R::select(smooth, sum + add, sum);
            }
        }
        let p = R::splat(0.1 / (2.0 * PI)) + R::splat(0.9) * sum / n;
        R::select(upper, p, R::splat(0.0))
    }

    /// The coating's sample; a refraction goes on as a walk until it leaves through the
    /// top, its weight the walk's throughput and its density the product of its choices
    /// (a delta walk) or [`LaneKernel::pdf`]'s estimate.
    #[inline]
    fn sample(&self, wo: V3<R>, u_lobe: R, u: (R, R)) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let first = self.coat.sample(wo, u_lobe, u);
        let exists = R::and(
            R::and(R::not(wo.z.cmp_le(zero)), first.ok),
            R::and(R::not(first.weight.is_black()), R::not(first.wi.z.cmp_eq(zero))),
        );
        let direct = R::and(exists, first.wi.z.cmp_gt(zero));
        let mut alive = R::and(exists, R::not(direct));
        let h = self.thickness;
        let scatters = R::not(self.albedo.is_black());
        let (mut beta, mut pdf, mut delta) = (first.weight, first.pdf, first.delta);
        let (mut z, mut w) = (h, first.wi);
        // Where each walk left through the top.
        let mut out = LaneSample {
            ok: R::splat_mask(false),
            ..first
        };
        if R::any(alive) {
            let mut walks = Walks::seeded(wo, [u_lobe, u.0, u.1]);
            for depth in 0u32.. {
                alive = R::and(alive, R::splat(depth as f32).cmp_lt(self.max_depth));
                if !R::any(alive) {
                    break;
                }
                let survive;
                (survive, alive) = Self::roulette(depth, beta, alive, &mut walks);
                beta = S::select(alive, beta.scale(one / survive), beta);
                pdf = R::select(alive, pdf * survive, pdf);
                let (plain, scat) = (R::and(alive, R::not(scatters)), R::and(alive, scatters));
                let [u] = walks.next::<R, 1>(scat);
                let dz = free_flight(u, w);
                let zp = R::select(w.z.cmp_gt(zero), z + dz, z - dz);
                let stays = R::and(scat, zp.cmp_eq(z));
                alive = R::and(alive, R::not(stays));
                let inside = R::and(R::and(scat, R::not(stays)), R::and(zero.cmp_lt(zp), zp.cmp_lt(h)));
                if R::any(inside) {
                    let (next, p) = sample_hg(self.g, -w, walks.next2(inside));
                    let fails = R::and(inside, R::or(p.cmp_le(zero), next.z.cmp_eq(zero)));
                    alive = R::and(alive, R::not(fails));
                    let moved = R::and(inside, R::not(fails));
                    beta = S::select(moved, beta.mul_each(self.albedo), beta);
                    pdf = R::select(moved, pdf * p, pdf);
                    delta = R::select_mask(moved, R::splat_mask(false), delta);
                    (w, z) = (V3::select(moved, next, w), R::select(moved, zp, z));
                }
                let crossing = R::and(scat, R::not(R::or(stays, inside)));
                z = R::select(crossing, clamp_height(zp, h), z);
                z = R::select(plain, R::select(z.cmp_eq(h), zero, h), z);
                beta = S::select(plain, beta.scale(transmittance(h, w)), beta);
                let at = R::or(plain, crossing);
                if !R::any(at) {
                    continue;
                }
                // Off the base or the coating's underside.
                let [u_lobe, u0, u1] = walks.next(at);
                let s = by_base_or_coat(self, z.cmp_eq(zero), -w, u_lobe, (u0, u1));
                let fails = R::or(
                    R::or(R::not(s.ok), s.weight.is_black()),
                    R::or(s.pdf.cmp_le(zero), s.wi.z.cmp_eq(zero)),
                );
                alive = R::and(alive, R::not(R::and(at, fails)));
                let ok = R::and(at, R::not(fails));
                beta = S::select(ok, beta.mul_each(s.weight), beta);
                pdf = R::select(ok, pdf * s.pdf, pdf);
                delta = R::select_mask(ok, R::and(delta, s.delta), delta);
                w = V3::select(ok, s.wi, w);
                // Out through the coating. (A delta walk's product of choices may underflow
                // to 0 after many events: it is still the walk's, and kept.)
                let leaves = R::and(R::and(ok, z.cmp_eq(h)), w.z.cmp_gt(zero));
                out.wi = V3::select(leaves, w, out.wi);
                out.weight = S::select(leaves, beta, out.weight);
                out.pdf = R::select(leaves, pdf, out.pdf);
                out.delta = R::select_mask(leaves, delta, out.delta);
                out.ok = R::or(out.ok, leaves);
                alive = R::and(alive, R::not(leaves));
            }
        }
        let wi = V3::select(direct, first.wi, out.wi);
        let estimate = R::or(R::and(direct, R::not(first.delta)), R::and(out.ok, R::not(out.delta)));
        let estimated = if R::any(estimate) { self.pdf(wo, wi) } else { zero };
        let walked = out.pdf.max(R::splat(f32::MIN_POSITIVE));
        let pdf = R::select(estimate, estimated, R::select(direct, first.pdf, walked));
        LaneSample {
            wi,
            weight: S::select(direct, first.weight, out.weight),
            pdf,
            delta: R::select_mask(direct, first.delta, out.delta),
            eta: R::select(direct, first.eta, one),
            ok: R::or(direct, R::and(out.ok, pdf.cmp_gt(zero))),
        }
    }
}

/// The base's sample where `on_base`, else the coating's (its underside), from the same
/// numbers.
#[inline(always)]
fn by_base_or_coat<R: Real, S: Spectrum<R>>(
    l: &LayeredLanes<R, S>,
    on_base: R::Mask,
    wo: V3<R>,
    u_lobe: R,
    u: (R, R),
) -> LaneSample<R, S> {
    penumbra_core::choose_lanes!(R, on_base, l.base.sample(wo, u_lobe, u), l.coat.sample(wo, u_lobe, u))
}

impl Gather for LayeredLanes<f32> {
    type Lanes<L: Lane8> = LayeredLanes<L>;
    /// Eight layered BSDFs of one transport mode (the first's).
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> LayeredLanes<L> {
        let real = |f: fn(&Self) -> f32| L::from_array(one.each_ref().map(f));
        LayeredLanes {
            coat: Gather::gather(&one.map(|l| l.coat)),
            base: BaseLanes {
                diffuse: Gather::gather(&one.map(|l| l.base.diffuse)),
                conductor: Gather::gather(&one.map(|l| l.base.conductor)),
                metal: L::mask_of(one.map(|l| l.base.metal)),
                specular: L::mask_of(one.map(|l| l.base.specular)),
            },
            thickness: real(|l| l.thickness),
            albedo: V3::gather(one, |l| l.albedo),
            g: real(|l| l.g),
            max_depth: real(|l| l.max_depth),
            samples: real(|l| l.samples),
        }
    }
}

#[cfg(test)]
impl LayeredLanes<f32> {
    /// The estimates (without the coating's own reflection) of `n` successive walks from
    /// one generator seeded by `seed`, to test the walks apart from their seeding.
    pub(super) fn walk_estimates(
        &self,
        wo: glam::Vec3,
        wi: glam::Vec3,
        n: usize,
        seed: u64,
    ) -> Vec<penumbra_core::Rgb> {
        let mut walks = Walks(std::array::from_fn(|_| Pcg32::new(seed, 0)));
        (0..n)
            .map(|_| self.walk_eval(wo.into(), wi.into(), true, &mut walks).into())
            .collect()
    }
}
