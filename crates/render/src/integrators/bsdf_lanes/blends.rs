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
//! asks its own parts for values alone, as the scalar mixture does. The replay gives back
//! what a part answered for the direction it is asked about, so a blend's answer has the
//! bits of its scalar BSDF (`blends_answered_in_lanes_give_the_scalar_answers`). Blends
//! nest at most `MAX_NESTING` deep (the scene's build refuses deeper), which bounds the
//! recursion through the parts' buckets.

use super::{answer_lanes, run_kernel, BsdfAnswer, BsdfPoint, BsdfQuery, Buckets};

use crate::bsdfs::{flip, part_lobe, Blend, Bsdf, BsdfKind, BsdfSample, Gather, LaneKernel, LaneSample, MixtureLanes};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, V3};
use penumbra_core::Rgb;

/// One part of one blend point, as its own kind answered it: towards the light (in the
/// frame the parts see) with the part's sample if it is the chosen one, and in the sampled
/// direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct Recorded<'r> {
    light: Option<Vec3>,
    first: Option<&'r BsdfAnswer>,
    chosen: bool,
    second: Option<&'r BsdfAnswer>,
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

impl Gather for Recorded<'_> {
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
        let sample = |r: &Recorded| r.first.filter(|_| r.chosen).and_then(|a| a.sample);
        let s = one.map(|r| sample(&r).unwrap_or(none));
        let rgb = |c: Rgb| Vec3::new(c.r, c.g, c.b);
        let f = |a: Option<&BsdfAnswer>| a.map_or(Vec3::ZERO, |a| rgb(a.f));
        let pdf = |a: Option<&BsdfAnswer>| a.map_or(0.0, |a| a.pdf);
        RecordedLanes {
            lit: L::mask_of(one.map(|r| r.light.is_some())),
            light: V3::gather(one, |r| r.light.unwrap_or(Vec3::ZERO)),
            f_light: V3::gather(one, |r| f(r.first)),
            pdf_light: L::from_array(one.map(|r| pdf(r.first))),
            f_sample: V3::gather(one, |r| f(r.second)),
            pdf_sample: L::from_array(one.map(|r| pdf(r.second))),
            sample: LaneSample {
                wi: V3::gather(&s, |s| s.wi),
                weight: V3::gather(&s, |s| rgb(s.weight)),
                pdf: L::from_array(s.map(|s| s.pdf)),
                delta: L::mask_of(s.map(|s| s.delta)),
                eta: L::from_array(s.map(|s| s.eta)),
                ok: L::mask_of(one.map(|r| sample(&r).is_some())),
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

/// A blend's part as a point of the BSDF stage: the part's BSDF (made once per blend
/// point) and the direction towards the viewer as the part sees it (the blend's side).
#[derive(Clone, Copy)]
pub(super) struct Part<'r, 's> {
    bsdf: &'r Bsdf<'s>,
    wo: Vec3,
}

impl<'s> BsdfPoint<'s> for Part<'_, 's> {
    #[inline(always)]
    fn bsdf(&self) -> &Bsdf<'s> {
        self.bsdf
    }
    #[inline(always)]
    fn wo(&self) -> Vec3 {
        self.wo
    }
}

/// A blend point's blend and the mirroring of its two-sided rule.
fn blend_of<'s>(sh: &impl BsdfPoint<'s>) -> (Blend<'s>, impl Fn(Vec3) -> Vec3) {
    let BsdfKind::Blend(b) = sh.bsdf().kind else {
        unreachable!("only blends are answered here")
    };
    let mirrored = sh.bsdf().mirrored(sh.wo());
    (b, move |w| if mirrored { flip(w) } else { w })
}

/// What a blend point asks of its parts in the first round.
struct Plan {
    /// The blend's weight of part b.
    weight: f32,
    /// The part chosen for the sample, if the point wants one.
    chosen: Option<usize>,
    /// `u_lobe` rescaled for the chosen part.
    u_lobe: f32,
    /// The light's direction and `wo` as the parts see them.
    light: Option<Vec3>,
    wo: Vec3,
}

impl Plan {
    /// The parts' weights, 1 - w and w (the floats `answer_blends` chose the part by).
    fn weights(&self) -> [f32; 2] {
        [1.0 - self.weight, self.weight]
    }
}

/// Asks of one round: the parts, what each is asked, and the answers.
struct Round<'r, 's> {
    parts: Vec<Part<'r, 's>>,
    queries: Vec<BsdfQuery>,
    answers: Vec<BsdfAnswer>,
}

impl<'r, 's> Round<'r, 's> {
    /// Room for `n` asks (two per blend point at most).
    fn with_capacity(n: usize) -> Self {
        Round {
            parts: Vec::with_capacity(n),
            queries: Vec::with_capacity(n),
            answers: Vec::with_capacity(n),
        }
    }

    /// Asks `part` `query`; its place among the asks.
    fn ask(&mut self, part: Part<'r, 's>, query: BsdfQuery) -> usize {
        self.parts.push(part);
        self.queries.push(query);
        self.parts.len() - 1
    }

    /// Answers the round's asks by kind in `buckets`.
    fn answer(&mut self, buckets: &mut Buckets) {
        self.answers.clear();
        self.answers.resize(self.parts.len(), BsdfAnswer::default());
        buckets.answer(&self.parts, &self.queries, &mut self.answers);
    }

    fn get(&self, at: Option<usize>) -> Option<BsdfAnswer> {
        at.map(|j| self.answers[j])
    }
}

/// Answers `queries[i]` of the blend points `shs[i]`, `i` in `points`, into `out[i]`: the
/// parts asked in `parts`' buckets, then mixed in lanes.
pub(super) fn answer_blends<'s, P: BsdfPoint<'s>>(
    points: &[usize],
    parts: &mut Buckets,
    shs: &[P],
    queries: &[BsdfQuery],
    out: &mut [BsdfAnswer],
) {
    // Each point's plan, and its parts' BSDFs where a round may ask them (the chosen
    // part, the parts of positive weight).
    let mut plans = Vec::with_capacity(points.len());
    let mut bsdfs: Vec<[Option<Bsdf<'s>>; 2]> = Vec::with_capacity(points.len());
    for &i in points {
        let (sh, q) = (&shs[i], &queries[i]);
        let (b, side) = blend_of(sh);
        let (wa, wb) = (1.0 - b.weight, b.weight);
        let take_a = q.u_lobe < wa;
        // (A point that wants no sample chooses no part.)
        let chosen = q.sample.then_some(if take_a { 0 } else { 1 });
        let needed = |k: usize, w: f32| (chosen == Some(k) || w > 0.0).then(|| [b.a, b.b][k].bsdf(b.uv));
        bsdfs.push([needed(0, wa), needed(1, wb)]);
        plans.push(Plan {
            weight: b.weight,
            chosen,
            u_lobe: part_lobe(q.u_lobe, (wa, wb), take_a),
            light: q.light.map(|(l, _)| side(l)),
            wo: side(sh.wo()),
        });
    }
    // First round: the chosen part's sample, every weighed part towards the light (its
    // density too, whatever the point needs: the sampled direction may be the light's,
    // whose answer the replay then gives back).
    let mut first = Round::with_capacity(2 * points.len());
    let mut asked = Vec::with_capacity(points.len());
    for (&i, (plan, part_bsdfs)) in points.iter().zip(plans.iter().zip(&bsdfs)) {
        let mut at = [None; 2];
        for (k, w) in plan.weights().into_iter().enumerate() {
            let sample = plan.chosen == Some(k);
            if let Some(bsdf) = part_bsdfs[k]
                .as_ref()
                .filter(|_| sample || (w > 0.0 && plan.light.is_some()))
            {
                let query = BsdfQuery {
                    light: plan.light.map(|l| (l, true)),
                    sample,
                    u_lobe: plan.u_lobe,
                    u: queries[i].u,
                };
                at[k] = Some(first.ask(Part { bsdf, wo: plan.wo }, query));
            }
        }
        asked.push(at);
    }
    first.answer(parts);
    // Second round: every weighed part in the direction of a smooth sample.
    let mut second = Round::with_capacity(2 * points.len());
    let mut again = Vec::with_capacity(points.len());
    for ((plan, part_bsdfs), at) in plans.iter().zip(&bsdfs).zip(&asked) {
        let mut at2 = [None; 2];
        let sampled = plan.chosen.and_then(|k| first.get(at[k])).and_then(|a| a.sample);
        if let Some(s) = sampled.filter(|s| !s.delta) {
            for (k, w) in plan.weights().into_iter().enumerate() {
                if let Some(bsdf) = part_bsdfs[k].as_ref().filter(|_| w > 0.0) {
                    let query = BsdfQuery {
                        light: Some((s.wi, true)),
                        sample: false,
                        u_lobe: 0.5,
                        u: Vec2::splat(0.5),
                    };
                    at2[k] = Some(second.ask(Part { bsdf, wo: plan.wo }, query));
                }
            }
        }
        again.push(at2);
    }
    second.answer(parts);
    // The mixtures of the recorded answers, eight points at a time.
    for (g, group) in points.chunks(8).enumerate() {
        answer_lanes(group, shs, queries, out, Some(run_kernel), |p| {
            let n = 8 * g + p;
            let (plan, at, at2) = (&plans[n], &asked[n], &again[n]);
            let part = |k: usize| Recorded {
                light: plan.light,
                first: at[k].map(|j| &first.answers[j]),
                chosen: plan.chosen == Some(k),
                second: at2[k].map(|j| &second.answers[j]),
            };
            MixtureLanes {
                a: part(0),
                b: part(1),
                weight: plan.weight,
            }
        });
    }
}
