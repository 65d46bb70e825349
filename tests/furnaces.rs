//! Metropolis light transport (`mlt`) and the photon mappers (`sppm`, `photon`) against
//! closed forms, the furnaces `path` and `bdpt` pass (tests/path.rs, tests/bdpt.rs): a
//! camera inside a closed emitting sphere of albedo ρ sees (1 - ρ^D) / (1 - ρ) with at
//! most D segments; lossless balls vanish against an emitting sphere and under a uniform
//! environment.
//!
//! A photon lands in the gather discs of many pixels, and a Markov chain splats to many
//! pixels, so pixels are not independent and the image's own pixel spread says nothing of
//! the error of its mean. The standard error is taken from independent renders instead
//! (different seeds): that of the mean of K renders is their standard deviation over √K.

use penumbra::renderer::integrators::IntegratorKind;
use penumbra::scene::{SceneDesc, SourceFile};
use penumbra::RenderControl;

fn desc(text: &str) -> SceneDesc {
    penumbra::scene::formats::native::read(&SourceFile::new("test.toml", text.to_string())).unwrap()
}

/// The red channel's image mean over `runs` renders with seeds 1, 2, ..., and its
/// standard error from their spread. (`mlt` with a small bootstrap and few chains: the
/// furnaces are easy, and every path length gets its own bootstrap.)
fn mean_and_se(desc: &SceneDesc, integrator: IntegratorKind, spp: u32, runs: u32) -> (f64, f64) {
    let means: Vec<f64> = (1..=runs as u64)
        .map(|seed| {
            let mut desc = desc.clone();
            desc.render.mlt.bootstrap = 2000;
            desc.render.mlt.chains = 64;
            desc.render.integrator = integrator;
            desc.render.spp = spp;
            desc.render.seed = seed;
            let film = penumbra::render(&desc, RenderControl::default()).unwrap().film;
            let image = film.image();
            image.iter().map(|p| p.r as f64).sum::<f64>() / image.len() as f64
        })
        .collect();
    let k = means.len() as f64;
    let mean = means.iter().sum::<f64>() / k;
    let var = means.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (k - 1.0);
    (mean, (var / k).sqrt())
}

/// The closed furnace for D = 1, 2, 3, 6 segments at albedo 0.5 and 0.9, for `mlt` and
/// both photon mappers: within 4 standard errors and 1.5% of the series. Every photon
/// here has the same density everywhere, and a disc of chord radius r on a sphere has area
/// exactly π r², so neither the radius nor the k nearest leave a bias; only noise remains.
#[test]
fn mlt_and_photon_mappers_sum_the_furnace_series() {
    for integrator in [IntegratorKind::Mlt, IntegratorKind::Sppm, IntegratorKind::Photon] {
        for (albedo, max_depth) in [(0.5f64, 1u32), (0.5, 2), (0.5, 3), (0.9, 6)] {
            let mut scene = desc(&format!(
                "[render]\nwidth = 16\nheight = 16\nmax_depth = {max_depth}\n\
                 [camera]\nposition = [0.3, -0.2, 0.1]\ntarget = [1, 0.5, -2]\nfov = 70\n[[material]]\nname = \"wall\"\ndiffuse = {albedo}\n\
                 [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"wall\"\nemission = 1\ntwo_sided = true\n"
            ));
            scene.render.photon.photons = 20_000;
            scene.render.photon.lookup = 50;
            let (mean, se) = mean_and_se(&scene, integrator, 4, 6);
            let expected = (1.0 - albedo.powi(max_depth as i32)) / (1.0 - albedo);
            println!(
                "{integrator:?}: albedo {albedo}, max_depth {max_depth}: {mean:.5} ± {se:.5} (expected {expected:.5})"
            );
            assert!(
                (mean - expected).abs() < 4.0 * se + 1e-5 && (mean - expected).abs() < 0.015 * expected,
                "{integrator:?}: albedo {albedo}, max_depth {max_depth}: {mean} ± {se}, expected {expected}"
            );
        }
    }
}

/// The camera and the materials a blend refers to, for the balls below.
const BALL_SCENE: &str = "[render]\nwidth = 16\nheight = 16\nmax_depth = 64\n\
    [camera]\nposition = [0, 0, 2.5]\ntarget = [0, 0, 0]\nfov = 30\n\
    [[material]]\nname = \"glass\"\ntype = \"dielectric\"\n\
    [[material]]\nname = \"white\"\ntype = \"diffuse\"\nreflectance = 1\n";

/// The emitting sphere (radiance 1, reflecting nothing) the balls sit in.
const EMITTING_SPHERE: &str = "[[material]]\nname = \"black\"\ndiffuse = 0\n[[shape]]\ntype = \"sphere\"\nradius = 3\n\
    material = \"black\"\nemission = 1\ntwo_sided = true\n";

/// A ball of `material` (native-format keys) in `surroundings`, photon settings for tests.
fn ball(material: &str, surroundings: &str) -> SceneDesc {
    let mut scene = desc(&format!(
        "{BALL_SCENE}{surroundings}[[material]]\nname = \"ball\"\n{material}\n\
         [[shape]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"ball\"\n"
    ));
    scene.render.photon.photons = 10_000;
    scene.render.photon.caustic_photons = 10_000;
    scene.render.photon.lookup = 30;
    scene
}

/// Lossless balls (glass, glass as the `phong` material's transmission, white diffuse,
/// white plastic with its delta coat, a blend of glass and white) inside an emitting
/// sphere that reflects nothing, and under a uniform environment, the path tracer's
/// furnace list (tests/path.rs): as bright as their surroundings (radiance 1), within 4
/// standard errors (plus 1e-4 for rounding) and 2%. The plastic, the blend
/// and the glass exercise the photon mappers' camera walk at surfaces with both delta and
/// smooth parts, and its delta bounces.
#[test]
fn lossless_balls_vanish_for_mlt_and_the_photon_mappers() {
    for (what, material) in penumbra_testkit::furnace::LOSSLESS_BALLS {
        for surroundings in [EMITTING_SPHERE, "[environment]\nradiance = 1\n"] {
            let scene = ball(material, surroundings);
            let place = if surroundings.contains("environment") {
                "environment"
            } else {
                "sphere"
            };
            // `mlt` from 12 runs: its chains' splats make the run-to-run spread of the image
            // mean wide (±0.5% here), and 4 runs understated it (one plastic case came out
            // 0.9950 ± 0.0008 from 4 runs; 16 runs of it give 0.9997 ± 0.0010).
            for (integrator, runs) in [
                (IntegratorKind::Mlt, 12),
                (IntegratorKind::Sppm, 4),
                (IntegratorKind::Photon, 4),
            ] {
                let (mean, se) = mean_and_se(&scene, integrator, 8, runs);
                println!("{integrator:?}: {what} in the {place}: {mean:.5} ± {se:.5}");
                // (The cap is 2%: `mlt`'s standard error through the glass is 0.5% at these
                // settings, `photon`'s on the blend 1.2%.)
                let cap = 0.02;
                assert!(
                    (mean - 1.0).abs() < 4.0 * se + 1e-4 && (mean - 1.0).abs() < cap,
                    "{integrator:?}: {what} in the {place}: {mean} ± {se}"
                );
            }
        }
    }
}

/// Rough metal, rough glass and rough plastic balls in the emitting sphere, the path
/// tracer's second furnace list: darker than the surroundings (single-scattering GGX loses
/// energy), never brighter (within 4 standard errors), and not darker than the path
/// tracer's bounds; for `bdpt`, `mlt` and both photon mappers.
#[test]
fn rough_balls_lose_energy_for_every_integrator() {
    for (what, material, at_least) in penumbra_testkit::furnace::ROUGH_BALLS {
        let scene = ball(material, EMITTING_SPHERE);
        for (integrator, runs) in [
            (IntegratorKind::Bdpt, 4),
            (IntegratorKind::Mlt, 12),
            (IntegratorKind::Sppm, 4),
            (IntegratorKind::Photon, 4),
        ] {
            let (mean, se) = mean_and_se(&scene, integrator, 8, runs);
            println!("{integrator:?}: {what}: {mean:.5} ± {se:.5}");
            assert!(
                mean <= 1.0 + 4.0 * se + 1e-3,
                "{integrator:?}: {what} gains energy: {mean} ± {se}"
            );
            assert!(mean >= at_least, "{integrator:?}: {what} loses too much: {mean} ± {se}");
        }
    }
}
