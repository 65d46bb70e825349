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
    /// A refractive index by Sellmeier's equation, n² = 1 + Σ B λ² / (λ² − C), λ in µm.
    Sellmeier { b: [f32; 3], c: [f32; 3] },
}

/// Glasses by name (Schott's catalogue Sellmeier coefficients; fused silica after
/// Malitson 1965), as pbrt-v4 names them (`glass-BK7`, ...) without the prefix.
#[allow(clippy::excessive_precision)]
pub const GLASSES: [(&str, [f32; 3], [f32; 3]); 7] = [
    (
        "BK7",
        [1.039_612_1, 0.231_792_34, 1.010_469_5],
        [0.006_000_699, 0.020_017_914, 103.560_65],
    ),
    (
        "BAF10",
        [1.585_149_5, 0.143_559_39, 1.085_212_7],
        [0.009_266_813, 0.042_448_98, 105.613_57],
    ),
    (
        "FK51A",
        [0.971_247_8, 0.216_901_42, 0.904_651_7],
        [0.004_723_02, 0.015_357_561, 168.681_33],
    ),
    (
        "LASF9",
        [2.000_295_5, 0.298_926_9, 1.806_918_4],
        [0.012_142_602, 0.053_873_624, 156.530_83],
    ),
    (
        "SF5",
        [1.524_818_9, 0.187_085_53, 1.427_290_2],
        [0.011_254_756, 0.058_899_54, 129.141_67],
    ),
    (
        "SF11",
        [1.737_597, 0.313_747_35, 1.898_781],
        [0.013_188_707, 0.062_306_814, 155.236_29],
    ),
    (
        "fused-silica",
        [0.696_166_3, 0.407_942_6, 0.897_479_4],
        [0.004_679_148, 0.013_512_063, 97.934],
    ),
];

/// The glass called `name` (case-insensitive; a `glass-` prefix allowed).
pub fn glass(name: &str) -> Option<SpectrumValue> {
    let name = name.strip_prefix("glass-").unwrap_or(name);
    GLASSES
        .iter()
        .find(|(n, ..)| n.eq_ignore_ascii_case(name))
        .map(|&(_, b, c)| SpectrumValue::Sellmeier { b, c })
}

impl SpectrumValue {
    /// The value at `lambda` nanometres.
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            SpectrumValue::Tabulated(t) => t.eval(lambda),
            SpectrumValue::Blackbody { kelvin, scale } => scale * Blackbody::new(*kelvin).eval(lambda),
            SpectrumValue::Sellmeier { b, c } => {
                let l2 = (lambda * 1e-3).powi(2);
                let n2 = 1.0 + (0..3).map(|i| b[i] * l2 / (l2 - c[i])).sum::<f32>();
                n2.max(1.0).sqrt()
            }
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
    /// A dielectric's index of refraction inside by wavelength, and the index outside: a
    /// dispersive glass (its RGB-mode index is `eta` of the material).
    pub ior: Option<(SpectrumValue, f32)>,
}

impl MaterialSpectra {
    pub fn get(&self, role: Role) -> Option<&SpectrumValue> {
        self.by_role.iter().find(|(r, _)| *r == role).map(|(_, s)| s)
    }
}

/// An emitter's own spectrum: its radiance is `scale` times `spectrum`, and `rgb` is the
/// RGB radiance the emitter has in the scene for it (the RGB values the light answers,
/// scaled by a texture or a distance falloff, scale the spectrum alike).
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterSpectrum {
    pub spectrum: SpectrumValue,
    pub scale: f32,
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
    /// The mean over the channels the path still carries (all of RGB's, as `Rgb::mean`;
    /// a dispersed spectral path's hero alone): the spectral MIS of `volpath` over the
    /// wavelengths that could have drawn the path.
    fn mean(&self, s: Self::S) -> f32;
    /// The hero wavelength, if the path carries wavelengths.
    fn hero(&self) -> Option<f32>;
    /// Whether the path still carries several wavelengths (not RGB paths, not paths
    /// already dispersed).
    fn carries_several(&self) -> bool;
    /// Keeps the hero wavelength alone: a dispersive refraction sends the others elsewhere.
    fn keep_hero_only(&mut self);
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
    fn hero(&self) -> Option<f32> {
        None
    }
    fn carries_several(&self) -> bool {
        false
    }
    fn keep_hero_only(&mut self) {}
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
                own.scale * c.max_component() / reference
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
        if self.wl.is_hero_only() {
            s.0[0]
        } else {
            s.brightness()
        }
    }

    fn hero(&self) -> Option<f32> {
        Some(self.wl.lambda[0])
    }

    fn carries_several(&self) -> bool {
        !self.wl.is_hero_only()
    }

    fn keep_hero_only(&mut self) {
        self.wl.keep_hero_only();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::Pcg32;

    /// Each glass's index at the helium d line (587.56 nm) is its catalogue n_d.
    #[test]
    fn glasses_have_their_catalogue_indices() {
        for (name, nd) in [
            ("BK7", 1.5168),
            ("glass-BAF10", 1.67003),
            ("FK51A", 1.48656),
            ("LASF9", 1.85025),
            ("SF5", 1.67271),
            ("sf11", 1.78472),
            ("fused-silica", 1.45846),
        ] {
            let n = glass(name).unwrap().eval(587.56);
            assert!((n - nd).abs() < 2e-4, "{name}: {n} against {nd}");
        }
        // Normal dispersion: blue bends more than red.
        let bk7 = glass("BK7").unwrap();
        assert!(bk7.eval(450.0) > bk7.eval(650.0));
        assert!(glass("unobtainium").is_none());
    }

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
            scale: 1.0,
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
