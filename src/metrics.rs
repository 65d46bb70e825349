//! Image comparison: the error metrics `penumbra diff` prints and the convergence tests use.
//! Relative MSE follows the definition of ../shared/references/README.md (and of Rousselle
//! et al. 2011): the mean over pixels and channels of (a − r)² / (r² + 0.01).

use penumbra_core::Rgb;

/// How far an image is from a reference, over every pixel and channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    /// Root mean squared error.
    pub rmse: f64,
    /// Mean of (a − r)² / (r² + 0.01).
    pub rel_mse: f64,
    /// Mean of |a − r| / (|r| + 0.01).
    pub mean_abs_rel: f64,
    /// Mean of the image over mean of the reference, per channel: a global bias shows here
    /// even when noise dominates the other metrics.
    pub mean_ratio: [f64; 3],
}

/// The errors of `image` against `reference` (same size; pixels compared in order).
pub fn compare(image: &[Rgb], reference: &[Rgb]) -> Errors {
    assert_eq!(image.len(), reference.len(), "images of different sizes");
    let (mut se, mut rel, mut abs) = (0f64, 0f64, 0f64);
    let (mut sum_a, mut sum_r) = ([0f64; 3], [0f64; 3]);
    for (a, r) in image.iter().zip(reference) {
        for (k, (x, y)) in a.to_array().into_iter().zip(r.to_array()).enumerate() {
            sum_a[k] += x as f64;
            sum_r[k] += y as f64;
            let (x, y) = (x as f64, y as f64);
            let d = x - y;
            se += d * d;
            rel += d * d / (y * y + 0.01);
            abs += d.abs() / (y.abs() + 0.01);
        }
    }
    let n = (3 * image.len()).max(1) as f64;
    Errors {
        rmse: (se / n).sqrt(),
        rel_mse: rel / n,
        mean_abs_rel: abs / n,
        mean_ratio: [0, 1, 2].map(|k| sum_a[k] / sum_r[k]),
    }
}

/// A false-colour picture of the per-pixel relative error |a − r| / (|r| + 0.01) (mean of
/// the channels), on a log scale from 1e-3 (black) through blue, green and yellow to 1 and
/// above (white). Values are display-ready: written to PNG they appear as drawn.
pub fn error_image(image: &[Rgb], reference: &[Rgb]) -> Vec<Rgb> {
    image
        .iter()
        .zip(reference)
        .map(|(a, r)| {
            let e: f32 = a
                .to_array()
                .into_iter()
                .zip(r.to_array())
                .map(|(x, y)| (x - y).abs() / (y.abs() + 0.01))
                .sum::<f32>()
                / 3.0;
            let t = ((e.max(1e-3).log10() + 3.0) / 3.0).clamp(0.0, 1.0);
            // Black -> blue -> green -> yellow -> white, linearised for the PNG curve.
            let stops = [
                [0.0, 0.0, 0.0],
                [0.1, 0.2, 0.9],
                [0.1, 0.8, 0.3],
                [1.0, 0.9, 0.1],
                [1.0, 1.0, 1.0],
            ];
            let x = t * (stops.len() - 1) as f32;
            let i = (x as usize).min(stops.len() - 2);
            let f = x - i as f32;
            let c: Vec<f32> = (0..3).map(|k| stops[i][k] * (1.0 - f) + stops[i + 1][k] * f).collect();
            Rgb::new(c[0], c[1], c[2]).map(|v| v.powf(2.2))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_of_known_differences() {
        let r = vec![Rgb::splat(1.0), Rgb::splat(0.0)];
        let a = vec![Rgb::splat(1.1), Rgb::splat(0.1)];
        let e = compare(&a, &r);
        assert!((e.rmse - 0.1).abs() < 1e-6, "{e:?}");
        // (0.01 / 1.01 + 0.01 / 0.01) / 2
        assert!((e.rel_mse - (0.01 / 1.01 + 1.0) / 2.0).abs() < 1e-6, "{e:?}");
        assert!((e.mean_abs_rel - (0.1 / 1.01 + 0.1 / 0.01) / 2.0).abs() < 1e-5, "{e:?}");
        assert_eq!(compare(&r, &r).rel_mse, 0.0);
        let img = error_image(&a, &r);
        assert_eq!(img.len(), 2);
        assert!(img[1].luminance() > img[0].luminance(), "larger errors are brighter");
    }
}
