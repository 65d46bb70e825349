//! The furnace balls every light-transport integrator is tested with (tests/path.rs,
//! tests/furnaces.rs), as native-format material keys: one list for all of them.

/// Balls that must vanish against surroundings of radiance 1: (name, material keys). The
/// blend refers to materials named `glass` and `white`, which the scene must define.
pub const LOSSLESS_BALLS: [(&str, &str); 5] = [
    ("smooth glass", "type = \"dielectric\"\nior = 1.5"),
    ("phong glass", "diffuse = 0\ntransmission = 1\nior = 1.5"),
    ("white diffuse", "type = \"diffuse\"\nreflectance = 1"),
    ("white plastic", "type = \"plastic\"\ndiffuse = 1\nior = 1.5"),
    (
        "blend of glass and white",
        "type = \"blend\"\na = \"glass\"\nb = \"white\"\nweight = 0.3",
    ),
];

/// Rough balls, darker than their surroundings (single-scattering GGX loses energy) but
/// not below the bound: (name, material keys, bound). (Single-scattering GGX loses 31% at
/// normal incidence for α = 0.5, by quadrature of D G2 cos θm.)
pub const ROUGH_BALLS: [(&str, &str, f64); 4] = [
    (
        "rough metal 0.1",
        "type = \"conductor\"\neta = 1\nk = 10000\nroughness = 0.1",
        0.97,
    ),
    (
        "rough metal 0.8",
        "type = \"conductor\"\neta = 1\nk = 10000\nroughness = 0.8",
        0.4,
    ),
    ("rough glass 0.3", "type = \"dielectric\"\nroughness = 0.3", 0.6),
    // Mitsuba 3's rough plastic model (ours) loses much more than the bare GGX lobe: its
    // base is seen through the coating's single-scattering transmittance, and Mitsuba's own
    // `roughplastic` with a white base has albedo 0.69 at normal incidence and 0.66 at 70°
    // for α = 0.3 (its `sample`, 100,000 draws, scalar_rgb). Ours in the furnace: 0.689-0.693
    // for bdpt, mlt, sppm and photon (standard errors 0.001-0.002); the floor is 10 of them
    // below.
    (
        "rough plastic 0.3",
        "type = \"plastic\"\ndiffuse = 1\nroughness = 0.3",
        0.67,
    ),
];
