//! A discrete distribution over `n` items with given non-negative weights, sampled by
//! inverting its cumulative distribution (pbrt-v4 section A.1, "PiecewiseConstant1D",
//! restricted to the discrete case). Used to pick a light by power or a triangle by area,
//! and for the rows and cells of an environment map drawn by inversion
//! ([`crate::Distribution2D`]). The inversion starts from a guide table (Chen and Asau, "On
//! Generating Random Variates from an Empirical Distribution", AIIE Transactions 6(2),
//! 1974): the item at each of n equally spaced values of u, so that a search covers one
//! bucket instead of the whole CDF, with the same result. The CDF and guide entries sit
//! side by side, eight bytes an item, so that a large map's tables stay compact.

use crate::lanes::Real;

/// Distributions of at most this many items are searched by counting (see `find`).
const SMALL: usize = 16;

/// Items `0..n` with probability proportional to their weights.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// Entry `i`: the CDF before item `i` (sum of the weights before it, normalized; 1 at
    /// `i = n`) and the guide table's item that u = i / n falls in. Side by side, so that
    /// the guide entry of a bucket and the CDF near it share a cache line.
    table: Vec<Entry>,
    total: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    cdf: f32,
    guide: u32,
}

impl Distribution1D {
    /// `None` when there are no weights, one is negative or not finite, or all are zero.
    pub fn new(weights: impl IntoIterator<Item = f32>) -> Option<Self> {
        let mut sums = vec![];
        let mut total = 0f64;
        for w in weights {
            if !(w.is_finite() && w >= 0.0) {
                return None;
            }
            sums.push(total);
            total += w as f64;
        }
        if total <= 0.0 {
            return None;
        }
        sums.push(total);
        let table = sums.into_iter().map(|s| Entry {
            cdf: (s / total) as f32,
            guide: 0,
        });
        let mut d = Distribution1D {
            table: table.collect(),
            total,
        };
        let n = d.len();
        for j in 0..=n {
            d.table[j].guide = d.search(j as f32 / n as f32) as u32;
        }
        Some(d)
    }

    fn cdf(&self, i: usize) -> f32 {
        self.table[i].cdf
    }

    /// The last item i with cdf[i] <= u (so skipping empty intervals), by binary search of
    /// the whole CDF.
    fn search(&self, u: f32) -> usize {
        self.table.partition_point(|e| e.cdf <= u).clamp(1, self.len()) - 1
    }

    /// The guide table's bucket that u falls in.
    #[inline]
    fn bucket_index(&self, u: f32) -> usize {
        let n = self.len();
        ((u * n as f32) as usize).min(n - 1)
    }

    /// The guide table's first and last item of u's bucket.
    #[inline]
    fn bucket(&self, u: f32) -> (usize, usize) {
        let j = self.bucket_index(u);
        (self.table[j].guide as usize, self.table[j + 1].guide as usize)
    }

    /// [`Distribution1D::search`]'s answer, searched for between the guide table's items
    /// for u's bucket: the answer lies there whenever cdf[lo] <= u and u < cdf[hi + 1]
    /// (checked, so rounding at a bucket's edge falls back to the whole search).
    fn find(&self, u: f32) -> usize {
        let n = self.len();
        let (lo, hi) = self.bucket(u);
        if !(self.cdf(lo) <= u && (hi == n - 1 || u < self.cdf(hi + 1))) {
            return self.search(u);
        }
        lo + self.table[lo + 1..=hi].partition_point(|e| e.cdf <= u)
    }

    pub fn len(&self) -> usize {
        self.table.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// Probability of item `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        self.table.get(i + 1).map_or(0.0, |hi| hi.cdf - self.cdf(i))
    }

    /// The item whose CDF interval holds `u` in [0, 1), its probability, and `u` rescaled to
    /// [0, 1) within that interval (so one random number can serve again). Items of zero
    /// weight are never chosen. The one-lane instance of [`Distribution1D::sample_lanes`].
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        if self.len() > SMALL {
            return self.sample_searched(u);
        }
        let (i, pmf, rest) = self.sample_lanes(u);
        (i as usize, pmf, rest)
    }

    /// Asks the caches for the guide table's entries of `u`'s bucket, which
    /// [`Distribution1D::prefetch_sample`] reads.
    #[inline]
    pub(crate) fn prefetch_guide(&self, u: f32) {
        if self.len() > SMALL {
            let j = self.bucket_index(u);
            crate::simd::prefetch(&self.table[j]);
            crate::simd::prefetch(&self.table[j + 1]);
        }
    }

    /// Asks the caches for the entries a sample with `u` reads: the ends of its guide
    /// table's bucket (the guide entries themselves are read here, and no branch waits on
    /// them, so the loads of several lanes' calls overlap).
    #[inline]
    pub(crate) fn prefetch_sample(&self, u: f32) {
        if self.len() > SMALL {
            let (lo, hi) = self.bucket(u);
            crate::simd::prefetch(&self.table[lo]);
            crate::simd::prefetch(&self.table[hi + 1]);
        }
    }

    /// [`Distribution1D::sample`] of a distribution of more than a few items: its item
    /// found by the guide table's search.
    fn sample_searched(&self, u: f32) -> (usize, f32, f32) {
        let i = self.find(u);
        let (pmf, rest) = rescale(u, self.cdf(i), self.cdf(i + 1));
        (i, pmf, rest)
    }

    /// [`Distribution1D::sample`] per lane: each lane's item (a whole number as a float,
    /// exact below 2^24), its probability and `u` rescaled. A few items are found by
    /// counting the CDF entries at or below `u` in lanes; more by each lane's
    /// guide-table search. The floats are the scalar sample's in every lane.
    #[inline(always)]
    pub fn sample_lanes<R: Real>(&self, u: R) -> (R, R, R) {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let n = self.len();
        // One item (a scene's only light): the general answer, without its search and
        // division (pmf 1, and u, already below one, unchanged).
        if n == 1 {
            return (zero, one, unit_clamp(u));
        }
        if n <= SMALL {
            // A few items (a scene's lights, a mesh light's triangles): count the CDF
            // entries at or below u without branches. Which item a random u falls in is a
            // coin toss that a search's branches would mispredict; the count is the
            // search's answer.
            let mut count = zero;
            for e in &self.table[..n] {
                count = count + R::select(R::splat(e.cdf).cmp_le(u), one, zero);
            }
            // `count.clamp(1, n) - 1`: the count never exceeds n.
            let i = R::select(count.cmp_lt(one), one, count) - one;
            let [lo, hi] = R::map_lanes([i], |_, [i]| [self.cdf(i as usize), self.cdf(i as usize + 1)]);
            let (pmf, rest) = rescale(u, lo, hi);
            return (i, pmf, rest);
        }
        let [i, pmf, rest] = R::map_lanes([u], |_, [u]| {
            let (i, pmf, rest) = self.sample_searched(u);
            [i as f32, pmf, rest]
        });
        (i, pmf, rest)
    }
}

/// The probability of the item whose CDF interval is [`lo`, `hi`), and `u` rescaled to
/// [0, 1) within it.
#[inline(always)]
fn rescale<R: Real>(u: R, lo: R, hi: R) -> (R, R) {
    let pmf = hi - lo;
    (pmf, unit_clamp((u - lo) / pmf))
}

/// `x.clamp(0.0, ONE_MINUS_EPSILON)` per lane, as `f32::clamp` gives it (NaN kept).
#[inline(always)]
fn unit_clamp<R: Real>(x: R) -> R {
    let (zero, top) = (R::splat(0.0), R::splat(crate::samplers::ONE_MINUS_EPSILON));
    let x = R::select(x.cmp_lt(zero), zero, x);
    R::select(x.cmp_gt(top), top, x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picks_in_proportion_to_weight_and_skips_empty_items() {
        let d = Distribution1D::new([1.0, 0.0, 3.0, 0.0]).unwrap();
        assert_eq!(d.len(), 4);
        assert_eq!((d.pmf(0), d.pmf(1), d.pmf(2), d.pmf(3)), (0.25, 0.0, 0.75, 0.0));
        let n = 100_000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let (i, pmf, rest) = d.sample(u);
            assert!(
                pmf > 0.0 && (0.0..1.0).contains(&rest),
                "u {u}: item {i} pmf {pmf} rest {rest}"
            );
            counts[i] += 1;
        }
        // Evenly spaced u: the counts match the probabilities to within one.
        assert!(
            counts[0].abs_diff(25_000) <= 1 && counts[2].abs_diff(75_000) <= 1,
            "{counts:?}"
        );
        assert_eq!(d.sample(0.0).0, 0);
        assert_eq!(d.sample(crate::samplers::ONE_MINUS_EPSILON).0, 2);
        assert_eq!(d.sample(0.25).0, 2, "u on a boundary goes to the next non-empty item");
    }

    /// The guide table's search and the sample (by counting, for a few items) give the
    /// whole search's item for every u, on spiky, sparse, flat and few weights, at random
    /// u, at the buckets' edges and just below them; the sample in eight lanes gives the
    /// scalar one's bits.
    #[test]
    fn the_guide_table_finds_what_the_whole_search_finds() {
        use crate::lanes::{Lane8, F8};
        let mut rng = crate::Pcg32::new(3, 8);
        let mut spiky: Vec<f32> = (0..513).map(|_| rng.next_f32() * 1e-4).collect();
        spiky[200] = 1e3;
        spiky[201] = 5.0;
        let sparse: Vec<f32> = (0..300)
            .map(|i| if i % 37 == 0 { (i + 1) as f32 } else { 0.0 })
            .collect();
        let flat = vec![1.0f32; 1024];
        let tiny = vec![0.0, 2.0];
        let small = vec![
            1.0, 0.0, 0.0, 3.0, 2.0, 0.0, 0.5, 0.0, 1.0, 1.0, 0.0, 7.0, 0.0, 0.0, 2.0, 0.0,
        ];
        let few = vec![3.0, 1.0, 0.0];
        for weights in [spiky, sparse, flat, tiny, small, few] {
            let d = Distribution1D::new(weights.iter().copied()).unwrap();
            let n = d.len() as f32;
            let edges = (0..=d.len()).flat_map(|j| {
                let e = j as f32 / n;
                [e, e.next_down().max(0.0), e.next_up()]
            });
            let random = (0..20_000).map(|_| rng.next_f32());
            let us: Vec<f32> = edges.chain(random).filter(|u| (0.0..1.0).contains(u)).collect();
            for &u in &us {
                assert_eq!(d.find(u), d.search(u), "u {u} over {} items", d.len());
                assert_eq!(d.sample(u).0, d.search(u), "u {u} over {} items", d.len());
            }
            // Eight lanes give each number the scalar sample's bits.
            for chunk in us.chunks_exact(8) {
                let u: [f32; 8] = chunk.try_into().unwrap();
                let (i, pmf, rest) = d.sample_lanes(F8::from_array(u));
                let (i, pmf, rest) = (i.to_array(), pmf.to_array(), rest.to_array());
                for (k, &u) in u.iter().enumerate() {
                    let (si, spmf, srest) = d.sample(u);
                    assert_eq!(i[k] as usize, si, "u {u}");
                    assert_eq!(
                        (pmf[k].to_bits(), rest[k].to_bits()),
                        (spmf.to_bits(), srest.to_bits()),
                        "u {u}"
                    );
                }
            }
        }
    }

    #[test]
    fn rejects_weights_that_cannot_be_normalized() {
        assert!(Distribution1D::new([]).is_none());
        assert!(Distribution1D::new([0.0, 0.0]).is_none());
        assert!(Distribution1D::new([1.0, -1.0]).is_none());
        assert!(Distribution1D::new([1.0, f32::NAN]).is_none());
        assert!(Distribution1D::new([f32::INFINITY]).is_none());
    }
}
