//! Blackbody emission by Planck's law, as pbrt-v4's `BlackbodySpectrum`: normalised so that
//! its peak (at λ = b / T by Wien's displacement law) is 1.

/// The spectral radiance of a blackbody at `kelvin`, in W/(m² sr m), at `lambda` nanometres.
pub fn planck(lambda: f32, kelvin: f32) -> f32 {
    if kelvin <= 0.0 {
        return 0.0;
    }
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda as f64 * 1e-9;
    let le = 2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * kelvin as f64)).exp() - 1.0));
    le as f32
}

/// A blackbody's spectrum scaled to peak at 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blackbody {
    pub kelvin: f32,
    norm: f32,
}

impl Blackbody {
    pub fn new(kelvin: f32) -> Self {
        let peak = 2.897_772e-3 / kelvin as f64 * 1e9;
        Blackbody {
            kelvin,
            norm: 1.0 / planck(peak as f32, kelvin),
        }
    }

    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        planck(lambda, self.kelvin) * self.norm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Wien's law places the peak; the Stefan-Boltzmann law gives the total, π∫B dλ = σT⁴
    /// (integrated over 10 nm to 100 µm).
    #[test]
    fn planck_peaks_where_wien_says_and_integrates_to_stefan_boltzmann() {
        let b = Blackbody::new(5000.0);
        let peak = 2.897_772e6 / 5000.0;
        assert!((b.eval(peak) - 1.0).abs() < 1e-5);
        assert!(b.eval(peak - 5.0) < 1.0 && b.eval(peak + 5.0) < 1.0);
        let total: f64 = (0..100_000)
            .map(|i| planck(10.0 + i as f32 + 0.5, 5000.0) as f64 * 1e-9)
            .sum();
        let sigma = 5.670_374e-8 * 5000f64.powi(4);
        assert!(
            (std::f64::consts::PI * total / sigma - 1.0).abs() < 2e-3,
            "{}",
            std::f64::consts::PI * total / sigma
        );
    }
}
