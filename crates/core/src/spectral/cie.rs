//! The CIE 1931 2° standard observer x̄, ȳ, z̄ and the D65 illuminant, tabulated per
//! nanometre over [360, 830] nm and interpolated linearly between (as Mitsuba 3 does); the
//! conversion of XYZ to linear sRGB (IEC 61966-2-1, D65 white).

use super::cie_data::{CIE_X, CIE_Y, CIE_Z, D65, SAMPLES};
pub use super::cie_data::{LAMBDA_MAX, LAMBDA_MIN};

/// ∫ ȳ(λ) dλ over the tables (trapezoids of 1 nm): the Y of a constant spectrum 1.
pub const CIE_Y_INTEGRAL: f32 = 106.857_03;

/// Linear interpolation in a per-nanometre table; 0 outside [360, 830] nm.
#[inline]
fn lookup(table: &[f32; SAMPLES], lambda: f32) -> f32 {
    let x = lambda - LAMBDA_MIN;
    if !(0.0..=LAMBDA_MAX - LAMBDA_MIN).contains(&x) {
        return 0.0;
    }
    let i = (x as usize).min(SAMPLES - 2);
    let t = x - i as f32;
    table[i] + t * (table[i + 1] - table[i])
}

/// (x̄, ȳ, z̄) at `lambda` nanometres.
#[inline]
pub fn xyz_bar(lambda: f32) -> [f32; 3] {
    [lookup(&CIE_X, lambda), lookup(&CIE_Y, lambda), lookup(&CIE_Z, lambda)]
}

/// ȳ at `lambda` nanometres.
#[inline]
pub fn y_bar(lambda: f32) -> f32 {
    lookup(&CIE_Y, lambda)
}

/// The D65 illuminant's relative power at `lambda` (100 at 560 nm).
#[inline]
pub fn d65(lambda: f32) -> f32 {
    lookup(&D65, lambda)
}

/// The D65 illuminant scaled so that, as radiance, its Y is 1 ([`xyz_of`]):
/// `d65(λ) ∫ȳ dλ / ∫ d65 ȳ dλ`. An RGB illuminant's spectrum is its smooth reflectance
/// times this.
#[inline]
pub fn d65_unit(lambda: f32) -> f32 {
    d65(lambda) * D65_UNIT
}

/// ∫ȳ dλ / ∫ d65 ȳ dλ.
const D65_UNIT: f32 = CIE_Y_INTEGRAL / 10_566.881;

/// XYZ to linear sRGB (Rec. 709 primaries, D65 white), rows.
pub const XYZ_TO_SRGB: [[f32; 3]; 3] = [
    [3.240_479, -1.537_15, -0.498_535],
    [-0.969_256, 1.875_991, 0.041_556],
    [0.055_648, -0.204_043, 1.057_311],
];

/// Linear sRGB to XYZ, rows (the inverse of [`XYZ_TO_SRGB`]).
pub const SRGB_TO_XYZ: [[f32; 3]; 3] = [
    [0.412_453, 0.357_580, 0.180_423],
    [0.212_671, 0.715_160, 0.072_169],
    [0.019_334, 0.119_193, 0.950_227],
];

/// `m` times `v`.
#[inline]
pub fn apply(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// The XYZ of a spectrum `f` (radiance or, times an illuminant, reflectance), summed per
/// nanometre over the tables and divided by ∫ȳ, so that a constant 1 has Y = 1.
pub fn xyz_of(f: impl Fn(f32) -> f32) -> [f32; 3] {
    let mut xyz = [0f64; 3];
    for i in 0..SAMPLES {
        let lambda = LAMBDA_MIN + i as f32;
        let w = if i == 0 || i == SAMPLES - 1 { 0.5 } else { 1.0 };
        let v = f(lambda) as f64 * w;
        xyz[0] += v * CIE_X[i] as f64;
        xyz[1] += v * CIE_Y[i] as f64;
        xyz[2] += v * CIE_Z[i] as f64;
    }
    xyz.map(|c| (c / CIE_Y_INTEGRAL as f64) as f32)
}

/// The linear sRGB of a spectrum of radiance `f` (as [`xyz_of`]).
pub fn srgb_of(f: impl Fn(f32) -> f32) -> [f32; 3] {
    apply(&XYZ_TO_SRGB, xyz_of(f))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constants above are the tables' own sums, and the matrices invert each other.
    #[test]
    fn integrals_and_matrices_agree_with_the_tables() {
        let y = xyz_of(|_| 1.0)[1];
        assert!((y - 1.0).abs() < 1e-6, "{y}");
        let white = xyz_of(d65_unit);
        assert!((white[1] - 1.0).abs() < 1e-5, "{white:?}");
        // D65's chromaticity is (0.3127, 0.3290).
        let sum = white[0] + white[1] + white[2];
        assert!((white[0] / sum - 0.3127).abs() < 5e-4 && (white[1] / sum - 0.3290).abs() < 5e-4);
        // ... and D65 is sRGB's white: (1, 1, 1).
        let rgb = srgb_of(d65_unit);
        assert!(rgb.iter().all(|c| (c - 1.0).abs() < 2e-3), "{rgb:?}");
        for (i, e) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            let back = apply(&XYZ_TO_SRGB, apply(&SRGB_TO_XYZ, e));
            assert!(back.iter().zip(e).all(|(a, b)| (a - b).abs() < 1e-4), "{i}: {back:?}");
        }
        assert_eq!(xyz_bar(359.0), [0.0; 3]);
        assert_eq!(y_bar(555.0), 1.0);
        assert!((y_bar(555.5) - 0.9995).abs() < 1e-6);
    }
}
