//! The volumetric path tracer (`volpath`) against closed forms.
//!
//! - Transmittance: an absorbing slab between the camera and a white background passes
//!   exp(-σa d) of it, per channel (each channel's σa differs, so the hero-channel
//!   sampling and its spectral MIS are exercised).
//! - Furnaces: a medium of albedo 1 (any σt per channel, any phase function) under a uniform
//!   environment of radiance 1, bounded by a null surface or by glass, looks exactly like
//!   its surroundings: every path ends in the environment.
//! - Without media, `volpath` is `path`, bit for bit.
//! - Spectral mode (paths of four wavelengths): the same furnaces, now per wavelength; an
//!   emitter's own spectrum seen through its colour.

use penumbra::math::{PixelSampler, Ray, SamplerKind, UVec2, Vec3};
use penumbra::renderer::integrators::{IntegratorKind, IntegratorOptions, MAX_DEPTH_LIMIT};
use penumbra::renderer::{RayCounts, Scene};
use penumbra::scene::{build_scene, SourceFile};
use penumbra_testkit::{assert_within_3se, MeanEstimate};

fn scene_from(text: &str) -> Scene {
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("media.toml", text.to_string())).unwrap();
    build_scene(&desc).unwrap()
}

/// Mean and standard error, per channel, of `n` estimates by `kind` along the rays
/// `ray(i)`, paths of at most `max_depth` segments.
fn estimate(scene: &Scene, kind: IntegratorKind, max_depth: u32, n: u32, ray: impl Fn(u32) -> Ray) -> [(f64, f64); 3] {
    let options = IntegratorOptions {
        max_depth,
        ..IntegratorOptions::default()
    };
    let integrator = kind.create(options);
    let mut sampler = PixelSampler::new(SamplerKind::Independent, 5, n);
    let mut counts = RayCounts::default();
    let mut m: [MeanEstimate; 3] = Default::default();
    for i in 0..n {
        sampler.start(UVec2::new(i % 1009, i / 1009), i);
        let c = integrator.li(scene, &ray(i), &mut sampler, &mut counts, &mut Vec::new());
        for (m, v) in m.iter_mut().zip(c.to_array()) {
            m.push(v as f64);
        }
    }
    m.map(|m| (m.mean(), m.standard_error()))
}

/// Rays from a point of a disk of radius 0.3 about `from` towards points of a disk of
/// radius 0.3 about `to` (both in the plane facing each other).
fn beam(from: Vec3, to: Vec3) -> impl Fn(u32) -> Ray {
    move |i| {
        let (a, b) = (i as f32 * 0.618_034, i as f32 * 0.414_214);
        let wobble = |s: f32, t: f32| Vec3::new(0.3 * s.sin(), 0.3 * t.cos(), 0.3 * (s + t).sin());
        let origin = from + wobble(a, b);
        Ray::new(origin, to + wobble(3.0 * b, 5.0 * a) - origin)
    }
}

/// An absorbing slab 1.5 units thick (a box with null faces) passes exp(-σa 1.5) of the
/// white background behind it: σa = (0.2, 0.8, 2.0). The estimator of one channel is
/// L T_c / mean(T) with probability mean(T) (the hero channel's survival), so its relative
/// standard deviation is sqrt(1/mean(T) - 1) = 1.6: over 40,000 paths, 0.8%.
#[test]
fn a_slab_passes_its_transmittance() {
    let scene = scene_from(
        "[world]\nbackground = 1\n\n\
         [[medium]]\nname = \"ink\"\nsigma_a = [0.2, 0.8, 2.0]\nsigma_s = 0\n\n\
         [[material]]\nname = \"boundary\"\ntype = \"null\"\n\n\
         [[shape]]\ntype = \"box\"\nmin = [-5, -5, -1.5]\nmax = [5, 5, 0]\nmaterial = \"boundary\"\ninterior = \"ink\"\n",
    );
    let result = estimate(
        &scene,
        IntegratorKind::Volpath,
        8,
        40_000,
        beam(Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.0, 0.0, -3.0)),
    );
    for ((mean, se), sigma) in result.into_iter().zip([0.2f64, 0.8, 2.0]) {
        // The rays lean by up to about 0.1 rad: their paths are longer by up to 0.5%.
        let expected = (-sigma * 1.5).exp();
        println!("sigma_a {sigma}: {mean:.5} +- {se:.5} (slab {expected:.5})");
        let slack = expected * 0.006 * sigma;
        assert_within_3se(&format!("sigma_a {sigma}"), mean, se, expected, slack);
    }
}

/// The camera inside an absorbing ball (its medium named by `[camera] medium`) of radius
/// 2 sees exp(-σa 2) of the white background in every direction.
#[test]
fn a_camera_in_a_medium_sees_through_it() {
    let scene = scene_from(
        "[world]\nbackground = 1\n\n[camera]\nposition = [0, 0, 0]\ntarget = [0, 0, -1]\nmedium = \"fog\"\n\n\
         [[medium]]\nname = \"fog\"\nsigma_a = [0.1, 0.3, 0.6]\nsigma_s = 0\n\n\
         [[material]]\nname = \"boundary\"\ntype = \"null\"\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"boundary\"\ninterior = \"fog\"\n",
    );
    let result = estimate(&scene, IntegratorKind::Volpath, 8, 40_000, |i| {
        let (a, b) = (i as f32 * 0.618_034, i as f32 * 0.414_214);
        Ray::new(Vec3::ZERO, Vec3::new(a.sin(), b.cos(), (a + b).sin()))
    });
    for ((mean, se), sigma) in result.into_iter().zip([0.1f64, 0.3, 0.6]) {
        let expected = (-sigma * 2.0).exp();
        println!("sigma_a {sigma}: {mean:.5} +- {se:.5} ({expected:.5})");
        assert_within_3se(&format!("sigma_a {sigma}"), mean, se, expected, 1e-4);
    }
}

/// Media of albedo 1 vanish under a uniform environment of radiance 1: scattering moves
/// light around but loses none, so each channel's mean is 1 (within 3 standard errors, and
/// 2%: the standard errors over 200,000 paths are 0.2-0.5%), whatever σt per channel,
/// phase function and boundary (a null surface, or glass that refracts the paths in and
/// out).
#[test]
fn white_media_vanish_in_a_uniform_environment() {
    let cases = [
        (
            "isotropic, null boundary",
            "sigma_a = 0\nsigma_s = [0.5, 2.0, 5.0]",
            "type = \"null\"",
        ),
        (
            "forward HG, null boundary",
            "sigma_a = 0\nsigma_s = [3.0, 1.0, 0.3]\nphase = \"hg\"\ng = 0.7",
            "type = \"null\"",
        ),
        (
            "backward HG, glass boundary",
            "albedo = 1\nsigma_t = [1.0, 2.0, 4.0]\nphase = \"hg\"\ng = -0.4",
            "type = \"dielectric\"",
        ),
    ];
    for (what, medium, boundary) in cases {
        let scene = scene_from(&format!(
            "[environment]\nradiance = 1\n\n[[medium]]\nname = \"cloud\"\n{medium}\n\n\
             [[material]]\nname = \"boundary\"\n{boundary}\n\n\
             [[shape]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\ninterior = \"cloud\"\n"
        ));
        let result = estimate(
            &scene,
            IntegratorKind::Volpath,
            MAX_DEPTH_LIMIT,
            200_000,
            beam(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO),
        );
        for (c, (mean, se)) in result.into_iter().enumerate() {
            println!("{what}, channel {c}: {mean:.5} +- {se:.5}");
            assert_within_3se(&format!("{what}, channel {c}"), mean, se, 1.0, 1e-4);
            assert!((mean - 1.0).abs() < 0.02, "{what}, channel {c}: {mean}");
        }
    }
}

/// A scene without media gets `path`'s radiance from `volpath`, bit for bit.
#[test]
fn without_media_volpath_is_path() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cbox-mitsuba.toml")).unwrap();
    let scene = scene_from(&text);
    let rays = beam(Vec3::new(0.0, 1.0, 3.5), Vec3::new(0.0, 1.0, 0.0));
    let path = estimate(&scene, IntegratorKind::Path, 8, 2_000, &rays);
    let volpath = estimate(&scene, IntegratorKind::Volpath, 8, 2_000, &rays);
    assert_eq!(path, volpath);
    assert!(path[0].0 > 0.0);
}

/// A camera inside a black sphere that emits radiance 1 from its inside, filled with a
/// medium of albedo 1, sees 1 in every channel: every path ends on the sphere. The light
/// is an area light, sampled from points in the medium and met by phase-sampled rays.
/// Within 3 standard errors (0.1-0.25% over a million paths).
#[test]
fn a_white_medium_inside_an_emitting_sphere_is_its_radiance() {
    // A boundary (the same medium on both sides) just inside the light: light samples'
    // shadow rays cross it 0.02 short of the light. (Going on from the pushed-off crossing
    // point in the old direction, they used to meet the light itself and count it as a
    // blocker: 0.4-1.1% too dark, 10-20 standard errors at 4 million paths.)
    let null_shell = "[[material]]\nname = \"boundary\"\ntype = \"null\"\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 1.98\nmaterial = \"boundary\"\ninterior = \"cloud\"\nexterior = \"cloud\"\n";
    for (what, medium, extra) in [
        ("isotropic", "sigma_a = 0\nsigma_s = [0.5, 1.0, 2.0]", ""),
        ("forward HG", "sigma_a = 0\nsigma_s = 1.5\nphase = \"hg\"\ng = 0.6", ""),
        (
            "isotropic, a boundary just inside",
            "sigma_a = 0\nsigma_s = [0.5, 1.0, 2.0]",
            null_shell,
        ),
    ] {
        let scene = scene_from(&format!(
            "[camera]\nposition = [0, 0, 0]\ntarget = [0, 0, -1]\nmedium = \"cloud\"\n\n\
             [[medium]]\nname = \"cloud\"\n{medium}\n\n\
             [[material]]\nname = \"black\"\ntype = \"diffuse\"\nreflectance = 0\n\n\
             [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"black\"\nemission = 1\ntwo_sided = true\ninterior = \"cloud\"\n{extra}"
        ));
        sees_radiance_one(&scene, what, 1_000_000);
    }
}

/// The camera-medium scenes inside the emitting sphere: `n` paths from points near its
/// centre in every direction average 1 in each channel, within 3 standard errors.
fn sees_radiance_one(scene: &Scene, what: &str, n: u32) {
    sees(scene, IntegratorKind::Volpath, what, n, [1.0; 3], 1e-4);
}

/// [`sees_radiance_one`] by `kind`, expecting `want` within 3 standard errors and `slack`.
fn sees(scene: &Scene, kind: IntegratorKind, what: &str, n: u32, want: [f32; 3], slack: f64) {
    let result = estimate(scene, kind, MAX_DEPTH_LIMIT, n, |i| {
        let (a, b) = (i as f32 * 0.618_034, i as f32 * 0.414_214);
        Ray::new(
            Vec3::new(0.5 * a.cos(), 0.5 * b.sin(), 0.3),
            Vec3::new(a.sin(), b.cos(), (a + b).sin()),
        )
    });
    for (c, (mean, se)) in result.into_iter().enumerate() {
        println!("{what}, channel {c}: {mean:.5} +- {se:.5}");
        assert_within_3se(&format!("{what}, channel {c}"), mean, se, want[c] as f64, slack);
    }
}

/// Spectral furnaces: inside a sphere that emits radiance 1 (white: D65 with Y = 1, whose
/// sRGB is (1, 1, 1) to 2e-3), a camera sees 1 in every channel through a white medium of
/// coloured σt, past a white diffuse ball, a glass ball and a dispersive flint ball (SF11:
/// paths that meet it keep their hero wavelength alone, weighted 4x): every wavelength's
/// path ends on the emitter with its full value. `path` traces the media-free scene spectrally too.
/// Within 3 standard errors (about 0.3% over 200,000 paths: the four wavelengths' XYZ
/// estimate is noisy) and the 2e-3 of D65's colour.
#[test]
fn spectral_furnaces_see_the_white_light() {
    let shell = "[[material]]\nname = \"black\"\ntype = \"diffuse\"\nreflectance = 0\n\n\
                 [[material]]\nname = \"white\"\ntype = \"diffuse\"\nreflectance = 1\n\n\
                 [[material]]\nname = \"glass\"\ntype = \"dielectric\"\n\n\
                 [[material]]\nname = \"flint\"\ntype = \"dielectric\"\nior = \"SF11\"\n\n\
                 [[shape]]\ntype = \"sphere\"\ncenter = [0, 0.8, -1]\nradius = 0.4\nmaterial = \"flint\"\n\n\
                 [[shape]]\ntype = \"sphere\"\ncenter = [0.8, 0, -1]\nradius = 0.4\nmaterial = \"white\"\n\n\
                 [[shape]]\ntype = \"sphere\"\ncenter = [-0.8, 0, -1]\nradius = 0.4\nmaterial = \"glass\"\n\n\
                 [render]\nintegrator = \"path\"\nspectral = true\n\n\
                 [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"black\"\nemission = 1\ntwo_sided = true\n";
    let scene = scene_from(shell);
    assert!(scene.spectral);
    sees(&scene, IntegratorKind::Path, "spectral path", 200_000, [1.0; 3], 2e-3);
    let scene = scene_from(&format!(
        "[camera]\nposition = [0, 0, 0]\ntarget = [0, 0, -1]\nmedium = \"cloud\"\n\n\
         [[medium]]\nname = \"cloud\"\nalbedo = 1\nsigma_t = [0.5, 1.0, 2.0]\n\n{}interior = \"cloud\"\n",
        shell
    ));
    sees(
        &scene,
        IntegratorKind::Volpath,
        "spectral volpath",
        200_000,
        [1.0; 3],
        2e-3,
    );
}

/// An emitter with its own spectrum (a ramp from 2 at 400 nm to 4 at 700 nm, 0 outside),
/// seen from inside: the colour of that spectrum (its sRGB through the CIE observer), not
/// the uplift of its RGB. Within 3 standard errors over 200,000 paths.
#[test]
fn an_emitters_own_spectrum_is_seen() {
    use penumbra::math::spectral::Tabulated;
    use penumbra::math::Rgb;
    use penumbra::renderer::spectral::{EmitterSpectrum, SpectrumValue};
    let mut scene = scene_from(
        "[render]\nintegrator = \"path\"\nspectral = true\n\n[[material]]\nname = \"black\"\ntype = \"diffuse\"\nreflectance = 0\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"black\"\nemission = 1\ntwo_sided = true\n",
    );
    let ramp = SpectrumValue::Tabulated(std::sync::Arc::new(
        Tabulated::new(&[(400.0, 2.0), (700.0, 4.0)]).unwrap(),
    ));
    let want = ramp.radiance_rgb();
    scene.light_spectra = vec![Some(EmitterSpectrum {
        spectrum: ramp,
        scale: 1.0,
        rgb: Rgb::WHITE,
    })];
    sees(
        &scene,
        IntegratorKind::Path,
        "ramp emitter",
        200_000,
        want.to_array(),
        1e-4,
    );
}

/// A grid medium of albedo 1 (density rising along x from 0 to 1, σt 1.5/3/0.5 where it
/// is 1) inside an emitting sphere is the sphere's radiance: delta tracking against the
/// majorant grid, null collisions and ratio-tracked shadow rays lose nothing and add
/// nothing. Within 3 standard errors over 400,000 paths.
#[test]
fn a_white_grid_medium_inside_an_emitting_sphere_is_its_radiance() {
    use glam::UVec3;
    use penumbra::math::{Rgb, Transform};
    use penumbra::renderer::media::{DensityGrid, GridMedium, Medium};
    use penumbra::renderer::phase::{HenyeyGreenstein, Phase};
    let mut scene = scene_from(
        "[camera]\nposition = [0, 0, 0]\ntarget = [0, 0, -1]\nmedium = \"cloud\"\n\n\
         [[medium]]\nname = \"cloud\"\n\n\
         [[material]]\nname = \"black\"\ntype = \"diffuse\"\nreflectance = 0\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"black\"\nemission = 1\ntwo_sided = true\ninterior = \"cloud\"\n",
    );
    let res = UVec3::new(16, 4, 4);
    let values = (0..res.x * res.y * res.z)
        .map(|i| ((i % res.x) as f32 + 0.5) / res.x as f32)
        .collect();
    let grid = std::sync::Arc::new(DensityGrid::new(res, values).unwrap());
    // The grid's unit cube stretched over [-2, 2]^3, the whole sphere.
    let to_world = Transform::scale(Vec3::splat(4.0))
        .unwrap()
        .then(Transform::translate(Vec3::splat(-2.0)));
    let phase = Phase::HenyeyGreenstein(HenyeyGreenstein::new(0.3));
    scene.media[0] = Medium::Grid(GridMedium::new(
        grid,
        Rgb::new(1.5, 3.0, 0.5),
        Rgb::WHITE,
        phase,
        to_world,
    ));
    sees_radiance_one(&scene, "grid medium", 400_000);
}
