//! Bidirectional path tracing against closed forms and against the path tracer.
//!
//! The furnaces are those the path tracer passes (tests/path.rs), rendered through the
//! driver so that light tracing's splats count: a camera inside a closed emitting sphere
//! of albedo ρ sees (1 - ρ^D) / (1 - ρ) with at most D segments; lossless balls vanish
//! against an emitting sphere and under a uniform environment. Every pixel has the same
//! expectation there, so the standard error of the image mean is the pixels' standard
//! deviation over the square root of their number.

use penumbra::renderer::integrators::{strategy_layer, IntegratorKind};
use penumbra::renderer::Film;
use penumbra::scene::{SceneDesc, SourceFile};
use penumbra::RenderControl;

fn desc(text: &str) -> SceneDesc {
    penumbra::scene::formats::native::read(&SourceFile::new("test.toml", text.to_string())).unwrap()
}

/// Renders `desc` with `integrator` at `spp` samples and seed `seed`.
fn render(desc: &SceneDesc, integrator: IntegratorKind, spp: u32, seed: u64, debug: bool) -> Film {
    let mut desc = desc.clone();
    desc.render.integrator = integrator;
    desc.render.spp = spp;
    desc.render.seed = seed;
    let control = RenderControl {
        debug_strategies: debug,
        ..RenderControl::default()
    };
    penumbra::render(&desc, control).unwrap().film
}

/// Mean of the red channel over the image, and its standard error (pixels independent).
fn mean_and_se(film: &Film) -> (f64, f64) {
    let v: Vec<f64> = film.image().iter().map(|p| p.r as f64).collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The closed furnace for D = 1, 2, 3, 6 segments at albedo 0.5 and 0.9: the geometric
/// series within 4 standard errors (about 0.3% here) and 1%.
#[test]
fn bdpt_sums_the_furnace_series() {
    for (albedo, max_depth) in [(0.5f64, 1u32), (0.5, 2), (0.5, 3), (0.9, 6)] {
        let scene = desc(&format!(
            "[render]\nwidth = 24\nheight = 24\nsampler = \"independent\"\nmax_depth = {max_depth}\n\
             [camera]\nposition = [0.3, -0.2, 0.1]\ntarget = [1, 0.5, -2]\nfov = 70\n[[material]]\nname = \"wall\"\ndiffuse = {albedo}\n\
             [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"wall\"\nemission = 1\ntwo_sided = true\n"
        ));
        let film = render(&scene, IntegratorKind::Bdpt, 16, 1, false);
        let (mean, se) = mean_and_se(&film);
        let expected = (1.0 - albedo.powi(max_depth as i32)) / (1.0 - albedo);
        println!("albedo {albedo}, max_depth {max_depth}: {mean:.5} ± {se:.5} (expected {expected:.5})");
        assert!(
            (mean - expected).abs() < 4.0 * se + 1e-5 && (mean - expected).abs() < 0.01 * expected,
            "albedo {albedo}, max_depth {max_depth}: {mean} ± {se}, expected {expected}"
        );
    }
}

/// Lossless balls (glass, white diffuse, white plastic) inside an emitting sphere that
/// reflects nothing, and under a uniform environment: as bright as their surroundings
/// (radiance 1), within 4 standard errors (plus 1e-4 for rounding in the single-precision
/// Fresnel and η² factors, as the path tracer's test allows) and 1%. The environment case starts light paths
/// at infinity (a disk facing the scene) and ends camera paths there.
#[test]
fn lossless_balls_vanish_for_bdpt() {
    let camera = "[render]\nwidth = 24\nheight = 24\nmax_depth = 64\nsampler = \"independent\"\n\
        [camera]\nposition = [0, 0, 2.5]\ntarget = [0, 0, 0]\nfov = 30\n";
    for (what, material) in [
        ("glass", "type = \"dielectric\"\nior = 1.5"),
        ("white diffuse", "type = \"diffuse\"\nreflectance = 1"),
        ("white plastic", "type = \"plastic\"\ndiffuse = 1\nior = 1.5"),
    ] {
        for surroundings in [
            "[[material]]\nname = \"black\"\ndiffuse = 0\n[[shape]]\ntype = \"sphere\"\nradius = 3\n\
             material = \"black\"\nemission = 1\ntwo_sided = true\n",
            "[environment]\nradiance = 1\n",
        ] {
            let scene = desc(&format!(
                "{camera}{surroundings}[[material]]\nname = \"ball\"\n{material}\n\
                 [[shape]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"ball\"\n"
            ));
            let film = render(&scene, IntegratorKind::Bdpt, 32, 2, false);
            let (mean, se) = mean_and_se(&film);
            let place = if surroundings.contains("environment") {
                "environment"
            } else {
                "sphere"
            };
            println!("{what} in the {place}: {mean:.5} ± {se:.5}");
            assert!(
                (mean - 1.0).abs() < 4.0 * se + 1e-4 && (mean - 1.0).abs() < 0.01,
                "{what} in the {place}: {mean} ± {se}"
            );
        }
    }
}

/// Each strategy on its own, unweighted, estimates the whole of its path length: with at
/// most two segments, the emitter seen directly (s = 0, t = 2) plus any one of the three
/// direct-lighting strategies (BSDF sampling s = 0, t = 3; light sampling s = 1, t = 2;
/// light tracing s = 2, t = 1) matches `path` in the image mean, within 4 standard errors
/// of the difference (the standard errors from 8 independent renders of each). And the
/// weighted strategy images add up to the image, pixel by pixel.
#[test]
fn every_strategy_alone_estimates_its_path_length() {
    let text = "[render]\nwidth = 32\nheight = 32\nmax_depth = 2\nsampler = \"independent\"\n\
        filter = { type = \"box\" }\n\
        [camera]\nposition = [0, 1, 3.5]\ntarget = [0, 0.8, 0]\nfov = 50\n\
        [[material]]\nname = \"white\"\ntype = \"diffuse\"\nreflectance = 0.8\n\
        [[material]]\nname = \"red\"\ntype = \"diffuse\"\nreflectance = [0.8, 0.2, 0.1]\n\
        [[shape]]\ntype = \"quad\"\ncorner = [-2, 0, 2]\nedge1 = [4, 0, 0]\nedge2 = [0, 0, -4]\nmaterial = \"white\"\n\
        [[shape]]\ntype = \"quad\"\ncorner = [-2, 0, -2]\nedge1 = [4, 0, 0]\nedge2 = [0, 2.5, 0]\nmaterial = \"red\"\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [0.3, 0.5, 0]\nradius = 0.5\nmaterial = \"white\"\n\
        [[shape]]\ntype = \"quad\"\ncorner = [-0.5, 2, -0.5]\nedge1 = [1, 0, 0]\nedge2 = [0, 0, 1]\nmaterial = \"white\"\nemission = 6\n";
    let scene = desc(text);
    let mean_of = |pixels: &[penumbra::math::Rgb]| pixels.iter().map(|p| p.r as f64).sum::<f64>() / pixels.len() as f64;
    let stats = |xs: &[f64]| {
        let n = xs.len() as f64;
        let m = xs.iter().sum::<f64>() / n;
        let var = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
        (m, (var / n).sqrt())
    };
    let runs = 8;
    let mut path = Vec::new();
    let mut strategies: Vec<Vec<f64>> = vec![Vec::new(); 3];
    for seed in 0..runs {
        path.push(mean_of(
            &render(&scene, IntegratorKind::Path, 16, 100 + seed, false).image(),
        ));
        let film = render(&scene, IntegratorKind::Bdpt, 16, 200 + seed, true);
        let layers: std::collections::BTreeMap<u32, Vec<penumbra::math::Rgb>> =
            film.layer_images().into_iter().collect();
        let seen = mean_of(&layers[&strategy_layer(0, 2, false)]);
        for (k, (s, t)) in [(0, 3), (1, 2), (2, 1)].into_iter().enumerate() {
            strategies[k].push(seen + mean_of(&layers[&strategy_layer(s, t, false)]));
        }
        // The weighted images add up to the image.
        let image = film.image();
        let mut sum = vec![penumbra::math::Rgb::BLACK; image.len()];
        for (&layer, pixels) in &layers {
            if layer % 2 == 0 {
                for (s, p) in sum.iter_mut().zip(pixels) {
                    *s += *p;
                }
            }
        }
        let off = image
            .iter()
            .zip(&sum)
            .filter(|(a, b)| (a.r - b.r).abs() > 1e-4 * (1.0 + a.r.abs()))
            .count();
        assert!(
            off <= image.len() / 100,
            "{off} pixels differ from the sum of the strategies"
        );
        assert!((mean_of(&image) - mean_of(&sum)).abs() < 1e-4 * mean_of(&image));
    }
    let (p, p_se) = stats(&path);
    for (k, name) in [
        "s=0, t=3 (BSDF sampling)",
        "s=1, t=2 (light sampling)",
        "s=2, t=1 (light tracing)",
    ]
    .iter()
    .enumerate()
    {
        let (m, se) = stats(&strategies[k]);
        let tolerance = 4.0 * (se * se + p_se * p_se).sqrt();
        println!("{name}: {m:.5} ± {se:.5}; path {p:.5} ± {p_se:.5}");
        assert!((m - p).abs() < tolerance, "{name}: {m} ± {se} vs path {p} ± {p_se}");
    }
}
