//! Warps from the unit square to the shapes sampling needs, each with its density (pbrt-v4
//! section A.5; Shirley and Chiu 1997 for the concentric disk; Malley's method for the
//! cosine-weighted hemisphere). Directions are in a local frame with z up.

use crate::lanes::{Real, V3};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_4, PI};

/// A point on the unit disk, uniform by area, by Shirley and Chiu's concentric map (which
/// keeps strata compact). Density 1/π.
pub fn uniform_disk(u: Vec2) -> Vec2 {
    let (x, y) = uniform_disk_lanes(u.x, u.y);
    Vec2::new(x, y)
}

/// [`uniform_disk`] for lanes of any [`Real`] type.
#[inline(always)]
pub fn uniform_disk_lanes<R: Real>(ux: R, uy: R) -> (R, R) {
    let (two, one, zero) = (R::splat(2.0), R::splat(1.0), R::splat(0.0));
    let (ox, oy) = (two * ux - one, two * uy - one);
    // The angle is φ or π/2 - φ with |φ| <= π/4, where short series are exact to a float.
    // Written with selects, not branches: which octant a random point lands in is a coin
    // toss that a branch predictor loses half the time.
    let swap = ox.abs().cmp_le(oy.abs());
    let (a, b) = (R::select(swap, oy, ox), R::select(swap, ox, oy));
    let (sin, cos) = sin_cos_octant(R::splat(FRAC_PI_4) * (b / a));
    let (x, y) = (R::select(swap, sin, cos), R::select(swap, cos, sin));
    // The centre maps to itself (its angle, 0/0, is not needed).
    let centre = R::and(ox.cmp_eq(zero), oy.cmp_eq(zero));
    (R::select(centre, zero, a * x), R::select(centre, zero, a * y))
}

/// `(sin x, cos x)` for |x| <= π/4 by their Taylor series to degrees 9 and 10, whose
/// truncation errors there (below 2e-9 and 1e-10) vanish under float rounding: a few
/// multiply-adds instead of a library call with its range reduction.
#[inline(always)]
pub fn sin_cos_octant<R: Real>(x: R) -> (R, R) {
    let c = R::splat;
    let x2 = x * x;
    let sin =
        x * (c(1.0) + x2 * (c(-1.0 / 6.0) + x2 * (c(1.0 / 120.0) + x2 * (c(-1.0 / 5040.0) + x2 * c(1.0 / 362_880.0)))));
    let cos = c(1.0)
        + x2 * (c(-0.5)
            + x2 * (c(1.0 / 24.0) + x2 * (c(-1.0 / 720.0) + x2 * (c(1.0 / 40_320.0) + x2 * c(-1.0 / 3_628_800.0)))));
    (sin, cos)
}

pub const UNIFORM_DISK_PDF: f32 = FRAC_1_PI;

/// A direction uniform over the sphere (Archimedes: z uniform in [-1, 1]). Density 1/(4π).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    uniform_sphere_lanes(u.x, u.y).into()
}

/// [`uniform_sphere`] per lane of any [`Real`] type.
#[inline(always)]
pub fn uniform_sphere_lanes<R: Real>(ux: R, uy: R) -> V3<R> {
    at_height(R::splat(1.0) - R::splat(2.0) * ux, uy)
}

pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// A direction uniform over the upper (z >= 0) hemisphere. Density 1/(2π).
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    at_height(u.x, u.y).into()
}

pub const UNIFORM_HEMISPHERE_PDF: f32 = 1.0 / (2.0 * PI);

/// A direction over the upper hemisphere with density cos θ / π (Malley's method: a uniform
/// disk point lifted onto the hemisphere).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    cosine_hemisphere_lanes(u.x, u.y).into()
}

/// [`cosine_hemisphere`] for lanes of any [`Real`] type.
#[inline(always)]
pub fn cosine_hemisphere_lanes<R: Real>(ux: R, uy: R) -> V3<R> {
    let (x, y) = uniform_disk_lanes(ux, uy);
    V3::new(x, y, (R::splat(1.0) - (x * x + y * y)).max(R::splat(0.0)).sqrt())
}

/// Density of [`cosine_hemisphere`] at `w` (zero below the horizon).
pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    w.z.max(0.0) * FRAC_1_PI
}

/// A direction uniform over the cone of directions within angle acos(`cos_max`) of +z.
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    at_height(1.0 - u.x * (1.0 - cos_max), u.y).into()
}

/// A direction about +z with density (n + 1)/(2π) cos^n θ over the upper hemisphere: the
/// lobe of the normalized Phong BRDF (Lafortune and Willems 1994), cos θ = u^(1/(n+1)).
pub fn phong_lobe(u: Vec2, exponent: f32) -> Vec3 {
    phong_lobe_lanes(u.x, u.y, exponent).into()
}

/// [`phong_lobe`] per lane of any [`Real`] type.
#[inline(always)]
pub fn phong_lobe_lanes<R: Real>(ux: R, uy: R, exponent: R) -> V3<R> {
    at_height(ux.powf(R::splat(1.0) / (exponent + R::splat(1.0))), uy)
}

/// Density of [`phong_lobe`] at `w`.
pub fn phong_lobe_pdf(w: Vec3, exponent: f32) -> f32 {
    phong_lobe_pdf_lanes(w.into(), exponent)
}

/// [`phong_lobe_pdf`] per lane of any [`Real`] type.
#[inline(always)]
pub fn phong_lobe_pdf_lanes<R: Real>(w: V3<R>, exponent: R) -> R {
    let zero = R::splat(0.0);
    let pdf = (exponent + R::splat(1.0)) / R::splat(2.0 * PI) * w.z.powf(exponent);
    R::select(w.z.cmp_gt(zero), pdf, zero)
}

/// The unit direction with z-coordinate `z` at azimuth 2π `u_phi`: uniform z and azimuth
/// give uniform solid angle (Archimedes' hat-box theorem).
#[inline(always)]
fn at_height<R: Real>(z: R, u_phi: R) -> V3<R> {
    // 1 - z² is never -0, so `max`'s choice between zeros cannot show.
    let r = (R::splat(1.0) - z * z).max(R::splat(0.0)).sqrt();
    let (sin, cos) = crate::trig::sin_cos_turns(u_phi);
    V3::new(r * cos, r * sin, z)
}

/// Density of [`uniform_cone`] at `w`: 1 / (2π (1 - cos_max)) inside the cone, else zero.
pub fn uniform_cone_pdf(w: Vec3, cos_max: f32) -> f32 {
    if w.z >= cos_max {
        1.0 / (2.0 * PI * (1.0 - cos_max))
    } else {
        0.0
    }
}

/// Barycentric coordinates (b1, b2) of a point uniform over a triangle by area
/// (Heitz 2019's low-distortion map); the point is `(1 - b1 - b2) p0 + b1 p1 + b2 p2`.
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let (b1, b2) = uniform_triangle_lanes(u.x, u.y);
    Vec2::new(b1, b2)
}

/// [`uniform_triangle`] for lanes of any [`Real`] type.
#[inline(always)]
pub fn uniform_triangle_lanes<R: Real>(ux: R, uy: R) -> (R, R) {
    let two = R::splat(2.0);
    let (hx, hy) = (ux / two, uy / two);
    let below = ux.cmp_lt(uy);
    let b0 = R::select(below, hx, ux - hy);
    let b1 = R::select(below, uy - hx, hy);
    (b1, R::splat(1.0) - b0 - b1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_testkit::{chi2_directions, chi2_test, Grid2, Uniforms};

    /// Chi-square tests run in this module, for the significance correction.
    const TESTS: usize = 11;
    const N: usize = 400_000;

    /// The octant series agree with the library's sine and cosine to a few ulps.
    #[test]
    fn octant_series_match_sin_and_cos() {
        let mut worst = 0.0f32;
        for i in 0..=100_000 {
            let x = (i as f32 / 50_000.0 - 1.0) * FRAC_PI_4;
            let (s, c) = sin_cos_octant(x);
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
        }
        assert!(worst < 3e-7, "largest error {worst}");
    }

    #[test]
    fn direction_warps_fit_their_densities() {
        let r = chi2_directions(1, N, |u| Some(uniform_sphere(u)), |_| UNIFORM_SPHERE_PDF);
        r.assert_fits("uniform sphere", TESTS);
        let r = chi2_directions(
            2,
            N,
            |u| Some(uniform_hemisphere(u)),
            |w| if w.z >= 0.0 { UNIFORM_HEMISPHERE_PDF } else { 0.0 },
        );
        r.assert_fits("uniform hemisphere", TESTS);
        let r = chi2_directions(3, N, |u| Some(cosine_hemisphere(u)), cosine_hemisphere_pdf);
        r.assert_fits("cosine hemisphere", TESTS);
        assert!((r.integral - 1.0).abs() < 1e-4, "{}", r.describe());
        for (seed, cos_max) in [(4, 0.3f32), (5, 0.95), (6, -0.5)] {
            let r = chi2_directions(
                seed,
                N,
                |u| Some(uniform_cone(u, cos_max)),
                |w| uniform_cone_pdf(w, cos_max),
            );
            r.assert_fits(&format!("cone, cos_max {cos_max}"), TESTS);
            assert!((r.integral - 1.0).abs() < 1e-3, "cone {cos_max}: {}", r.describe());
        }
        for (seed, n) in [(8, 1.0f32), (9, 10.0), (10, 60.0)] {
            let r = chi2_directions(seed, N, |u| Some(phong_lobe(u, n)), |w| phong_lobe_pdf(w, n));
            r.assert_fits(&format!("Phong lobe, exponent {n}"), TESTS);
            assert!((r.integral - 1.0).abs() < 1e-3, "Phong {n}: {}", r.describe());
        }
    }

    #[test]
    fn area_warps_fit_their_densities() {
        let grid = Grid2 {
            min: [-1.0, -1.0],
            max: [1.0, 1.0],
            bins: [20, 20],
        };
        let mut u = Uniforms::new(7);
        let r = chi2_test(
            grid,
            N,
            || Some(uniform_disk(u.next_vec2())).map(|p| [p.x as f64, p.y as f64]),
            |[x, y]| {
                if x * x + y * y <= 1.0 {
                    UNIFORM_DISK_PDF as f64
                } else {
                    0.0
                }
            },
        );
        r.assert_fits("concentric disk", TESTS);
        // Barycentrics of a uniform triangle point: uniform over the half square b1 + b2 <= 1.
        let grid = Grid2 {
            min: [0.0, 0.0],
            max: [1.0, 1.0],
            bins: [20, 20],
        };
        let mut u = Uniforms::new(8);
        let r = chi2_test(
            grid,
            N,
            || Some(uniform_triangle(u.next_vec2())).map(|b| [b.x as f64, b.y as f64]),
            |[x, y]| if x + y <= 1.0 { 2.0 } else { 0.0 },
        );
        r.assert_fits("uniform triangle", TESTS);
    }

    #[test]
    fn warps_land_in_their_domains() {
        let mut rng = crate::Pcg32::new(1, 0);
        for _ in 0..10_000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            assert!(uniform_disk(u).length() <= 1.0 + 1e-6);
            assert!((uniform_sphere(u).length() - 1.0).abs() < 1e-5);
            let h = cosine_hemisphere(u);
            assert!((h.length() - 1.0).abs() < 1e-5 && h.z >= 0.0);
            let c = uniform_cone(u, 0.8);
            assert!((c.length() - 1.0).abs() < 1e-5 && c.z >= 0.8 - 1e-6);
            let b = uniform_triangle(u);
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
        }
    }
}
