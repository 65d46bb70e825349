//! Systematic resampling, shared by `sir` and `smc`.

/// `n` indices drawn in proportion to `weights` by systematic resampling (one uniform
/// `u`, then evenly spaced; Kitagawa 1996): each index k appears ⌊n w_k / Σw⌋ or one more
/// times. Empty when the weights sum to zero or overflow.
pub(super) fn systematic(weights: impl Iterator<Item = f32> + Clone, n: usize, u: f32) -> Vec<usize> {
    let total: f64 = weights.clone().map(|w| w.max(0.0) as f64).sum();
    let mut out = Vec::with_capacity(n);
    if total <= 0.0 || !total.is_finite() {
        return out;
    }
    let step = total / n as f64;
    let mut next = u as f64 * step;
    let mut cumulative = 0.0;
    for (k, w) in weights.enumerate() {
        cumulative += w.max(0.0) as f64;
        while out.len() < n && next < cumulative {
            out.push(k);
            next += step;
        }
    }
    // Rounding may leave the last few short: they go to the last positive weight.
    let last = out.last().copied();
    while let Some(k) = last.filter(|_| out.len() < n) {
        out.push(k);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn systematic_resampling_keeps_proportions() {
        let w = [1.0f32, 0.0, 3.0, 4.0];
        let picks = systematic(w.iter().copied(), 8, 0.5);
        let count = |k: usize| picks.iter().filter(|&&p| p == k).count();
        assert_eq!(picks.len(), 8);
        assert_eq!((count(0), count(1), count(2), count(3)), (1, 0, 3, 4));
        assert!(systematic([0.0f32; 3].iter().copied(), 4, 0.3).is_empty());
    }
}
