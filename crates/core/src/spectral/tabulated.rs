//! A spectrum given at wavelengths (nanometres, increasing), linear between them and 0
//! outside them, as Mitsuba's `irregular`/`regular` spectra and pbrt-v4's
//! `PiecewiseLinearSpectrum` are.

/// Samples (λ, value), λ strictly increasing.
#[derive(Clone, Debug, PartialEq)]
pub struct Tabulated {
    lambda: Vec<f32>,
    value: Vec<f32>,
}

impl Tabulated {
    /// The spectrum of `points`, if there is at least one, the wavelengths increase and
    /// every number is finite.
    pub fn new(points: &[(f32, f32)]) -> Result<Self, String> {
        if points.is_empty() {
            return Err("a spectrum needs at least one wavelength:value pair".into());
        }
        if let Some((l, v)) = points.iter().find(|(l, v)| !(l.is_finite() && v.is_finite())) {
            return Err(format!("{l}:{v} is not a finite wavelength and value"));
        }
        if let Some(w) = points.windows(2).find(|w| w[1].0 <= w[0].0) {
            return Err(format!(
                "wavelengths must increase ({} nm comes after {} nm)",
                w[1].0, w[0].0
            ));
        }
        Ok(Tabulated {
            lambda: points.iter().map(|p| p.0).collect(),
            value: points.iter().map(|p| p.1).collect(),
        })
    }

    /// The value at `lambda`: linear between samples, 0 outside them (a single sample is a
    /// constant).
    pub fn eval(&self, lambda: f32) -> f32 {
        if self.lambda.len() == 1 {
            return self.value[0];
        }
        let (first, last) = (self.lambda[0], self.lambda[self.lambda.len() - 1]);
        if !(lambda >= first && lambda <= last) {
            return 0.0;
        }
        let i = self
            .lambda
            .partition_point(|&l| l <= lambda)
            .clamp(1, self.lambda.len() - 1)
            - 1;
        let t = (lambda - self.lambda[i]) / (self.lambda[i + 1] - self.lambda[i]);
        self.value[i] + t * (self.value[i + 1] - self.value[i])
    }

    /// The largest value.
    pub fn max_value(&self) -> f32 {
        self.value.iter().copied().fold(0.0, f32::max)
    }
}
