//! Walker's alias method (Walker, "An Efficient Method for Generating Discrete Random
//! Variables with General Distributions", ACM TOMS 3(3), 1977), built by Vose's linear-time
//! construction (Vose, "A Linear Algorithm for Generating Random Numbers with a Given
//! Distribution", IEEE TSE 17(9), 1991): an item of `n` is drawn with one table entry and
//! one comparison, whatever the weights. Slot `i` (picked uniformly) keeps its own item
//! with probability `q[i]` and otherwise gives its alias; every item's share of the slots
//! adds up to its weight over the total. [`crate::Distribution2D`] samples an
//! environment map's cells this way: no search, so no branch for a random number to
//! mispredict, and two reads of memory (the slot, then the item's payload), made in the
//! lanes of a SIMD type as in one ([`sample_lanes`]).

use crate::lanes::Real;
use crate::samplers::ONE_MINUS_EPSILON;

/// One slot of an alias table: the probability of keeping the slot's own item, and the
/// item given otherwise.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AliasEntry {
    keep: f32,
    alias: u32,
}

/// Builds the slots for `weights` (any non-negative, finite values with a positive sum;
/// `None` otherwise). Items of zero weight are never drawn: their slots give their
/// alias always.
pub fn build(weights: &[f64]) -> Option<Vec<AliasEntry>> {
    let n = weights.len();
    let total: f64 = weights.iter().sum();
    if n == 0 || !(total > 0.0 && total.is_finite()) || weights.iter().any(|w| w.is_nan() || *w < 0.0) {
        return None;
    }
    // Each weight as a multiple of the mean: a slot holds exactly 1.
    let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
    let mut slots = vec![AliasEntry::default(); n];
    while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
        small.pop();
        slots[s] = AliasEntry {
            keep: scaled[s] as f32,
            alias: l as u32,
        };
        // The large item gives the rest of slot `s` from its own excess.
        scaled[l] = (scaled[l] + scaled[s]) - 1.0;
        if scaled[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // What is left holds (up to rounding) exactly one slot's worth each; an item of zero
    // weight left over by rounding gives a drawn item instead.
    let drawn = weights.iter().position(|&w| w > 0.0)? as u32;
    for i in large.into_iter().chain(small) {
        slots[i] = if weights[i] > 0.0 {
            AliasEntry {
                keep: 1.0,
                alias: i as u32,
            }
        } else {
            AliasEntry {
                keep: 0.0,
                alias: drawn,
            }
        };
    }
    Some(slots)
}

/// The item drawn with `u` in [0, 1), and `u` rescaled to [0, 1) within the share of the
/// slot that gave it (so that the one number can serve again, as with an inverted CDF),
/// in the lanes of `R`, the same floats in every lane as in one: each lane draws from
/// the slots of its own `table` (any number the closures understand, e.g. a row of a
/// larger table), `n` slots each; `read(table, slot)` gives a slot. The item comes back as
/// a float (exact below 2^24 items), with the rescaled number. `prefetch(table, slot)` is
/// called for every lane before any `read`, so that the lanes' reads of a table not in
/// the caches overlap.
#[inline(always)]
pub fn sample_lanes<R: Real>(
    n: usize,
    u: R,
    table: R,
    prefetch: impl Fn(f32, usize),
    read: impl Fn(f32, usize) -> AliasEntry,
) -> (R, R) {
    // `slot`: the truncation of a non-negative number is its floor.
    let scaled = u * R::splat(n as f32);
    let last = R::splat((n - 1) as f32);
    let i = scaled.floor();
    let i = R::select(i.cmp_lt(last), i, last);
    let f = min(scaled - i, R::splat(ONE_MINUS_EPSILON));
    let [] = R::map_lanes([table, i], |_, [t, i]| {
        prefetch(t, i as usize);
        []
    });
    let [keep, alias] = R::map_lanes([table, i], |_, [t, i]| {
        let e = read(t, i as usize);
        [e.keep, e.alias as f32]
    });
    // Selects, not branches: which side of `keep` a random `f` falls is a coin toss.
    let kept = f.cmp_lt(keep);
    let item = R::select(kept, i, alias);
    let lo = R::select(kept, R::splat(0.0), keep);
    let width = R::select(kept, keep, R::splat(1.0) - keep);
    (item, min((f - lo) / width, R::splat(ONE_MINUS_EPSILON)))
}

/// `f32::min` of a number that is not NaN and a constant, per lane.
#[inline(always)]
fn min<R: Real>(x: R, c: R) -> R {
    R::select(x.cmp_lt(c), x, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One draw from `slots`, in one lane.
    fn sample(slots: &[AliasEntry], u: f32) -> (usize, f32) {
        let (item, rest) = sample_lanes(slots.len(), u, 0.0, |_, _| {}, |_, i| slots[i]);
        (item as usize, rest)
    }

    /// Each item's share of the slots is its probability, exactly up to rounding.
    fn shares(slots: &[AliasEntry]) -> Vec<f64> {
        let n = slots.len() as f64;
        let mut p = vec![0.0; slots.len()];
        for (i, e) in slots.iter().enumerate() {
            p[i] += e.keep as f64 / n;
            p[e.alias as usize] += (1.0 - e.keep as f64) / n;
        }
        p
    }

    #[test]
    fn every_item_gets_its_weight_and_empty_items_nothing() {
        let w = [1.0, 0.0, 3.0, 0.5, 0.0, 7.25, 2.0];
        let total: f64 = w.iter().sum();
        let slots = build(&w).unwrap();
        for (i, (p, wi)) in shares(&slots).iter().zip(w).enumerate() {
            assert!((p - wi / total).abs() < 1e-7, "item {i}: {p} vs {}", wi / total);
        }
        // Drawn with a dense sweep of u: never an empty item, counts in proportion.
        let n = 70_000;
        let mut counts = [0usize; 7];
        for k in 0..n {
            let (item, rest) = sample(&slots, (k as f32 + 0.5) / n as f32);
            assert!(
                w[item] > 0.0 && (0.0..1.0).contains(&rest),
                "u {k}: item {item}, rest {rest}"
            );
            counts[item] += 1;
        }
        for (i, &c) in counts.iter().enumerate() {
            // A stratified sweep: off by at most a slot's rounding, far below 1e-3.
            assert!((c as f64 / n as f64 - w[i] / total).abs() < 1e-3, "item {i}: {c}");
        }
    }

    #[test]
    fn the_rescaled_number_is_uniform_within_the_item() {
        // Within each item, `rest` of a uniform sweep fills [0, 1) evenly: ten bins each
        // get a tenth of the item's draws (a stratified sweep, so within a draw or two).
        let w = [2.0, 5.0, 1.0];
        let slots = build(&w).unwrap();
        let n = 80_000;
        let mut bins = [[0usize; 10]; 3];
        for k in 0..n {
            let (item, rest) = sample(&slots, (k as f32 + 0.5) / n as f32);
            bins[item][(rest * 10.0) as usize] += 1;
        }
        for (i, b) in bins.iter().enumerate() {
            let total: usize = b.iter().sum();
            for &c in b {
                assert!((c as f64 - total as f64 / 10.0).abs() <= 3.0, "item {i}: {b:?}");
            }
        }
    }

    #[test]
    fn bad_weights_are_refused() {
        assert!(build(&[]).is_none());
        assert!(build(&[0.0, 0.0]).is_none());
        assert!(build(&[1.0, -1.0]).is_none());
        assert!(build(&[1.0, f64::NAN]).is_none());
        assert!(build(&[1.0, f64::INFINITY]).is_none());
        // One item: always it.
        let slots = build(&[0.0, 2.0]).unwrap();
        assert!((0..100).all(|k| sample(&slots, k as f32 / 100.0).0 == 1));
    }
}
