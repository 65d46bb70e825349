//! The figures and numbers of `docs/direct-lighting.md`: each direct-lighting strategy
//! rendered with a given number of samples, and its error against a converged reference of
//! the same scene. Every pixel is shaded at its centre (one camera ray, no antialiasing), so
//! that all the noise is the light estimator's.
//!
//! `cargo run --release --example direct_lighting [OUT_DIR]` (default `docs/images`) writes
//! `direct-*.png` and prints the tables in Markdown. About a minute on two cores.

use penumbra::math::{Rgb, SamplerKind};
use penumbra::renderer::integrators::{DirectOptions, LightSampling};
use penumbra::renderer::Filter;
use penumbra::scene::image_io::{write_image, Image};
use penumbra::scene::{SceneDesc, SourceFile};
use penumbra::RenderControl;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn load(name: &str) -> SceneDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    let text = std::fs::read_to_string(&path).expect("scene file");
    penumbra::scene::formats::native::read(&SourceFile::new(path, text)).expect("valid scene")
}

struct Frame {
    pixels: Vec<Rgb>,
    width: u32,
    height: u32,
    seconds: f64,
    rays: u64,
}

fn render(desc: &SceneDesc, sampling: LightSampling, light_samples: u32, spp: u32) -> Frame {
    let mut d = desc.clone();
    d.render.direct = DirectOptions {
        sampling,
        light_samples,
        ..d.render.direct
    };
    d.render.spp = spp;
    let start = Instant::now();
    let r = penumbra::render(&d, RenderControl::default()).expect("renders");
    Frame {
        pixels: r.film.image(),
        width: r.film.width,
        height: r.film.height,
        seconds: start.elapsed().as_secs_f64(),
        rays: r.stats.rays.total() - r.stats.rays.camera,
    }
}

/// Relative MSE, mean of (a - r)² / (r² + 0.01) over pixels and channels, and the relative
/// RMS error sqrt(Σ (a - r)² / Σ r²).
fn errors(a: &[Rgb], reference: &[Rgb]) -> (f64, f64) {
    let (mut rel_mse, mut num, mut den) = (0.0, 0.0, 0.0);
    for (p, q) in a.iter().zip(reference) {
        for (x, y) in p.to_array().into_iter().zip(q.to_array()) {
            let (x, y) = (x as f64, y as f64);
            rel_mse += (x - y) * (x - y) / (y * y + 0.01);
            num += (x - y) * (x - y);
            den += y * y;
        }
    }
    (rel_mse / (3 * a.len()) as f64, (num / den).sqrt())
}

fn save(dir: &Path, name: &str, f: &Frame) {
    let path = dir.join(format!("direct-{name}.png"));
    let image = Image {
        width: f.width,
        height: f.height,
        pixels: &f.pixels,
    };
    write_image(&path, &image, 0.0).expect("writes the image");
}

fn table(dir: &Path, desc: &SceneDesc, scene: &str, rows: &[(&str, LightSampling, u32, u32)], reference: &Frame) {
    println!("\n| {scene}: strategy | light samples | rays per pixel | relative MSE | relative RMS error | time (s) |");
    println!("|---|---|---|---|---|---|");
    for &(name, sampling, n, spp) in rows {
        let f = render(desc, sampling, n, spp);
        let (rel_mse, rms) = errors(&f.pixels, &reference.pixels);
        let rays = f.rays as f64 / (f.width * f.height) as f64;
        let samples = if spp == 1 {
            format!("{n}")
        } else {
            format!("{spp} x {n}")
        };
        println!(
            "| {name} | {samples} | {rays:.1} | {rel_mse:.3e} | {rms:.3} | {:.2} |",
            f.seconds
        );
        save(dir, &format!("{scene}-{name}"), &f);
    }
}

fn main() {
    let dir: PathBuf = std::env::args()
        .nth(1)
        .map_or_else(|| "docs/images".into(), PathBuf::from);
    std::fs::create_dir_all(&dir).expect("output directory");
    let centred = |mut d: SceneDesc| {
        d.render.filter = Filter::Box { radius: 1e-4 };
        d.render.sampler = SamplerKind::Independent;
        d
    };

    // The box under a square light: the course's three figures, then every strategy with
    // 16 rays per pixel (8 + 8 for MIS).
    let boxed = centred(load("box-light.toml"));
    let reference = render(&boxed, LightSampling::Stratified, 4096, 1);
    save(&dir, "box-reference", &reference);
    println!(
        "box reference: stratified, 4096 light samples, {:.1} s",
        reference.seconds
    );
    table(
        &dir,
        &boxed,
        "box",
        &[
            ("grid-2x2", LightSampling::Grid, 4, 1),
            ("uniform-1", LightSampling::Uniform, 1, 1),
            ("uniform-64", LightSampling::Uniform, 64, 1),
            ("grid-8x8", LightSampling::Grid, 64, 1),
            ("bsdf-16", LightSampling::Bsdf, 16, 1),
            ("uniform-16", LightSampling::Uniform, 16, 1),
            ("stratified-16", LightSampling::Stratified, 16, 1),
            ("solid-angle-16", LightSampling::SolidAngle, 16, 1),
            ("mis-8", LightSampling::Mis, 8, 1),
        ],
        &reference,
    );

    // Veach's plates: one sample of each strategy per light, as in his figure.
    let mut veach = centred(load("veach-mis.toml"));
    veach.render.width = 384;
    veach.render.height = 256;
    let reference = render(&veach, LightSampling::Mis, 256, 1);
    save(&dir, "veach-reference", &reference);
    println!(
        "\nveach reference: mis, 256 light and 256 BSDF samples, {:.1} s",
        reference.seconds
    );
    table(
        &dir,
        &veach,
        "veach",
        &[
            ("solid-angle", LightSampling::SolidAngle, 4, 1),
            ("bsdf", LightSampling::Bsdf, 4, 1),
            ("mis", LightSampling::Mis, 4, 1),
            ("bsdf-24", LightSampling::Bsdf, 24, 1),
            ("solid-angle-5", LightSampling::SolidAngle, 5, 1),
        ],
        &reference,
    );
}
