//! Quadrature for the chi-square test's expected counts: adaptive Simpson (Lyness 1969) in
//! one dimension, and for rectangles a fixed open rule across adaptive integrals along:
//! accurate on integrands with edges, such as a density that is zero outside a cone.

/// Initial panels: adaptivity starts from these, so a narrow feature that the first three
/// points of a single panel would all miss is still seen.
const PANELS: usize = 12;

/// The integral of `f` over `[a, b]`, refined until two levels agree to `eps`.
pub fn integrate_1d(f: &dyn Fn(f64) -> f64, a: f64, b: f64, eps: f64) -> f64 {
    let h = (b - a) / PANELS as f64;
    (0..PANELS)
        .map(|i| {
            let (a, b) = (a + i as f64 * h, a + (i + 1) as f64 * h);
            let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
            let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
            step(f, a, b, fa, fm, fb, whole, eps / PANELS as f64, 12)
        })
        .sum()
}

#[allow(clippy::too_many_arguments)]
fn step(f: &dyn Fn(f64) -> f64, a: f64, b: f64, fa: f64, fm: f64, fb: f64, whole: f64, eps: f64, depth: u32) -> f64 {
    let m = 0.5 * (a + b);
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * eps {
        return left + right + delta / 15.0;
    }
    step(f, a, m, fa, flm, fm, left, 0.5 * eps, depth - 1) + step(f, m, b, fm, frm, fb, right, 0.5 * eps, depth - 1)
}

/// Panels of the outer (x) rule in [`integrate_2d`].
const OUTER_PANELS: usize = 48;

/// The integral of `f` over the rectangle `lo..hi`: three-point Gauss–Legendre on each of
/// `OUTER_PANELS` panels in x (an open rule: a density that jumps at the rectangle's edge,
/// such as a hemisphere's at cos θ = 0, is never sampled on the edge) of adaptive integrals
/// in y. The outer rule is fixed because the inner
/// integrals are only accurate to their tolerance, which an adaptive outer rule would
/// chase to full depth; as a function of x the inner integral is continuous wherever the
/// density's edges are not parallel to the y axis, so a fixed rule converges. The inner
/// tolerance is relative to a first coarse estimate of the whole, so steep but large
/// densities do not drive every panel to full depth.
pub fn integrate_2d(f: &dyn Fn([f64; 2]) -> f64, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let wx = hi[0] - lo[0];
    // Nodes and weights of three-point Gauss–Legendre on [-1, 1].
    let r = (0.6f64).sqrt();
    let rule = [(-r, 5.0 / 9.0), (0.0, 8.0 / 9.0), (r, 5.0 / 9.0)];
    let outer = |g: &dyn Fn(f64) -> f64| {
        let h = wx / OUTER_PANELS as f64;
        (0..OUTER_PANELS)
            .map(|i| {
                let mid = lo[0] + (i as f64 + 0.5) * h;
                rule.iter().map(|&(x, w)| w * g(mid + 0.5 * h * x)).sum::<f64>() * 0.5 * h
            })
            .sum::<f64>()
    };
    let coarse = outer(&|x| integrate_1d(&|y| f([x, y]), lo[1], hi[1], f64::INFINITY));
    let eps = (1e-6 * coarse.abs() / wx.max(1e-12)).max(1e-12 * (hi[1] - lo[1]));
    outer(&|x| integrate_1d(&|y| f([x, y]), lo[1], hi[1], eps))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_on_smooth_and_close_on_edged_integrands() {
        let cubic = integrate_1d(&|x| x * x * x - 2.0 * x, 0.0, 2.0, 1e-10);
        assert!((cubic - 0.0).abs() < 1e-9, "{cubic}");
        let sin = integrate_1d(&f64::sin, 0.0, std::f64::consts::PI, 1e-10);
        assert!((sin - 2.0).abs() < 1e-8, "{sin}");
        // A step at an irrational point: the area to its right.
        let edge = 0.1 * std::f64::consts::SQRT_2;
        let step = integrate_1d(&|x| if x > edge { 1.0 } else { 0.0 }, 0.0, 1.0, 1e-9);
        assert!((step - (1.0 - edge)).abs() < 1e-5, "{step}");
        // A disk of radius 0.5 in the unit square.
        let disk = integrate_2d(
            &|[x, y]| {
                if (x - 0.5).powi(2) + (y - 0.5).powi(2) < 0.25 {
                    1.0
                } else {
                    0.0
                }
            },
            [0.0, 0.0],
            [1.0, 1.0],
        );
        assert!((disk - std::f64::consts::PI / 4.0).abs() < 1e-4, "{disk}");
    }
}
