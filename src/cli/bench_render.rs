//! `penumbra bench render SCENE`: rendering speed (samples/s, rays/s, rays per sample), best
//! and median of repeats, and with `--mitsuba` Mitsuba 3's speed on its Cornell box measured
//! in the same command, as a ratio (../shared/anchors/run.sh setup must have been run).

use super::Failure;
use clap::Args;
use penumbra::math::{Rgb, SamplerKind};
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
    /// ../shared/anchors, in its vectorised (llvm_ad_rgb; one render after each of ours,
    /// for paired ratios) and its scalar (scalar_rgb) variant, and print our speed
    /// relative to each.
    #[arg(long)]
    pub mitsuba: bool,
    /// Sampler for our renders (overrides the scene's): sobol, stratified, halton, independent.
    #[arg(long)]
    pub sampler: Option<String>,
    /// Path depth from which `path` plays Russian roulette (default: the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=penumbra::renderer::integrators::MAX_DEPTH_LIMIT as i64))]
    pub rr_depth: Option<u32>,
    /// A reference image (.exr, .pfm): print our render's relative MSE against it and, with
    /// --mitsuba, the time each renderer needs for the same error.
    #[arg(long = "ref", value_name = "R")]
    pub reference: Option<PathBuf>,
}

/// What one Mitsuba run reported.
struct MitsubaRun {
    samples_per_s: f64,
    /// Best wall time of the timed renders, seconds.
    wall: f64,
    rel_mse: Option<f64>,
}

pub fn run(args: RenderBenchArgs) -> Result<(), Failure> {
    let bad = |m: String| Failure::BadInput(miette::miette!("{m}"));
    if let Some(d) = args
        .rr_depth
        .filter(|&d| args.mitsuba && d != penumbra::renderer::integrators::RR_DEPTH)
    {
        return Err(bad(format!(
            "--rr-depth {d} with --mitsuba: Mitsuba's box is rendered with its rr_depth of {}, so the two would not be comparable",
            penumbra::renderer::integrators::RR_DEPTH
        )));
    }
    let mut desc = penumbra::scene::read_scene(&args.scene).map_err(|e| Failure::BadInput(e.into()))?;
    desc.render.spp = args.spp;
    if let Some(d) = args.rr_depth {
        desc.render.rr_depth = d;
    }
    if let Some(name) = &args.sampler {
        desc.render.sampler = SamplerKind::from_name(name).ok_or_else(|| {
            bad(format!(
                "unknown sampler {name:?} (expected one of {})",
                SamplerKind::NAMES.join(", ")
            ))
        })?;
    }
    println!("sampler: {:?}", desc.render.sampler);
    let reference = match &args.reference {
        Some(path) => Some(
            penumbra::scene::image_io::read_image(path)
                .map_err(|e| bad(format!("cannot read {}: {e}", path.display())))?,
        ),
        None => None,
    };
    let threads = args.threads.unwrap_or(0) as usize;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Failure::Internal(format!("cannot start worker threads: {e}")))?;
    let mut times = Vec::new();
    let mut rays_per_sample = 0.0;
    let mut image = Vec::new();
    let samples = desc.render.width as f64 * desc.render.height as f64 * args.spp as f64;
    // With --mitsuba, each of our renders is followed by one of Mitsuba's vectorised
    // variant, so that the two are timed in the same stretch of a shared machine's load and
    // each pair gives a ratio of its own.
    let mut llvm_rounds = Vec::new();
    for _ in 0..args.repeats {
        let (seconds, film, rays) = render_once(&pool, &desc)?;
        times.push(seconds);
        rays_per_sample = rays / samples;
        image = film;
        if args.mitsuba {
            llvm_rounds.push(mitsuba("llvm_ad_rgb", args.spp, 1, pool.current_num_threads()).map_err(bad)?);
        }
    }
    let mut paired: Vec<f64> = times
        .iter()
        .zip(&llvm_rounds)
        .map(|(t, m)| samples / t / m.samples_per_s)
        .collect();
    paired.sort_by(f64::total_cmp);
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
    let our_error = match &reference {
        Some(r) if r.pixels.len() == image.len() => {
            let e = penumbra::metrics::compare(&image, &r.pixels).rel_mse;
            println!("penumbra relMSE against the reference: {e:.4e}");
            Some(e)
        }
        Some(r) => {
            return Err(bad(format!(
                "the reference is {}x{}, the render {}x{}",
                r.width, r.height, desc.render.width, desc.render.height
            )))
        }
        None => None,
    };
    if args.mitsuba {
        for variant in ["llvm_ad_rgb", "scalar_rgb"] {
            let theirs = match variant {
                "llvm_ad_rgb" => best_of(&llvm_rounds),
                _ => mitsuba(variant, args.spp, args.repeats, pool.current_num_threads()).map_err(bad)?,
            };
            println!(
                "mitsuba {variant} (Cornell box, 256x256, max depth 8): {:.3} Msamples/s best; penumbra / mitsuba = {:.2}",
                theirs.samples_per_s * 1e-6,
                ours / theirs.samples_per_s
            );
            if variant == "llvm_ad_rgb" {
                println!(
                    "  {} rounds of one render each, ours then Mitsuba's: ratios min/median {:.2}/{:.2}",
                    paired.len(),
                    paired[0],
                    paired[paired.len() / 2]
                );
            }
            if let (Some(e), Some(e_theirs), Some(r)) = (our_error, theirs.rel_mse, &reference) {
                // First guess: error falling as 1/spp, so the time to a given error scales
                // with it; then the spp that reaches it, found by rendering (low-discrepancy
                // samplers converge faster than 1/spp, so the guess is off for them).
                let ours_to_theirs = best * e / e_theirs;
                println!(
                    "  to mitsuba's relMSE {e_theirs:.4e} at {} spp ({:.3} s): penumbra needs about {ours_to_theirs:.3} s (our {e:.4e} x {best:.3} s, error taken as 1/spp) = {:.2}x its time",
                    args.spp,
                    theirs.wall,
                    ours_to_theirs / theirs.wall
                );
                let guess = (args.spp as f64 * e / e_theirs).ceil().max(1.0) as u32;
                match spp_for_error(&pool, &desc, &r.pixels, e_theirs, guess)? {
                    Some((n, e_n)) => {
                        let t = n as f64 * desc.render.width as f64 * desc.render.height as f64 / ours;
                        println!(
                            "  measured: our relMSE is {e_n:.4e} at {n} spp, {t:.3} s at our best speed = {:.2}x its time",
                            t / theirs.wall
                        );
                    }
                    None => println!("  measured: not reached by {} spp", 4 * guess),
                }
            }
        }
    }
    Ok(())
}

/// One render of `desc`: wall seconds, the image, rays traced.
fn render_once(pool: &rayon::ThreadPool, desc: &penumbra::scene::SceneDesc) -> Result<(f64, Vec<Rgb>, f64), Failure> {
    let start = Instant::now();
    let result = pool
        .install(|| penumbra::render(desc, penumbra::RenderControl::default()))
        .map_err(|e| Failure::BadInput(e.into()))?;
    Ok((
        start.elapsed().as_secs_f64(),
        result.film.image(),
        result.stats.rays.total() as f64,
    ))
}

/// The fewest samples per pixel, searched from `guess` in steps of about 3%, whose render
/// has a relative MSE against `reference` of at most `target`, and that error; `None` when
/// four times the guess does not reach it. Renders are deterministic, so each error is
/// exact for the seed.
fn spp_for_error(
    pool: &rayon::ThreadPool,
    desc: &penumbra::scene::SceneDesc,
    reference: &[Rgb],
    target: f64,
    guess: u32,
) -> Result<Option<(u32, f64)>, Failure> {
    let error = |spp: u32| -> Result<f64, Failure> {
        let mut d = desc.clone();
        d.render.spp = spp;
        let (_, image, _) = render_once(pool, &d)?;
        Ok(penumbra::metrics::compare(&image, reference).rel_mse)
    };
    let step = (guess / 32).max(1);
    let (mut n, mut e) = (guess, error(guess)?);
    if e > target {
        // Up until the target is reached: the spp before it missed, so that is the answer.
        while e > target {
            if n >= 4 * guess {
                return Ok(None);
            }
            n += step;
            e = error(n)?;
        }
        return Ok(Some((n, e)));
    }
    // The guess reaches it: down while fewer samples still do.
    while n > step {
        let e_less = error(n - step)?;
        if e_less > target {
            break;
        }
        (n, e) = (n - step, e_less);
    }
    Ok(Some((n, e)))
}

/// The best speed and wall time of several single-render runs (`runs` is not empty).
fn best_of(runs: &[MitsubaRun]) -> MitsubaRun {
    MitsubaRun {
        samples_per_s: runs.iter().map(|r| r.samples_per_s).fold(0.0, f64::max),
        wall: runs.iter().map(|r| r.wall).fold(f64::INFINITY, f64::min),
        rel_mse: runs[0].rel_mse,
    }
}

/// Mitsuba's best samples per second, best wall time and relative MSE on its Cornell box in
/// `variant`, from the anchors' script.
fn mitsuba(variant: &str, spp: u32, repeats: u32, threads: usize) -> Result<MitsubaRun, String> {
    let anchors = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/anchors");
    // Where ../shared/anchors/run.sh puts its virtual environment.
    let venv = std::env::var_os("ANCHORS_VENV").map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(std::env::var("HOME").unwrap_or_default()).join(".cache/penumbra-anchors/venv")
    });
    let python = venv.join("bin/python");
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
    // "llvm_ad_rgb  thr=2 spp=   64 wall min/med = 1.361/1.364s (load 8.6 ms) -> 3.081 Msamples/s best, relMSE=0.00133"
    let number = |line: &str, after: &str, end: char| -> Option<f64> {
        line.split(after).nth(1)?.split(end).next()?.trim().parse().ok()
    };
    text.lines()
        .find_map(|l| {
            Some(MitsubaRun {
                samples_per_s: number(l, "-> ", ' ')? * 1e6,
                wall: number(l, "min/med = ", '/')?,
                rel_mse: number(l, "relMSE=", ' '),
            })
        })
        .ok_or_else(|| {
            format!(
                "no speed in Mitsuba's output:\n{text}{}",
                String::from_utf8_lossy(&out.stderr)
            )
        })
}
