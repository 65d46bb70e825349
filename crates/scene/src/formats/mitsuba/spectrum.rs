//! Spectra to linear sRGB, as Mitsuba 3's RGB variants do when they load a `<spectrum>`:
//! X = ∫ S x̄ dλ / ∫ ȳ dλ (and likewise Y, Z) over 360-830 nm, then the XYZ to linear
//! sRGB (D65) matrix. The CIE 1931 matching functions are the multi-lobe Gaussian fit of
//! Wyman, Sloan and Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching
//! Functions" (JCGT 2013), within about 1% of the tables. A sampled spectrum is linear
//! between its samples and zero outside them (Mitsuba's `irregular` spectrum).

use penumbra_core::Rgb;

/// The piecewise Gaussian of the fit: `scale` times a Gaussian with different widths below
/// and above `mean` (inverse widths `a` and `b`).
fn lobe(x: f64, mean: f64, a: f64, b: f64) -> f64 {
    let t = (x - mean) * if x < mean { a } else { b };
    (-0.5 * t * t).exp()
}

/// CIE 1931 x̄, ȳ, z̄ at wavelength `l` in nanometres (Wyman et al. 2013, eq. 2-4).
pub fn cie_xyz(l: f64) -> [f64; 3] {
    let x = 1.056 * lobe(l, 599.8, 0.0264, 0.0323) + 0.362 * lobe(l, 442.0, 0.0624, 0.0374)
        - 0.065 * lobe(l, 501.1, 0.0490, 0.0382);
    let y = 0.821 * lobe(l, 568.8, 0.0213, 0.0247) + 0.286 * lobe(l, 530.9, 0.0613, 0.0322);
    let z = 1.217 * lobe(l, 437.0, 0.0845, 0.0278) + 0.681 * lobe(l, 459.0, 0.0385, 0.0725);
    [x, y, z]
}

/// The range the matching functions are integrated over, and the step (1 nm).
const FIRST: f64 = 360.0;
const LAST: f64 = 830.0;

/// Linear sRGB of the spectrum `samples` (wavelength in nm, value), sorted by wavelength.
pub fn spectrum_to_rgb(samples: &[(f64, f64)]) -> Rgb {
    let value = |l: f64| -> f64 {
        let i = samples.partition_point(|s| s.0 <= l);
        match i {
            0 => 0.0,
            _ if i == samples.len() => {
                let last = samples[i - 1];
                if l == last.0 {
                    last.1
                } else {
                    0.0
                }
            }
            _ => {
                let (a, b) = (samples[i - 1], samples[i]);
                a.1 + (b.1 - a.1) * (l - a.0) / (b.0 - a.0)
            }
        }
    };
    let (mut xyz, mut y_norm) = ([0.0f64; 3], 0.0);
    let steps = (LAST - FIRST) as usize;
    for k in 0..=steps {
        let l = FIRST + k as f64;
        let cmf = cie_xyz(l);
        let v = value(l);
        for c in 0..3 {
            xyz[c] += v * cmf[c];
        }
        y_norm += cmf[1];
    }
    let [x, y, z] = xyz.map(|c| c / y_norm);
    xyz_to_linear_srgb([x, y, z])
}

/// XYZ to linear sRGB primaries with a D65 white (IEC 61966-2-1).
pub fn xyz_to_linear_srgb([x, y, z]: [f64; 3]) -> Rgb {
    Rgb::new(
        (3.240479 * x - 1.537150 * y - 0.498535 * z) as f32,
        (-0.969256 * x + 1.875991 * y + 0.041556 * z) as f32,
        (0.055648 * x - 0.204043 * y + 1.057311 * z) as f32,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit's peaks where the CIE tables have them (x̄ 1.0622 at 595 nm, ȳ 1.0 at 555 nm,
    /// z̄ 1.7826 at 445-450 nm), within the fit's stated error.
    #[test]
    fn matching_functions_peak_where_the_tables_do() {
        assert!((cie_xyz(595.0)[0] - 1.0622).abs() < 0.02);
        assert!((cie_xyz(555.0)[1] - 1.0).abs() < 0.01);
        assert!((cie_xyz(447.0)[2] - 1.78).abs() < 0.03);
    }

    /// A flat spectrum of value v over the whole range is the equal-energy white of
    /// luminance v: Y = v exactly, and in sRGB (D65 white) slightly pink (x, y = 1/3).
    #[test]
    fn a_flat_spectrum_keeps_its_luminance() {
        let rgb = spectrum_to_rgb(&[(300.0, 0.5), (900.0, 0.5)]);
        let y = 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b;
        assert!((y - 0.5).abs() < 0.005, "{rgb:?}");
        assert!(rgb.r > rgb.b, "equal energy is redder than D65: {rgb:?}");
    }

    /// Samples outside the range count as zero; a spectrum seen only in the red is red.
    #[test]
    fn a_red_spectrum_is_red() {
        let rgb = spectrum_to_rgb(&[(600.0, 0.0), (620.0, 1.0), (700.0, 1.0)]);
        assert!(rgb.r > 5.0 * rgb.g.abs() && rgb.r > 5.0 * rgb.b.abs(), "{rgb:?}");
    }
}
