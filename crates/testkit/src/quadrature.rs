//! Adaptive Simpson quadrature (Lyness 1969), nested for rectangles: accurate on
//! integrands with edges, such as a density that is zero outside a cone.

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
            step(f, a, b, fa, fm, fb, whole, eps / PANELS as f64, 16)
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

/// The integral of `f` over the rectangle `lo..hi`: adaptive in y inside adaptive in x.
pub fn integrate_2d(f: &dyn Fn([f64; 2]) -> f64, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    let eps = 1e-7 * area.max(1e-12);
    integrate_1d(
        &|x| integrate_1d(&|y| f([x, y]), lo[1], hi[1], eps / (hi[0] - lo[0]).max(1e-12)),
        lo[0],
        hi[0],
        eps,
    )
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
