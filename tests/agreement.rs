//! The light-transport integrators (`path`, `bdpt`, `mlt`, `sppm`) converge to the same
//! image: the Cornell box (in the repository), the Veach MIS scene and the Veach
//! bidirectional room (from ../shared, skipped with a note when it is absent), and a scene
//! under an environment map.
//!
//! The threshold comes from the measured noise. Each integrator renders the scene twice
//! with different seeds. For independent unbiased renders X and Y of the same image, the
//! expected relative MSE between them is the sum of their per-pixel relative variances,
//! so the mean of relMSE(a₁, b₁) and relMSE(a₂, b₂) should match the mean of relMSE(a₁, a₂)
//! and relMSE(b₁, b₂); a bias between a and b adds its square to the first only. We assert
//! the cross error below 1.5 times the within error (the factor covers the randomness of
//! the estimates themselves) and print the figures. Path tracing meets the caustics of
//! these scenes as rare, very bright pixels that would make any relative MSE a lottery,
//! so the errors are trimmed: the worst 0.5% of pixels are left out of every figure alike
//! (a bias over more than that still shows).
//!
//! `sppm` is consistent, not unbiased: at a finite radius it blurs the indirect light over
//! its gather discs. The passes are chosen so that this bias stays below the noise the
//! test allows (it shrinks with the radius, as passes add up).

use penumbra::math::{Rgb, SamplerKind};
use penumbra::metrics::compare;
use penumbra::renderer::integrators::IntegratorKind;
use penumbra::renderer::Film;
use penumbra::scene::{SceneDesc, SourceFile};
use penumbra::RenderControl;
use std::path::{Path, PathBuf};

fn render(desc: &SceneDesc, integrator: IntegratorKind, spp: u32, seed: u64) -> Film {
    let mut desc = desc.clone();
    desc.render.integrator = integrator;
    desc.render.spp = spp;
    desc.render.seed = seed;
    penumbra::render(&desc, RenderControl::default()).unwrap().film
}

/// Renders `desc` at `size` with each integrator at its sample count, twice, and checks
/// that they agree as the module's documentation says.
fn agree(name: &str, mut desc: SceneDesc, size: (u32, u32), runs: &[(IntegratorKind, u32)]) {
    (desc.render.width, desc.render.height) = size;
    let images: Vec<[Vec<Rgb>; 2]> = runs
        .iter()
        .enumerate()
        .map(|(k, &(integrator, spp))| [1, 2].map(|seed| render(&desc, integrator, spp, 10 * k as u64 + seed).image()))
        .collect();
    let within: Vec<f64> = images.iter().map(|[x, y]| trimmed_rel_mse(y, x)).collect();
    for (i, &(a, spp_a)) in runs.iter().enumerate() {
        for (j, &(b, spp_b)) in runs.iter().enumerate().skip(i + 1) {
            let cross = [0, 1].map(|k| compare(&images[j][k], &images[i][k]));
            let cross_mean =
                0.5 * (trimmed_rel_mse(&images[j][0], &images[i][0]) + trimmed_rel_mse(&images[j][1], &images[i][1]));
            let noise = 0.5 * (within[i] + within[j]);
            println!(
                "{name}: {a:?} {spp_a} spp vs {b:?} {spp_b} spp: relMSE {cross_mean:.3e} (within: {:.3e}, {:.3e}); mean ratios {:?} {:?}",
                within[i], within[j], cross[0].mean_ratio, cross[1].mean_ratio
            );
            assert!(
                cross_mean < 1.5 * noise,
                "{name}: {a:?} vs {b:?}: relMSE {cross_mean:.3e} against noise {noise:.3e}"
            );
        }
    }
}

/// The relative MSE of `a` against `b` (as `penumbra diff` computes it, per channel
/// (a - b)² / (b² + 0.01)) over the pixels, leaving out the worst 0.5% of them.
fn trimmed_rel_mse(a: &[Rgb], b: &[Rgb]) -> f64 {
    let mut e: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(x, y)| {
            let per = |x: f32, y: f32| {
                let (x, y) = (x as f64, y as f64);
                (x - y) * (x - y) / (y * y + 0.01)
            };
            (per(x.r, y.r) + per(x.g, y.g) + per(x.b, y.b)) / 3.0
        })
        .collect();
    e.sort_by(f64::total_cmp);
    let keep = e.len() - e.len() / 200;
    e[..keep].iter().sum::<f64>() / keep as f64
}

fn shared_scene(relative: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/scenes")
        .join(relative);
    if !path.exists() {
        println!(
            "note: skipping: {} is not there (../shared is not beside the repository)",
            path.display()
        );
        return None;
    }
    Some(path)
}

#[test]
fn integrators_agree_on_the_cornell_box() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cbox-mitsuba.toml");
    let file = SourceFile::new(&path, std::fs::read_to_string(&path).unwrap());
    let desc = penumbra::scene::formats::native::read(&file).unwrap();
    agree(
        "Cornell box",
        desc,
        (64, 64),
        &[
            (IntegratorKind::Path, 256),
            (IntegratorKind::Bdpt, 64),
            (IntegratorKind::Mlt, 1024),
            (IntegratorKind::Sppm, 256),
        ],
    );
}

/// [`agree`] on a scene of ../shared (skipped with a note when it is absent), with
/// `path`, `bdpt`, `mlt` and `sppm` at the given samples (mutations, passes) per pixel.
fn agree_on_shared(name: &str, relative: &str, size: (u32, u32), [path, bdpt, mlt, sppm]: [u32; 4]) {
    let Some(file) = shared_scene(relative) else {
        return;
    };
    let desc = penumbra::scene::read_scene(&file).unwrap();
    let runs = [
        (IntegratorKind::Path, path),
        (IntegratorKind::Bdpt, bdpt),
        (IntegratorKind::Mlt, mlt),
        (IntegratorKind::Sppm, sppm),
    ];
    agree(name, desc, size, &runs);
}

#[test]
fn integrators_agree_on_the_veach_mis_scene() {
    agree_on_shared(
        "Veach MIS",
        "pbrt-veach-mis/scene-v4.pbrt",
        (128, 72),
        [256, 64, 256, 256],
    );
}

#[test]
fn integrators_agree_on_the_veach_bidirectional_room() {
    agree_on_shared(
        "Veach bidir",
        "pbrt-veach-bidir/scene-v4.pbrt",
        (64, 64),
        [512, 64, 512, 512],
    );
}

/// Under an environment map with a small bright spot (a sun) and a blue upper half: a
/// diffuse floor, a plastic and a rough metal ball. Light paths start from the map's own
/// distribution on a disk facing the scene, and camera paths end at infinity. With the
/// independent sampler, so that both of the map's draws meet here: path and bdpt draw its
/// cells by alias tables, mlt and sppm (numbers of their own) by inverting the CDFs
/// (`scene/build.rs`).
#[test]
fn integrators_agree_under_an_environment_map() {
    let dir = tempfile::tempdir().unwrap();
    let (width, height) = (64u32, 32u32);
    let pixels: Vec<Rgb> = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            match (x, y) {
                (20..=23, 5..=7) => Rgb::new(200.0, 180.0, 150.0),
                (_, 0..=15) => Rgb::new(0.4, 0.5, 0.8),
                _ => Rgb::splat(0.3),
            }
        })
        .collect();
    let sky = dir.path().join("sky.pfm");
    let image = penumbra::scene::image_io::Image {
        width,
        height,
        pixels: &pixels,
    };
    penumbra::scene::image_io::write_image(&sky, &image, 0.0).unwrap();
    let text = format!(
        "[render]\nmax_depth = 5\n[camera]\nposition = [0, 1.5, 4]\ntarget = [0, 0.5, 0]\nfov = 45\n\
         [environment]\nfile = \"{}\"\n\
         [[material]]\nname = \"floor\"\ntype = \"diffuse\"\nreflectance = 0.6\n\
         [[material]]\nname = \"glossy\"\ntype = \"plastic\"\ndiffuse = [0.6, 0.3, 0.2]\n\
         [[material]]\nname = \"metal\"\ntype = \"conductor\"\nroughness = 0.2\n\
         [[shape]]\ntype = \"quad\"\ncorner = [-3, 0, 3]\nedge1 = [6, 0, 0]\nedge2 = [0, 0, -6]\nmaterial = \"floor\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [-0.6, 0.5, 0]\nradius = 0.5\nmaterial = \"glossy\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.6, 0.5, 0]\nradius = 0.5\nmaterial = \"metal\"\n",
        sky.display()
    );
    let mut desc = penumbra::scene::formats::native::read(&SourceFile::new("env.toml", text)).unwrap();
    desc.render.sampler = SamplerKind::Independent;
    agree(
        "environment map",
        desc,
        (64, 48),
        &[
            (IntegratorKind::Path, 256),
            (IntegratorKind::Bdpt, 128),
            (IntegratorKind::Mlt, 512),
            (IntegratorKind::Sppm, 256),
        ],
    );
}
