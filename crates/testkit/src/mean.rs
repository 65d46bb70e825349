//! The mean of independent estimates and its standard error, for "within k standard errors
//! of the closed form" assertions (Welford's running update, stable for long runs).

/// Running mean and variance of a stream of estimates.
#[derive(Clone, Copy, Debug, Default)]
pub struct MeanEstimate {
    n: u64,
    mean: f64,
    m2: f64,
}

impl MeanEstimate {
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }

    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Standard error of the mean: the sample standard deviation over √n.
    pub fn standard_error(&self) -> f64 {
        if self.n < 2 {
            return f64::INFINITY;
        }
        (self.m2 / (self.n - 1) as f64 / self.n as f64).sqrt()
    }
}

/// Panics, naming `what`, unless `mean` is within 3 standard errors `se` (plus `slack`) of
/// `expected`. Three standard errors: a correct estimator fails about 0.3% of the time,
/// once and for all for a fixed seed.
pub fn assert_within_3se(what: &str, mean: f64, se: f64, expected: f64, slack: f64) {
    assert_within_se(what, mean, se, expected, slack, 3.0);
}

/// [`assert_within_3se`] with `k` standard errors: for a family of many comparisons, where
/// k = 4 keeps the chance that any of 35 fails by chance near 0.2% (two-sided normal tail
/// 6.3e-5 each).
pub fn assert_within_se(what: &str, mean: f64, se: f64, expected: f64, slack: f64, k: f64) {
    assert!(
        (mean - expected).abs() <= k * se + slack,
        "{what}: {mean} +- {se} is {:.1} standard errors from {expected}",
        (mean - expected).abs() / se
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_standard_error_of_a_known_sample() {
        let mut m = MeanEstimate::default();
        for x in [1.0, 2.0, 3.0, 4.0] {
            m.push(x);
        }
        // Sample variance 5/3, standard error sqrt(5/3 / 4).
        assert!((m.mean() - 2.5).abs() < 1e-12);
        assert!((m.standard_error() - (5.0f64 / 12.0).sqrt()).abs() < 1e-12);
        assert_within_3se("2.5 vs 2", m.mean(), m.standard_error(), 2.0, 0.0);
        assert_eq!(MeanEstimate::default().standard_error(), f64::INFINITY);
    }

    #[test]
    #[should_panic(expected = "standard errors from")]
    fn a_mean_far_from_the_expectation_fails() {
        assert_within_3se("off", 2.5, 0.1, 2.0, 0.0);
    }
}
