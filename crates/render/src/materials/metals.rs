//! Named metals: complex indices of refraction η + ik as linear-sRGB triples, the measured
//! spectra Mitsuba and pbrt ship (Palik's handbook data) integrated against the CIE colour
//! matching functions, as circulated with Mitsuba's RGB mode.

use crate::bsdfs::Role;
use crate::spectral::{MaterialSpectra, SpectrumValue};
use penumbra_core::spectral::Tabulated;
use penumbra_core::Rgb;
use std::sync::Arc;

/// Name, η and k of every named metal.
pub const METALS: [(&str, [f32; 3], [f32; 3]); 4] = [
    ("Au", [0.143119, 0.374957, 1.442479], [3.98316, 2.385721, 1.603215]),
    ("Ag", [0.155265, 0.116723, 0.138381], [4.828343, 3.122246, 2.14695]),
    ("Cu", [0.200438, 0.924033, 1.102212], [3.912949, 2.452848, 2.142188]),
    ("Al", [1.65746, 0.880369, 0.521229], [9.223869, 6.269523, 4.837]),
];

/// η and k of the metal called `name` (e.g. "Au"), if known.
pub fn metal_ior(name: &str) -> Option<(Rgb, Rgb)> {
    METALS
        .iter()
        .find(|(n, _, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, eta, k)| (Rgb::from(*eta), Rgb::from(*k)))
}

/// The measured spectra of η and k of the metal called `name`, for spectral rendering
/// ([`super::metal_spectra`]), as the material's [`Role::Eta`] and [`Role::K`].
pub fn metal_spectra(name: &str) -> Option<MaterialSpectra> {
    let (_, eta, k) = super::metal_spectra::METAL_SPECTRA
        .iter()
        .find(|(n, _, _)| n.eq_ignore_ascii_case(name))?;
    let table = |rows: &[(f32, f32)]| {
        SpectrumValue::Tabulated(Arc::new(
            Tabulated::new(rows).expect("the built-in metal data are sorted"),
        ))
    };
    Some(MaterialSpectra {
        by_role: vec![(Role::Eta, table(eta)), (Role::K, table(k))],
        ior: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::spectral::cie;

    /// Normal-incidence reflectance |(η − 1 + ik)/(η + 1 + ik)|².
    fn r0(eta: f32, k: f32) -> f32 {
        ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k)
    }

    /// Each metal's reflectance colour at normal incidence from its spectra (Fresnel per
    /// wavelength, under D65) is near the colour its RGB η and k give (within 0.06: the RGB
    /// triples average η and k, not the reflectance, so gold's red differs by 0.055), and
    /// nearer to it than to any other metal's: the spectra are the metals the table names.
    #[test]
    fn metal_spectra_give_the_rgb_metals_colours() {
        let rgb: Vec<[f32; 3]> = METALS
            .iter()
            .map(|(_, eta, k)| std::array::from_fn(|i| r0(eta[i], k[i])))
            .collect();
        let distance = |a: [f32; 3], b: [f32; 3]| (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f32::max);
        for (m, (name, ..)) in METALS.iter().enumerate() {
            let s = metal_spectra(name).unwrap();
            let (e, kk) = (s.get(Role::Eta).unwrap(), s.get(Role::K).unwrap());
            let spectral = cie::srgb_of(|l| r0(e.eval(l), kk.eval(l)) * cie::d65_unit(l));
            println!("{name}: {spectral:?} against {:?}", rgb[m]);
            assert!(
                distance(spectral, rgb[m]) < 0.06,
                "{name}: {spectral:?} against {:?}",
                rgb[m]
            );
            for (other, c) in rgb.iter().enumerate().filter(|(o, _)| *o != m) {
                assert!(
                    distance(spectral, rgb[m]) < distance(spectral, *c),
                    "{name} is nearer {}",
                    METALS[other].0
                );
            }
        }
    }
}
