//! `penumbra bench render SCENE`: rendering speed (samples/s, rays/s, rays per sample), best
//! and median of repeats, and with `--mitsuba` Mitsuba 3's speed on its Cornell box measured
//! in the same command, as a ratio (../shared/anchors/run.sh setup must have been run).

use super::Failure;
use clap::Args;
use penumbra::math::SamplerKind;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct RenderBenchArgs {
    /// Scene file (.toml).
    pub scene: PathBuf,
    /// Samples per pixel of each timed render.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: u32,
    /// Timed renders; best and median are reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeats: u32,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Also run Mitsuba 3 on its Cornell box with the same spp, repeats and threads, through
    /// ../shared/anchors, in its vectorised (llvm_ad_rgb) and its scalar (scalar_rgb)
    /// variant, and print our speed relative to each.
    #[arg(long)]
    pub mitsuba: bool,
}

pub fn run(args: RenderBenchArgs) -> Result<(), Failure> {
    let bad = |m: String| Failure::BadInput(miette::miette!("{m}"));
    let mut desc = penumbra::scene::read_scene(&args.scene).map_err(|e| Failure::BadInput(e.into()))?;
    desc.render.spp = args.spp;
    if desc.render.sampler != SamplerKind::Independent {
        eprintln!("note: the scene uses the {:?} sampler", desc.render.sampler);
    }
    let threads = args.threads.unwrap_or(0) as usize;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Failure::Internal(format!("cannot start worker threads: {e}")))?;
    let mut times = Vec::new();
    let mut rays_per_sample = 0.0;
    let samples = desc.render.width as f64 * desc.render.height as f64 * args.spp as f64;
    for _ in 0..args.repeats {
        let start = Instant::now();
        let result = pool
            .install(|| penumbra::render(&desc, penumbra::RenderControl::default()))
            .map_err(|e| Failure::BadInput(e.into()))?;
        times.push(start.elapsed().as_secs_f64());
        rays_per_sample = result.stats.rays.total() as f64 / samples;
    }
    times.sort_by(f64::total_cmp);
    let (best, median) = (times[0], times[times.len() / 2]);
    let ours = samples / best;
    println!(
        "penumbra {}: {}x{} at {} spp, {} threads: wall best/median {best:.3}/{median:.3} s -> {:.3} Msamples/s best ({:.3} median), {:.2} Mrays/s, {rays_per_sample:.2} rays per sample",
        args.scene.display(),
        desc.render.width,
        desc.render.height,
        args.spp,
        pool.current_num_threads(),
        ours * 1e-6,
        samples / median * 1e-6,
        ours * rays_per_sample * 1e-6,
    );
    if args.mitsuba {
        for variant in ["llvm_ad_rgb", "scalar_rgb"] {
            let theirs = mitsuba(variant, args.spp, args.repeats, pool.current_num_threads()).map_err(bad)?;
            println!(
                "mitsuba {variant} (Cornell box, 256x256, max depth 8): {:.3} Msamples/s best; penumbra / mitsuba = {:.2}",
                theirs * 1e-6,
                ours / theirs
            );
        }
    }
    Ok(())
}

/// Mitsuba's best samples per second on its Cornell box in `variant`, from the anchors' script.
fn mitsuba(variant: &str, spp: u32, repeats: u32, threads: usize) -> Result<f64, String> {
    let anchors = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/anchors");
    let home = std::env::var("HOME").unwrap_or_default();
    let python = PathBuf::from(home).join(".cache/penumbra-anchors/venv/bin/python");
    if !python.exists() {
        return Err(format!(
            "--mitsuba needs the anchors: run {}/run.sh setup once",
            anchors.display()
        ));
    }
    let out = Command::new(&python)
        .arg(anchors.join("mitsuba_cbox.py"))
        .args(["bench", "--variant", variant, "--spps", &spp.to_string()])
        .args(["--repeats", &repeats.to_string(), "--threads", &threads.to_string()])
        .output()
        .map_err(|e| format!("cannot run Mitsuba through {}: {e}", python.display()))?;
    let text = String::from_utf8_lossy(&out.stdout);
    // "... -> 4.912 Msamples/s best, relMSE=..."
    text.lines()
        .find_map(|l| l.split("-> ").nth(1)?.split(' ').next()?.parse::<f64>().ok())
        .map(|m| m * 1e6)
        .ok_or_else(|| {
            format!(
                "no speed in Mitsuba's output:\n{text}{}",
                String::from_utf8_lossy(&out.stderr)
            )
        })
}
