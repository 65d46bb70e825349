//! Trigonometry written once over [`Real`], for the scalar renderer and for lanes alike:
//! sine and cosine of a fraction of a turn, the arctangent of a quotient and the arc
//! cosine. Each is a short polynomial after a branch-free range reduction (Cephes'
//! single-precision `atanf` and `asinf` polynomials, S. L. Moshier, "Methods and Programs
//! for Mathematical Functions", 1989; Taylor series on an octant for the sine and cosine),
//! so eight lanes cost about what one library call costs, and lane `k` of an eight-lane
//! result is bit for bit the scalar result for input `k`. Errors, measured against `f64`
//! in this file's tests: below 3e-7 absolute for every function over its whole domain.

use crate::lanes::Real;
use crate::warp::sin_cos_octant;
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

/// `(sin 2πt, cos 2πt)` for `t` in [0, 1]: the angle is reduced to the nearest quarter turn
/// by comparisons (exactly: `t - k/4` is a float when t lies within an eighth of a turn of
/// k/4) and the octant's series rotated by that many quarters.
#[inline(always)]
pub fn sin_cos_turns<R: Real>(t: R) -> (R, R) {
    let c = R::splat;
    let at_least = |b: f32| t.cmp_ge(c(b));
    let (q1, q2, q3, q4) = (at_least(0.125), at_least(0.375), at_least(0.625), at_least(0.875));
    // The nearest quarter: 0, 1/4, 1/2, 3/4 or 1 (a whole turn, the same as 0).
    let quarter = R::select(
        q4,
        c(1.0),
        R::select(q3, c(0.75), R::select(q2, c(0.5), R::select(q1, c(0.25), c(0.0)))),
    );
    let (s, co) = sin_cos_octant((t - quarter) * c(TAU));
    // Rotations by one, two and three quarters: (s, c) -> (c, -s), (-s, -c), (-c, s).
    let (one, two, three) = (R::and(q1, R::not(q2)), R::and(q2, R::not(q3)), R::and(q3, R::not(q4)));
    let sin = R::select(one, co, R::select(two, -s, R::select(three, -co, s)));
    let cos = R::select(one, -s, R::select(two, -co, R::select(three, s, co)));
    (sin, cos)
}

/// arctan(x) for x in [0, 1] (Cephes' `atanf`: reduced to |x| <= tan(π/8) by
/// arctan x = π/4 + arctan((x - 1)/(x + 1)), then a degree-9 odd polynomial).
#[inline(always)]
fn atan_unit<R: Real>(x: R) -> R {
    let c = R::splat;
    let far = x.cmp_gt(c(0.414_213_57));
    let x = R::select(far, (x - c(1.0)) / (x + c(1.0)), x);
    let z = x * x;
    let p = (((c(8.053_744_5e-2) * z - c(1.387_768_6e-1)) * z + c(1.997_771_1e-1)) * z - c(3.333_295e-1)) * z * x + x;
    R::select(far, c(FRAC_PI_4) + p, p)
}

/// The angle of the point (x, y) from the x axis, in [-π, π], as `f32::atan2` gives it
/// (up to its rounding) except on the edges: 0 at the origin and for NaN, and x = -0 taken
/// as +0 (±0, not ±π, on the negative zero axis). The smaller coordinate over the larger
/// goes to the unit interval's arctangent, and the octant is restored by symmetries.
#[inline(always)]
pub fn atan2<R: Real>(y: R, x: R) -> R {
    let c = R::splat;
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay.cmp_gt(ax);
    let (num, den) = (R::select(steep, ax, ay), R::select(steep, ay, ax));
    // 0/0 at the origin: the angle 0 there (a NaN quotient would reach the result).
    let q = R::select(den.cmp_gt(c(0.0)), num / den, c(0.0));
    let a = atan_unit(q);
    let a = R::select(steep, c(FRAC_PI_2) - a, a);
    let a = R::select(x.cmp_lt(c(0.0)), c(PI) - a, a);
    a.copysign(y)
}

/// arcsin(x) for |x| <= 1/2 (Cephes' `asinf` polynomial, degree 11, odd).
#[inline(always)]
fn asin_half<R: Real>(x: R) -> R {
    let c = R::splat;
    let z = x * x;
    ((((c(4.216_32e-2) * z + c(2.418_131e-2)) * z + c(4.547_002_6e-2)) * z + c(7.495_300_3e-2)) * z + c(1.666_675_2e-1))
        * z
        * x
        + x
}

/// arccos(x) in [0, π] for x in [-1, 1] (clamped there): π/2 - arcsin x near 0, and
/// 2 arcsin(√((1 - |x|)/2)) (or π minus it) beyond |x| = 1/2, which keeps its precision
/// near ±1 where 1 - x² would lose it.
#[inline(always)]
pub fn acos<R: Real>(x: R) -> R {
    let c = R::splat;
    let ax = x.abs();
    let outer = ax.cmp_gt(c(0.5));
    let s = R::select(outer, ((c(1.0) - ax) * c(0.5)).max(c(0.0)).sqrt(), x);
    let a = asin_half(s);
    let outer_angle = a + a;
    let outer_angle = R::select(x.cmp_lt(c(0.0)), c(PI) - outer_angle, outer_angle);
    R::select(outer, outer_angle, c(FRAC_PI_2) - a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::{Lane8, F8};
    use crate::rng::Pcg32;

    const STEPS: usize = 200_000;

    /// Each function against `f64`'s over a dense grid of its domain, endpoints included.
    #[test]
    fn every_function_is_within_3e7_of_the_exact_value() {
        let mut worst = [0f64; 3];
        for i in 0..=STEPS {
            let t = i as f32 / STEPS as f32;
            let (s, co) = sin_cos_turns(t);
            let exact = std::f64::consts::TAU * t as f64;
            worst[0] = worst[0]
                .max((s as f64 - exact.sin()).abs())
                .max((co as f64 - exact.cos()).abs());
            let x = 2.0 * t - 1.0;
            worst[1] = worst[1].max((acos(x) as f64 - (x as f64).acos()).abs());
            let angle = exact - std::f64::consts::PI;
            let (py, px) = ((angle.sin() * 3.0) as f32, (angle.cos() * 3.0) as f32);
            worst[2] = worst[2].max((atan2(py, px) as f64 - (py as f64).atan2(px as f64)).abs());
        }
        for (name, w) in ["sin_cos_turns", "acos", "atan2"].iter().zip(worst) {
            println!("{name}: worst error {w:e}");
            assert!(w < 3e-7, "{name}: worst error {w:e}");
        }
    }

    /// The edges: the axes, the origin, signed zeros and the ends of acos's domain.
    #[test]
    fn axes_zeros_and_domain_ends() {
        assert_eq!(atan2(0.0f32, 0.0), 0.0);
        assert_eq!(atan2(0.0f32, 1.0), 0.0);
        assert_eq!(atan2(1.0f32, 0.0), FRAC_PI_2);
        assert_eq!(atan2(-1.0f32, 0.0), -FRAC_PI_2);
        assert_eq!(atan2(0.0f32, -1.0), PI);
        assert_eq!(atan2(-0.0f32, -1.0), -PI);
        assert_eq!(acos(1.0f32), 0.0);
        assert_eq!(acos(-1.0f32), PI);
        assert_eq!(acos(1.5f32), 0.0);
        assert_eq!(sin_cos_turns(0.0f32), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25f32), (1.0, 0.0));
        assert_eq!(sin_cos_turns(0.5f32).1, -1.0);
        assert_eq!(sin_cos_turns(1.0f32).1, 1.0);
    }

    /// Eight lanes give the scalar bits, lane by lane.
    #[test]
    fn eight_lanes_equal_the_scalar_functions_bit_for_bit() {
        let mut rng = Pcg32::new(7, 3);
        for _ in 0..20_000 {
            let a: [f32; 8] = std::array::from_fn(|_| rng.next_f32());
            let b: [f32; 8] = std::array::from_fn(|_| rng.next_f32() * 4.0 - 2.0);
            let (la, lb) = (F8::from_array(a), F8::from_array(b));
            let (s, co) = sin_cos_turns(la);
            let ac = acos(lb);
            let at = atan2(lb, la - F8::splat(0.5));
            for k in 0..8 {
                let (ss, sc) = sin_cos_turns(a[k]);
                assert_eq!(s.to_array()[k].to_bits(), ss.to_bits());
                assert_eq!(co.to_array()[k].to_bits(), sc.to_bits());
                assert_eq!(ac.to_array()[k].to_bits(), acos(b[k]).to_bits());
                assert_eq!(at.to_array()[k].to_bits(), atan2(b[k], a[k] - 0.5).to_bits());
            }
        }
    }
}
