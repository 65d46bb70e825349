//! How a path turns the scene's colours into what it carries ([`Tint`]): RGB as it is
//! ([`RgbTint`]), or, in spectral mode, values at the path's four wavelengths
//! ([`SpectralTint`]; hero-wavelength sampling, Wilkie et al. 2014): RGB reflectances
//! uplifted to smooth spectra (Jakob and Hanika 2019: [`penumbra_core::spectral::rgb2spec`]),
//! RGB emission uplifted and multiplied by D65 (pbrt-v4's `RGBIlluminantSpectrum`, Mitsuba's
//! `d65`), and the spectra a scene gives itself ([`SpectrumValue`]: tabulated, blackbody)
//! evaluated directly. The integrator is one program over the tint's payload type.

use crate::bsdfs::Role;
use penumbra_core::lanes::V3;
use penumbra_core::spectral::blackbody::Blackbody;
use penumbra_core::spectral::rgb2spec::Unbounded;
use penumbra_core::spectral::{cie, RgbToSpectrum, Tabulated, Wavelengths};
use penumbra_core::spectrum::{Sampled4, Spectrum};
use penumbra_core::Rgb;
use std::sync::Arc;

/// A spectrum the scene gives (rather than an RGB colour).
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumValue {
    /// Linear between samples, 0 outside them.
    Tabulated(Arc<Tabulated>),
    /// A blackbody's normalised spectrum (peak 1) times `scale`.
    Blackbody { kelvin: f32, scale: f32 },
}

impl SpectrumValue {
    /// The value at `lambda` nanometres.
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            SpectrumValue::Tabulated(t) => t.eval(lambda),
            SpectrumValue::Blackbody { kelvin, scale } => scale * Blackbody::new(*kelvin).eval(lambda),
        }
    }

    /// Its colour as radiance (linear sRGB through the CIE 1931 observer).
    pub fn radiance_rgb(&self) -> Rgb {
        let [r, g, b] = cie::srgb_of(|l| self.eval(l));
        Rgb::new(r, g, b)
    }

    /// Its colour as a reflectance under D65 (linear sRGB).
    pub fn reflectance_rgb(&self) -> Rgb {
        let [r, g, b] = cie::srgb_of(|l| self.eval(l) * cie::d65_unit(l));
        Rgb::new(r, g, b)
    }
}

/// The spectra a material gives for some of its parameters; the others are uplifted from
/// their RGB values.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialSpectra {
    pub by_role: Vec<(Role, SpectrumValue)>,
}

impl MaterialSpectra {
    pub fn get(&self, role: Role) -> Option<&SpectrumValue> {
        self.by_role.iter().find(|(r, _)| *r == role).map(|(_, s)| s)
    }
}

/// An emitter's own spectrum and the RGB radiance it stands for (which the emitter's RGB
/// values are scaled from).
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterSpectrum {
    pub spectrum: SpectrumValue,
    pub rgb: Rgb,
}

/// How a path turns the scene's colours into its payload [`Tint::S`].
pub trait Tint {
    type S: Spectrum<f32> + Copy + std::fmt::Debug;
    /// A material parameter of `role` whose RGB value is `c` (its spectrum taken from
    /// `spectra` where the material gives one).
    fn param(&self, spectra: Option<&MaterialSpectra>, role: Role, c: V3<f32>) -> Self::S;
    /// Emitted radiance `c` (RGB), of an emitter with spectrum `own` if it has one.
    fn illuminant(&self, own: Option<&EmitterSpectrum>, c: Rgb) -> Self::S;
    /// A positive coefficient of any size (a medium's σ).
    fn unbounded(&self, c: Rgb) -> Self::S;
    /// The same value in every channel.
    fn splat(&self, v: f32) -> Self::S {
        Self::S::splat(v)
    }
    /// The radiance `s` as linear sRGB for the film.
    fn to_rgb(&self, s: Self::S) -> Rgb;
    /// The mean over the channels (as `Rgb::mean` for RGB).
    fn mean(&self, s: Self::S) -> f32;
}

/// RGB rendering: colours as they are.
#[derive(Clone, Copy, Debug, Default)]
pub struct RgbTint;

impl Tint for RgbTint {
    type S = V3<f32>;
    #[inline]
    fn param(&self, _: Option<&MaterialSpectra>, _: Role, c: V3<f32>) -> V3<f32> {
        c
    }
    #[inline]
    fn illuminant(&self, _: Option<&EmitterSpectrum>, c: Rgb) -> V3<f32> {
        c.into()
    }
    #[inline]
    fn unbounded(&self, c: Rgb) -> V3<f32> {
        c.into()
    }
    #[inline]
    fn to_rgb(&self, s: V3<f32>) -> Rgb {
        s.into()
    }
    #[inline]
    fn mean(&self, s: V3<f32>) -> f32 {
        Rgb::from(s).mean()
    }
}

/// Spectral rendering: values at a path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct SpectralTint {
    pub wl: Wavelengths,
    table: &'static RgbToSpectrum,
}

impl SpectralTint {
    /// The tint of a path whose hero wavelength is drawn by `u`.
    pub fn sample(u: f32) -> Self {
        SpectralTint {
            wl: Wavelengths::sample_visible(u),
            table: RgbToSpectrum::srgb(),
        }
    }

    fn each(&self, f: impl Fn(f32) -> f32) -> Sampled4<f32> {
        Sampled4(self.wl.lambda.map(f))
    }

    /// An RGB reflectance (in [0, 1]) at the wavelengths.
    pub fn reflectance(&self, c: Rgb) -> Sampled4<f32> {
        if c.max_component() > 1.0 {
            return self.unbounded(c);
        }
        let s = self.table.sigmoid(c.to_array());
        self.each(|l| s.eval(l))
    }
}

impl Tint for SpectralTint {
    type S = Sampled4<f32>;

    fn param(&self, spectra: Option<&MaterialSpectra>, role: Role, c: V3<f32>) -> Sampled4<f32> {
        if let Some(s) = spectra.and_then(|m| m.get(role)) {
            return self.each(|l| s.eval(l));
        }
        let c = Rgb::from(c);
        if role.bounded() {
            self.reflectance(c)
        } else {
            self.unbounded(c)
        }
    }

    fn illuminant(&self, own: Option<&EmitterSpectrum>, c: Rgb) -> Sampled4<f32> {
        if let Some(own) = own {
            // The emitter's RGB values are its spectrum's colour times a scale (a texture,
            // a distance falloff).
            let reference = own.rgb.max_component();
            let scale = if reference > 0.0 {
                c.max_component() / reference
            } else {
                0.0
            };
            return self.each(|l| own.spectrum.eval(l) * scale);
        }
        let u = Unbounded::new(self.table, c.to_array());
        self.each(|l| u.eval(l) * cie::d65_unit(l))
    }

    fn unbounded(&self, c: Rgb) -> Sampled4<f32> {
        let u = Unbounded::new(self.table, c.to_array());
        self.each(|l| u.eval(l))
    }

    fn to_rgb(&self, s: Sampled4<f32>) -> Rgb {
        let [r, g, b] = self.wl.to_srgb(s.0);
        Rgb::new(r, g, b)
    }

    fn mean(&self, s: Sampled4<f32>) -> f32 {
        s.brightness()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::Pcg32;

    /// Averaged over many paths' wavelengths, an uplifted RGB emission, and an uplifted
    /// reflectance lit by a white (D65) one, come back as their RGB colours (to the
    /// table's accuracy and 3 standard errors; a coloured light's product is not the RGB
    /// product, which is the point of spectral rendering); a tabulated emitter gives its own
    /// spectrum's colour.
    #[test]
    fn uplifted_colours_average_back_to_their_rgb() {
        let light = Rgb::new(18.387, 13.9873, 6.75357);
        let albedo = Rgb::new(0.570068, 0.0430135, 0.0443706);
        let flat = EmitterSpectrum {
            spectrum: SpectrumValue::Tabulated(Arc::new(Tabulated::new(&[(400.0, 2.0), (700.0, 4.0)]).unwrap())),
            rgb: Rgb::WHITE,
        };
        let white = Rgb::splat(5.0);
        let expected = [light, albedo * white, flat.spectrum.radiance_rgb() * 3.0];
        let mut rng = Pcg32::new(1, 7);
        let n = 200_000;
        let mut sums = [[0f64; 3]; 3];
        let mut squares = [[0f64; 3]; 3];
        for _ in 0..n {
            let t = SpectralTint::sample(rng.next_f32());
            let e = t.illuminant(None, light);
            let lit = t.reflectance(albedo).mul_each(t.illuminant(None, white));
            let values = [e, lit, t.illuminant(Some(&flat), Rgb::splat(3.0))];
            for (k, v) in values.into_iter().enumerate() {
                let c = t.to_rgb(v).to_array();
                for i in 0..3 {
                    sums[k][i] += c[i] as f64;
                    squares[k][i] += (c[i] as f64).powi(2);
                }
            }
        }
        for k in 0..3 {
            let want = expected[k].to_array();
            for i in 0..3 {
                let mean = sums[k][i] / n as f64;
                let se = ((squares[k][i] / n as f64 - mean * mean) / n as f64).sqrt();
                // The table's round trip is good to about 0.005 of the brightest channel.
                let tolerance = 3.0 * se + 0.006 * expected[k].max_component() as f64;
                assert!(
                    (mean - want[i] as f64).abs() < tolerance,
                    "case {k} channel {i}: {mean} ± {se} against {}",
                    want[i]
                );
            }
        }
    }
}
