//! The `env` integrator's strategies (light, bsdf, mis, sir, smc) estimate the same
//! direct lighting from an environment map, in every frame of an animation; and
//! `penumbra render --frames` writes numbered images.

mod common;

use common::{penumbra, text};
use penumbra::renderer::integrators::{EnvSampling, IntegratorKind};
use penumbra::scene::{SceneDesc, SourceFile};
use penumbra::RenderControl;
use std::path::PathBuf;

/// Every strategy.
const ALL: [EnvSampling; 5] = [
    EnvSampling::Light,
    EnvSampling::Bsdf,
    EnvSampling::Mis,
    EnvSampling::Sir,
    EnvSampling::Smc,
];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Renders frames `frames` of `desc` with `sampling` through one integrator (so `smc`
/// carries its particles), at `spp`: each frame's image as luminances.
fn frames(desc: &SceneDesc, sampling: EnvSampling, spp: u32, frames: std::ops::Range<u32>) -> Vec<Vec<f64>> {
    let mut desc = desc.clone();
    desc.render.integrator = IntegratorKind::Env;
    desc.render.env.sampling = sampling;
    desc.render.spp = spp;
    let integrator = penumbra::integrator(&desc, false);
    frames
        .map(|f| {
            let scene = desc.at_frame(f);
            let film = penumbra::render_with(&scene, integrator.as_ref(), RenderControl::default())
                .unwrap()
                .film;
            film.image().iter().map(|p| p.luminance() as f64).collect()
        })
        .collect()
}

/// scenes/glossy-env.toml: two balls under a turning HDR sky.
fn glossy_env() -> SceneDesc {
    let path = repo().join("scenes/glossy-env.toml");
    let file = SourceFile::new(&path, std::fs::read_to_string(&path).unwrap());
    penumbra::scene::formats::native::read(&file).unwrap()
}

/// Mean and standard error of the mean of an image's pixels (independent pixel samples:
/// each pixel's estimate uses its own samples only, with the box filter).
fn mean_and_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// A white diffuse ball under a uniform environment of radiance 1 reflects radiance 1
/// everywhere: every strategy, in each of three frames, within 4 standard errors and 0.5%;
/// `sir` and `smc` also with an odd number of candidates (3: one from the map, two from
/// the BSDF), whose mixture density must follow that split (an even split's density
/// would make them 13% bright here).
#[test]
fn every_strategy_passes_the_white_furnace() {
    let text = "[render]\nwidth = 16\nheight = 16\nfilter = { type = \"box\" }\n\
        [camera]\nposition = [0, 0, 2.2]\ntarget = [0, 0, 0]\nfov = 25\n\
        [environment]\nradiance = 1\nspin = 10\n\
        [[material]]\nname = \"white\"\ntype = \"diffuse\"\nreflectance = 1\n\
        [[shape]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"white\"\n";
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("furnace.toml", text.to_string())).unwrap();
    let mut odd = desc.clone();
    odd.render.env.candidates = 3;
    let runs = ALL
        .iter()
        .map(|&s| (s, &desc))
        .chain([(EnvSampling::Sir, &odd), (EnvSampling::Smc, &odd)]);
    for (sampling, desc) in runs {
        for (f, image) in frames(desc, sampling, 8, 0..3).iter().enumerate() {
            let (mean, se) = mean_and_se(image);
            let m = desc.render.env.candidates;
            println!("{sampling:?} (M = {m}) frame {f}: {mean:.5} ± {se:.5}");
            assert!(
                (mean - 1.0).abs() < 4.0 * se + 1e-4 && (mean - 1.0).abs() < 0.005,
                "{sampling:?} (M = {m}) frame {f}: {mean} ± {se}"
            );
        }
    }
}

/// Under the turning HDR sky of scenes/glossy-env.toml (a sun, two bright panels, a glossy
/// and a rough metal ball), every strategy's image mean matches a 256-spp `mis` reference
/// in each of four frames. Pixels differ from each other by the image, not by noise, so
/// the standard error is that of the per-pixel differences (each pixel's two estimates
/// share an expectation): within 4 of them for the unbiased
/// strategies (light, bsdf, mis, sir), and within 4 standard errors plus 2% for `smc`,
/// which is biased after its first frame (its particles, carried from frame to frame and
/// moved by a few Metropolis steps, lag the turning sky a little: about 1% measured).
#[test]
fn strategies_agree_under_a_turning_sky() {
    let mut desc = glossy_env();
    (desc.render.width, desc.render.height) = (40, 30);
    let reference = frames(&desc, EnvSampling::Mis, 256, 0..4);
    for sampling in ALL {
        let images = frames(&desc, sampling, 16, 0..4);
        for (f, (image, reference)) in images.iter().zip(&reference).enumerate() {
            let difference: Vec<f64> = image.iter().zip(reference).map(|(a, b)| a - b).collect();
            let (d, se) = mean_and_se(&difference);
            let (expected, _) = mean_and_se(reference);
            let mean = expected + d;
            let slack = if sampling == EnvSampling::Smc {
                0.02 * expected
            } else {
                0.0
            };
            println!("{sampling:?} frame {f}: {mean:.5} ± {se:.5} (reference {expected:.5})");
            assert!(
                (mean - expected).abs() < 4.0 * se + slack,
                "{sampling:?} frame {f}: {mean} ± {se}, reference {expected}"
            );
        }
    }
}

/// smc's first frame is unbiased (resampling gives (Z, particle) pairs with E[Z h] = ∫ p h
/// for any h, and Metropolis moves that leave p invariant keep that; the moves' own
/// chi-square test is in env/smc.rs): the image mean of the glossy scene's first frame
/// matches 256-spp `mis` within 4 standard errors of the per-pixel differences, without
/// the slack the later frames need.
#[test]
fn smc_first_frame_is_unbiased() {
    let mut desc = glossy_env();
    (desc.render.width, desc.render.height) = (40, 30);
    let reference = frames(&desc, EnvSampling::Mis, 256, 0..1).remove(0);
    let image = frames(&desc, EnvSampling::Smc, 16, 0..1).remove(0);
    let difference: Vec<f64> = image.iter().zip(&reference).map(|(a, b)| a - b).collect();
    let (d, se) = mean_and_se(&difference);
    let (expected, _) = mean_and_se(&reference);
    println!(
        "smc, first frame: {:.5} ± {se:.5} (reference {expected:.5})",
        expected + d
    );
    assert!(
        d.abs() < 4.0 * se,
        "smc, first frame: {} ± {se}, reference {expected}",
        expected + d
    );
}

/// `--frames 2..4` writes OUTPUT_0002 and OUTPUT_0003 (and not 0004), each a different
/// image (the sky turns); bad ranges are refused.
#[test]
fn frames_write_numbered_images() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/glossy-env.toml");
    let scene = scene.to_str().unwrap();
    let out = penumbra(
        dir.path(),
        &[
            "render",
            scene,
            "--res",
            "24x18",
            "--spp",
            "2",
            "--frames",
            "2..4",
            "--env-sampling",
            "smc",
            "-o",
            "a.exr",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (a, b) = (dir.path().join("a_0002.exr"), dir.path().join("a_0003.exr"));
    assert!(a.exists() && b.exists() && !dir.path().join("a_0004.exr").exists());
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert!(
        text(&out.stderr).contains("smc: render 2 with these particles"),
        "{}",
        text(&out.stderr)
    );
    let bad = penumbra(dir.path(), &["render", scene, "--frames", "4..2"]);
    assert!(!bad.status.success());
    assert!(text(&bad.stderr).contains("holds no frames"), "{}", text(&bad.stderr));
}

/// `smc` keeps particles for only as many passes as fit in `--smc-memory`: at 128×96 and
/// 4 particles a pass's particles take 0.94 MiB, so 1 MiB keeps the first of 4 passes, and
/// in the second frame the other three quarters of the pixel samples start afresh (with
/// 512 MiB none do); 0 MiB keeps none.
#[test]
fn smc_particles_stay_within_their_memory() {
    let mut desc = glossy_env();
    desc.render.integrator = IntegratorKind::Env;
    desc.render.env.sampling = EnvSampling::Smc;
    (desc.render.width, desc.render.height, desc.render.spp) = (128, 96, 4);
    for (mib, kept) in [(512, 4u64), (1, 1), (0, 0)] {
        desc.render.env.memory_mib = mib;
        let integrator = penumbra::integrator(&desc, false);
        for f in 0..2 {
            penumbra::render_with(&desc.at_frame(f), integrator.as_ref(), RenderControl::default()).unwrap();
        }
        let report = integrator.report().join("\n");
        // "... accepted; F of T pixel samples started afresh"
        let counts: Vec<u64> = report
            .split("accepted; ")
            .nth(1)
            .and_then(|r| r.split(" pixel samples").next())
            .map(|r| r.split(" of ").map(|n| n.parse().unwrap()).collect())
            .unwrap_or_default();
        let (fresh, total) = (counts[0], counts[1]);
        let expected = total * (4 - kept) / 4;
        println!("{mib} MiB: {fresh} of {total} afresh (expected about {expected})");
        assert!(fresh.abs_diff(expected) <= total / 50, "{mib} MiB: {report}");
        assert_eq!(
            report.contains(&format!("particles of {kept} of 4 passes")),
            kept < 4,
            "{report}"
        );
    }
}
