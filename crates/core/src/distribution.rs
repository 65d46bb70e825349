//! A discrete distribution over `n` items with given non-negative weights, sampled by
//! inverting its cumulative distribution (pbrt-v4 section A.1, "PiecewiseConstant1D",
//! restricted to the discrete case). Used to pick a light by power or a triangle by area.

/// Items `0..n` with probability proportional to their weights.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// `cdf[i]` = sum of the weights before item `i`, normalized; `cdf[n]` = 1.
    cdf: Vec<f32>,
    total: f64,
}

impl Distribution1D {
    /// `None` when there are no weights, one is negative or not finite, or all are zero.
    pub fn new(weights: impl IntoIterator<Item = f32>) -> Option<Self> {
        let mut sums = vec![0f64];
        let mut total = 0f64;
        for w in weights {
            if !(w.is_finite() && w >= 0.0) {
                return None;
            }
            total += w as f64;
            sums.push(total);
        }
        if total <= 0.0 {
            return None;
        }
        let cdf = sums.iter().map(|s| (s / total) as f32).collect();
        Some(Distribution1D { cdf, total })
    }

    pub fn len(&self) -> usize {
        self.cdf.len() - 1
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
        self.cdf.get(i + 1).map_or(0.0, |hi| hi - self.cdf[i])
    }

    /// The item whose CDF interval holds `u` in [0, 1), its probability, and `u` rescaled to
    /// [0, 1) within that interval (so one random number can serve again). Items of zero
    /// weight are never chosen.
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        // The last i with cdf[i] <= u, skipping empty intervals.
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, self.len()) - 1;
        let pmf = self.pmf(i);
        let rest = ((u - self.cdf[i]) / pmf).clamp(0.0, crate::samplers::ONE_MINUS_EPSILON);
        (i, pmf, rest)
    }
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

    #[test]
    fn rejects_weights_that_cannot_be_normalized() {
        assert!(Distribution1D::new([]).is_none());
        assert!(Distribution1D::new([0.0, 0.0]).is_none());
        assert!(Distribution1D::new([1.0, -1.0]).is_none());
        assert!(Distribution1D::new([1.0, f32::NAN]).is_none());
        assert!(Distribution1D::new([f32::INFINITY]).is_none());
    }
}
