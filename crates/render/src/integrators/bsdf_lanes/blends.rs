//! Blends answered through their parts' own kinds: a blend's parts are asked as shading
//! points of their own (in the blend's frame, seen from its side), bucketed by kind with
//! every other point of that kind, and the parts' answers are then mixed in lanes by the
//! blend's own arithmetic ([`MixtureLanes`]) over a kernel that replays them
//! ([`Recorded`]). Each kind's kernel is compiled once, not once per pair of kinds; a part
//! of any kind (a layered BSDF, a blend) goes where points of that kind go.
//!
//! [`MixtureLanes::sample`] asks its parts in two rounds, and so do the asks here: first
//! the part that `u_lobe` chooses for a sample (with `u_lobe` rescaled as the mixture
//! rescales it) and every part of positive weight for its value and density towards the
//! light; then, where the chosen part's sample is not a delta one, every part of positive
//! weight for its value and density in the sampled direction. Only the chosen part is
//! asked for a sample (`BsdfQuery::sample`), so a blend of blends, asked for values alone,
//! asks its own parts for values alone, as the scalar mixture does. The replay gives back what a
//! part answered for the direction it is asked about, so a blend's answer has the bits of
//! its scalar BSDF (`blends_answered_in_lanes_give_the_scalar_answers`).

use super::{answer_lanes, run_kernel, BsdfAnswer, BsdfQuery, Buckets};
use crate::bsdfs::{flip, Blend, BsdfKind, BsdfSample, Gather, LaneKernel, LaneSample, MixtureLanes};
use crate::integrators::nee::Shading;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, V3};
use penumbra_core::samplers::ONE_MINUS_EPSILON;
use penumbra_core::Rgb;

/// One part of one blend point, as its own kind answered it: towards the light (in the
/// frame the parts see), with the part's sample if it is the chosen one, and in the
/// sampled direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct Recorded {
    light: Option<Vec3>,
    f_light: Vec3,
    pdf_light: f32,
    sample: Option<BsdfSample>,
    f_sample: Vec3,
    pdf_sample: f32,
}

/// Eight lanes' [`Recorded`] answers.
pub(super) struct RecordedLanes<L: Lane8> {
    lit: L::Mask,
    light: V3<L>,
    f_light: V3<L>,
    pdf_light: L,
    f_sample: V3<L>,
    pdf_sample: L,
    sample: LaneSample<L>,
}

impl Gather for Recorded {
    type Lanes<L: Lane8> = RecordedLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> RecordedLanes<L> {
        let none = BsdfSample {
            wi: Vec3::ZERO,
            weight: Rgb::BLACK,
            pdf: 0.0,
            delta: false,
            eta: 1.0,
        };
        let s = one.map(|r| r.sample.unwrap_or(none));
        let rgb = |c: Rgb| Vec3::new(c.r, c.g, c.b);
        RecordedLanes {
            lit: L::mask_of(one.map(|r| r.light.is_some())),
            light: V3::gather(one, |r| r.light.unwrap_or(Vec3::ZERO)),
            f_light: V3::gather(one, |r| r.f_light),
            pdf_light: L::from_array(one.map(|r| r.pdf_light)),
            f_sample: V3::gather(one, |r| r.f_sample),
            pdf_sample: L::from_array(one.map(|r| r.pdf_sample)),
            sample: LaneSample {
                wi: V3::gather(&s, |s| s.wi),
                weight: V3::gather(&s, |s| rgb(s.weight)),
                pdf: L::from_array(s.map(|s| s.pdf)),
                delta: L::mask_of(s.map(|s| s.delta)),
                eta: L::from_array(s.map(|s| s.eta)),
                ok: L::mask_of(one.map(|r| r.sample.is_some())),
            },
        }
    }
}

impl<L: Lane8> RecordedLanes<L> {
    /// Lanes asked about their light's direction (else the sampled one).
    #[inline(always)]
    fn at_light(&self, wi: V3<L>) -> L::Mask {
        let same = L::and(
            L::and(wi.x.cmp_eq(self.light.x), wi.y.cmp_eq(self.light.y)),
            wi.z.cmp_eq(self.light.z),
        );
        L::and(self.lit, same)
    }
}

impl<L: Lane8> LaneKernel<L> for RecordedLanes<L> {
    #[inline(always)]
    fn eval(&self, _wo: V3<L>, wi: V3<L>) -> V3<L> {
        V3::select(self.at_light(wi), self.f_light, self.f_sample)
    }

    #[inline(always)]
    fn pdf(&self, _wo: V3<L>, wi: V3<L>) -> L {
        L::select(self.at_light(wi), self.pdf_light, self.pdf_sample)
    }

    #[inline(always)]
    fn sample(&self, _wo: V3<L>, _u_lobe: L, _u: (L, L)) -> LaneSample<L> {
        self.sample
    }
}

/// `u.min(ONE_MINUS_EPSILON)` (NaN gives the bound), as the mixture rescales `u_lobe`.
fn below_one(u: f32) -> f32 {
    if u < ONE_MINUS_EPSILON {
        u
    } else {
        ONE_MINUS_EPSILON
    }
}

/// A blend point's blend, its parts' weights and the mirroring of its two-sided rule.
fn blend_of<'s>(sh: &Shading<'s>) -> (Blend<'s>, [f32; 2], impl Fn(Vec3) -> Vec3) {
    let BsdfKind::Blend(b) = sh.bsdf.kind else {
        unreachable!("only blends are answered here")
    };
    let mirrored = sh.bsdf.mirrored(sh.wo);
    (
        b,
        [1.0 - b.weight, b.weight],
        move |w| if mirrored { flip(w) } else { w },
    )
}

/// Asks of one round: the parts as shading points, what each is asked, and the answers.
struct Round<'s> {
    shs: Vec<Shading<'s>>,
    queries: Vec<BsdfQuery>,
    answers: Vec<BsdfAnswer>,
}

/// Part `k` of the blend at `sh` as a shading point of its own: the part's BSDF, seen
/// from the blend's side.
fn part_of<'s>(sh: &Shading<'s>, k: usize) -> Shading<'s> {
    let (b, _, side) = blend_of(sh);
    Shading {
        it: sh.it,
        bsdf: [b.a, b.b][k].bsdf(b.uv),
        frame: sh.frame,
        wo: side(sh.wo),
        ng: sh.ng,
        origin: sh.origin,
    }
}

impl<'s> Round<'s> {
    /// Room for `n` asks (two per blend point at most).
    fn with_capacity(n: usize) -> Self {
        Round {
            shs: Vec::with_capacity(n),
            queries: Vec::with_capacity(n),
            answers: Vec::with_capacity(n),
        }
    }

    /// Asks `part` `query`; its place among the asks.
    fn ask(&mut self, part: Shading<'s>, query: BsdfQuery) -> Option<usize> {
        self.shs.push(part);
        self.queries.push(query);
        Some(self.shs.len() - 1)
    }

    /// The part asked at `at`, again (its BSDF not made anew).
    fn part(&self, at: usize) -> Shading<'s> {
        let p = &self.shs[at];
        Shading {
            it: p.it,
            bsdf: p.bsdf,
            frame: p.frame,
            wo: p.wo,
            ng: p.ng,
            origin: p.origin,
        }
    }

    /// Answers the round's asks by kind in `buckets`.
    fn answer(&mut self, buckets: &mut Buckets) {
        self.answers.clear();
        self.answers.resize(self.shs.len(), BsdfAnswer::default());
        buckets.answer(&self.shs, &self.queries, &mut self.answers);
    }

    fn get(&self, at: Option<usize>) -> Option<BsdfAnswer> {
        at.map(|j| self.answers[j])
    }
}

/// Answers `queries[i]` of the blend points `shs[i]`, `i` in `points`, into `out[i]`: the
/// parts asked in `parts`' buckets, then mixed in lanes.
pub(super) fn answer_blends<'s>(
    points: &[usize],
    parts: &mut Buckets,
    shs: &[Shading<'s>],
    queries: &[BsdfQuery],
    out: &mut [BsdfAnswer],
) {
    // First round: the chosen part's sample, every weighed part towards the light.
    let mut first = Round::with_capacity(2 * points.len());
    let mut asked = Vec::with_capacity(points.len());
    for &i in points {
        let (sh, q) = (&shs[i], &queries[i]);
        let (_, [wa, wb], side) = blend_of(sh);
        let take_a = q.u_lobe < wa;
        let u_lobe = below_one(if take_a { q.u_lobe / wa } else { (q.u_lobe - wa) / wb });
        // The density too, whatever the point needs: the sampled direction may be the
        // light's, whose answer the replay then gives back.
        let light = q.light.map(|(l, _)| (side(l), true));
        // (A point that wants no sample chooses no part.)
        let chosen = q.sample.then_some(if take_a { 0 } else { 1 });
        let mut at = [None; 2];
        for (k, w) in [wa, wb].into_iter().enumerate() {
            let sample = chosen == Some(k);
            if sample || (w > 0.0 && light.is_some()) {
                let query = BsdfQuery {
                    light,
                    sample,
                    u_lobe,
                    u: q.u,
                };
                at[k] = first.ask(part_of(sh, k), query);
            }
        }
        asked.push((at, chosen));
    }
    first.answer(parts);
    // Second round: every weighed part in the direction of a smooth sample.
    let mut second = Round::with_capacity(2 * points.len());
    let mut again = Vec::with_capacity(points.len());
    for (&i, &(at, chosen)) in points.iter().zip(&asked) {
        let sh = &shs[i];
        let (_, weights, _) = blend_of(sh);
        let mut at2 = [None; 2];
        let sampled = chosen.and_then(|k| first.get(at[k])).and_then(|a| a.sample);
        if let Some(s) = sampled.filter(|s| !s.delta) {
            for (k, w) in weights.into_iter().enumerate() {
                if w > 0.0 {
                    let query = BsdfQuery {
                        light: Some((s.wi, true)),
                        sample: false,
                        u_lobe: 0.5,
                        u: Vec2::splat(0.5),
                    };
                    let part = at[k].map_or_else(|| part_of(sh, k), |j| first.part(j));
                    at2[k] = second.ask(part, query);
                }
            }
        }
        again.push(at2);
    }
    second.answer(parts);
    // The mixtures of the recorded answers, eight points at a time.
    let rgb = |c: Rgb| Vec3::new(c.r, c.g, c.b);
    let recorded: Vec<[Recorded; 2]> = points
        .iter()
        .zip(asked.iter().zip(&again))
        .map(|(&i, (&(at, chosen), at2))| {
            let (_, _, side) = blend_of(&shs[i]);
            std::array::from_fn(|k| {
                let (a1, a2) = (first.get(at[k]), second.get(at2[k]));
                Recorded {
                    light: queries[i].light.map(|(l, _)| side(l)),
                    f_light: a1.map_or(Vec3::ZERO, |a| rgb(a.f)),
                    pdf_light: a1.map_or(0.0, |a| a.pdf),
                    sample: if chosen == Some(k) {
                        a1.and_then(|a| a.sample)
                    } else {
                        None
                    },
                    f_sample: a2.map_or(Vec3::ZERO, |a| rgb(a.f)),
                    pdf_sample: a2.map_or(0.0, |a| a.pdf),
                }
            })
        })
        .collect();
    for (g, group) in points.chunks(8).enumerate() {
        answer_lanes(group, shs, queries, out, Some(run_kernel), |p| {
            let (b, _, _) = blend_of(&shs[group[p]]);
            let [a, c] = recorded[8 * g + p];
            MixtureLanes {
                a,
                b: c,
                weight: b.weight,
            }
        });
    }
}
