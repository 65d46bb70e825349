//! Named metals: complex indices of refraction η + ik as linear-sRGB triples, the measured
//! spectra Mitsuba and pbrt ship (Palik's handbook data) integrated against the CIE colour
//! matching functions, as circulated with Mitsuba's RGB mode.

use penumbra_core::Rgb;

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
