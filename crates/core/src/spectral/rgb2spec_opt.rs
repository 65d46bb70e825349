//! The optimiser that makes [`super::RgbToSpectrum`]'s table (Jakob and Hanika 2019,
//! section 3; the procedure of their `rgb2spec_opt`): for each colour of a grid over the
//! RGB cube, Gauss-Newton finds the sigmoid-of-a-quadratic reflectance whose colour under
//! the space's white (D65 for sRGB) matches it in CIELAB. Each column of the grid is solved
//! from a middle brightness upwards and downwards, each solve starting from its
//! neighbour's answer.
//!
//! Regenerate the built-in table with
//! `cargo run --release -p penumbra-core --example make_rgb2spec -- 32 crates/core/data/rgb2spec-srgb.bin`.

use super::cie::{self, LAMBDA_MAX, LAMBDA_MIN, SRGB_TO_XYZ, XYZ_TO_SRGB};
use super::RgbToSpectrum;

/// Wavelengths integrated over (Simpson's 3/8 rule at 5/3 nm over [360, 830]).
const FINE: usize = 283;

/// The integration tables: each wavelength (normalised to [0, 1]) and the linear-sRGB
/// response to a unit reflectance there under D65, quadrature weight included.
struct Tables {
    lambda: [f64; FINE],
    rgb: [[f64; FINE]; 3],
    white: [f64; 3],
}

fn tables() -> Tables {
    let h = (LAMBDA_MAX - LAMBDA_MIN) as f64 / (FINE - 1) as f64;
    let mut t = Tables {
        lambda: [0.0; FINE],
        rgb: [[0.0; FINE]; 3],
        white: [0.0; 3],
    };
    for i in 0..FINE {
        let lambda = LAMBDA_MIN as f64 + i as f64 * h;
        let bar = cie::xyz_bar(lambda as f32).map(f64::from);
        // D65 with Y = 1 as these sums (without ∫ȳ) weigh it: white's XYZ is sRGB's (1, 1, 1).
        let light = cie::d65_unit(lambda as f32) as f64 / cie::CIE_Y_INTEGRAL as f64;
        let weight = 3.0 / 8.0
            * h
            * match i {
                0 => 1.0,
                _ if i == FINE - 1 => 1.0,
                _ if (i - 1) % 3 == 2 => 2.0,
                _ => 3.0,
            };
        t.lambda[i] = (lambda - LAMBDA_MIN as f64) / (LAMBDA_MAX - LAMBDA_MIN) as f64;
        for k in 0..3 {
            for j in 0..3 {
                t.rgb[k][i] += XYZ_TO_SRGB[k][j] as f64 * bar[j] * light * weight;
            }
            t.white[k] += bar[k] * light * weight;
        }
    }
    t
}

/// CIELAB of a linear-sRGB colour, relative to the tables' white.
fn lab(t: &Tables, rgb: [f64; 3]) -> [f64; 3] {
    let xyz: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| SRGB_TO_XYZ[i][j] as f64 * rgb[j]).sum());
    let f = |v: f64| {
        let d = 6.0 / 29.0;
        if v > d * d * d {
            v.cbrt()
        } else {
            v / (3.0 * d * d) + 4.0 / 29.0
        }
    };
    let (fx, fy, fz) = (f(xyz[0] / t.white[0]), f(xyz[1] / t.white[1]), f(xyz[2] / t.white[2]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

fn sigmoid(x: f64) -> f64 {
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// The target's CIELAB minus that of the reflectance of normalised coefficients `c`.
fn residual(t: &Tables, c: [f64; 3], target: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for i in 0..FINE {
        let x = t.lambda[i];
        let s = sigmoid((c[0] * x + c[1]) * x + c[2]);
        for (o, row) in out.iter_mut().zip(&t.rgb) {
            *o += row[i] * s;
        }
    }
    let (a, b) = (lab(t, target), lab(t, out));
    std::array::from_fn(|j| a[j] - b[j])
}

/// Solves the 3x3 system `m x = r` by Gaussian elimination with partial pivoting.
fn solve(mut m: [[f64; 3]; 3], mut r: [f64; 3]) -> Option<[f64; 3]> {
    for col in 0..3 {
        let p = (col..3).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[p][col].abs() < 1e-15 {
            return None;
        }
        m.swap(col, p);
        r.swap(col, p);
        for row in col + 1..3 {
            let f = m[row][col] / m[col][col];
            let pivot = m[col];
            for (v, p) in m[row][col..].iter_mut().zip(&pivot[col..]) {
                *v -= f * p;
            }
            r[row] -= f * r[col];
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let s: f64 = (row + 1..3).map(|k| m[row][k] * x[k]).sum();
        x[row] = (r[row] - s) / m[row][row];
    }
    Some(x)
}

/// Gauss-Newton from `c` towards `target` (at most 15 steps, until the squared CIELAB
/// residual is below 1e-6); returns the residual's length.
fn gauss_newton(t: &Tables, target: [f64; 3], c: &mut [f64; 3]) -> f64 {
    const EPS: f64 = 1e-4;
    let mut r2 = 0.0;
    for _ in 0..15 {
        let res = residual(t, *c, target);
        let mut jac = [[0.0; 3]; 3];
        for i in 0..3 {
            let (mut lo, mut hi) = (*c, *c);
            lo[i] -= EPS;
            hi[i] += EPS;
            let (r0, r1) = (residual(t, lo, target), residual(t, hi, target));
            for j in 0..3 {
                jac[j][i] = (r1[j] - r0[j]) / (2.0 * EPS);
            }
        }
        let Some(step) = solve(jac, res) else {
            break;
        };
        r2 = 0.0;
        for j in 0..3 {
            c[j] -= step[j];
            r2 += res[j] * res[j];
        }
        let m = c[0].max(c[1]).max(c[2]);
        if m > 200.0 {
            for v in c.iter_mut() {
                *v *= 200.0 / m;
            }
        }
        if r2 < 1e-6 {
            break;
        }
    }
    r2.sqrt()
}

fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

/// The brightness nodes of a table of resolution `res`: twice-smoothstepped, denser near 0
/// and 1.
pub fn z_nodes(res: usize) -> Vec<f32> {
    (0..res)
        .map(|k| smoothstep(smoothstep(k as f64 / (res - 1) as f64)) as f32)
        .collect()
}

/// The coefficients (in nanometres, highest power first) of one column of the table: the
/// largest channel `l`, grid point (`x`, `y`), every brightness; and the largest residual.
pub fn column(res: usize, l: usize, x: usize, y: usize) -> (Vec<[f32; 3]>, f64) {
    let t = tables();
    column_with(&t, res, l, x, y)
}

fn column_with(t: &Tables, res: usize, l: usize, xi: usize, yi: usize) -> (Vec<[f32; 3]>, f64) {
    let z = z_nodes(res);
    let (x, y) = (xi as f64 / (res - 1) as f64, yi as f64 / (res - 1) as f64);
    let mut out = vec![[0.0f32; 3]; res];
    let mut worst = 0.0f64;
    let start = res / 5;
    let mut solve_at = |k: usize, c: &mut [f64; 3]| {
        let b = z[k] as f64;
        let mut rgb = [0.0; 3];
        rgb[l] = b;
        rgb[(l + 1) % 3] = x * b;
        rgb[(l + 2) % 3] = y * b;
        worst = worst.max(gauss_newton(t, rgb, c));
        // From λ normalised to [0, 1] back to nanometres.
        let (c0, c1) = (LAMBDA_MIN as f64, 1.0 / (LAMBDA_MAX - LAMBDA_MIN) as f64);
        let [a, b, cc] = *c;
        out[k] = [
            (a * c1 * c1) as f32,
            (b * c1 - 2.0 * a * c0 * c1 * c1) as f32,
            (cc - b * c0 * c1 + a * c0 * c0 * c1 * c1) as f32,
        ];
    };
    let mut c = [0.0; 3];
    for k in start..res {
        solve_at(k, &mut c);
    }
    let mut c = [0.0; 3];
    for k in (0..=start).rev() {
        solve_at(k, &mut c);
    }
    (out, worst)
}

/// The whole table at resolution `res`, its columns shared among `threads` threads; and
/// the largest CIELAB residual of any entry.
pub fn build(res: usize, threads: usize) -> (RgbToSpectrum, f64) {
    let t = tables();
    let columns: Vec<(usize, usize, usize)> = (0..3)
        .flat_map(|l| (0..res).flat_map(move |y| (0..res).map(move |x| (l, x, y))))
        .collect();
    let mut coeffs = vec![0.0f32; 9 * res * res * res];
    let mut worst = 0.0f64;
    let next = std::sync::atomic::AtomicUsize::new(0);
    type Solved = (usize, Vec<[f32; 3]>, f64);
    let results: Vec<Vec<Solved>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads.max(1))
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(&(l, x, y)) = columns.get(i) else {
                            break;
                        };
                        let (col, w) = column_with(&t, res, l, x, y);
                        mine.push((i, col, w));
                    }
                    mine
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("an optimiser thread"))
            .collect()
    });
    for (i, col, w) in results.into_iter().flatten() {
        let (l, x, y) = columns[i];
        worst = worst.max(w);
        for (z, c) in col.into_iter().enumerate() {
            let at = 3 * (((l * res + z) * res + y) * res + x);
            coeffs[at..at + 3].copy_from_slice(&c);
        }
    }
    (RgbToSpectrum::new(res, z_nodes(res), coeffs), worst)
}
