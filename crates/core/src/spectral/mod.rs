//! Spectral data and conversions: the CIE 1931 observer and D65 ([`cie`]), the sampling of
//! a path's wavelengths ([`wavelengths`]), smooth spectra for RGB colours after Jakob and
//! Hanika 2019 ([`rgb2spec`], with the optimiser that makes its table in [`rgb2spec_opt`]),
//! blackbody emission ([`blackbody`]) and tabulated spectra ([`tabulated`]).
//!
//! What a path carries at its sampled wavelengths is [`crate::spectrum::Sampled4`].

pub mod blackbody;
pub mod cie;
#[rustfmt::skip]
#[allow(clippy::excessive_precision)]
mod cie_data;
pub mod rgb2spec;
pub mod rgb2spec_opt;
pub mod tabulated;
pub mod wavelengths;

pub use cie::{LAMBDA_MAX, LAMBDA_MIN};
pub use rgb2spec::{RgbToSpectrum, Sigmoid};
pub use tabulated::Tabulated;
pub use wavelengths::Wavelengths;
