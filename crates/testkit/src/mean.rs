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

    /// Whether the mean is within `k` standard errors (plus `slack`) of `expected`.
    pub fn agrees_with(&self, expected: f64, k: f64, slack: f64) -> bool {
        (self.mean - expected).abs() <= k * self.standard_error() + slack
    }
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
        assert!(m.agrees_with(2.0, 1.0, 0.0) && !m.agrees_with(1.0, 1.0, 0.0));
        assert_eq!(MeanEstimate::default().standard_error(), f64::INFINITY);
    }
}
