//! `penumbra render`: read, override, render, write.

use super::progress::Reporter;
use super::{Failure, RenderArgs};
use penumbra::geometry::AccelKind;
use penumbra::math::SamplerKind;
use penumbra::renderer::integrators::{IntegratorKind, LightSampling, MisHeuristic};
use penumbra::renderer::lights::LightSelection;
use penumbra::scene::image_io::{write_image, Image, ImageFormat};
use penumbra::scene::SceneDesc;
use penumbra::RenderControl;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

fn bad(message: impl Into<String>) -> Failure {
    Failure::BadInput(miette::miette!("{}", message.into()))
}

/// A named choice given on the command line.
fn pick<T>(
    value: &Option<String>,
    flag: &str,
    names: &[&str],
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Option<T>, Failure> {
    value
        .as_deref()
        .map(|v| {
            parse(v).ok_or_else(|| {
                bad(format!(
                    "--{flag}: unknown value `{v}`; expected one of: {}",
                    names.join(", ")
                ))
            })
        })
        .transpose()
}

fn apply_overrides(desc: &mut SceneDesc, args: &RenderArgs) -> Result<(), Failure> {
    let r = &mut desc.render;
    if let Some(spp) = args.spp {
        r.spp = spp;
    }
    if let Some(seed) = args.seed {
        r.seed = seed;
    }
    if let Some(d) = args.max_depth {
        r.max_depth = d;
    }
    if let Some(w) = args.min_weight {
        r.min_weight = w;
    }
    if let Some((w, h)) = args.res {
        r.width = w;
        r.height = h;
    }
    if let Some(k) = pick(
        &args.integrator,
        "integrator",
        &IntegratorKind::NAMES,
        IntegratorKind::from_name,
    )? {
        r.integrator = k;
    }
    if let Some(k) = pick(&args.accel, "accel", &AccelKind::NAMES, AccelKind::from_name)? {
        r.accel = k;
    }
    if let Some(k) = pick(&args.sampler, "sampler", &SamplerKind::NAMES, SamplerKind::from_name)? {
        r.sampler = k;
    }
    let d = &mut r.direct;
    if let Some(k) = pick(
        &args.light_sampling,
        "light-sampling",
        &LightSampling::NAMES,
        LightSampling::from_name,
    )? {
        d.sampling = k;
    }
    if let Some(n) = args.light_samples {
        d.light_samples = n;
    }
    if let Some(k) = pick(
        &args.mis_heuristic,
        "mis-heuristic",
        &MisHeuristic::NAMES,
        MisHeuristic::from_name,
    )? {
        d.heuristic = k;
    }
    if let Some(k) = pick(
        &args.light_selection,
        "light-selection",
        &LightSelection::NAMES,
        LightSelection::from_name,
    )? {
        d.selection = k;
    }
    d.check().map_err(|e| bad(format!("--light-samples: {e}")))?;
    Ok(())
}

pub fn run(args: RenderArgs) -> Result<(), Failure> {
    if ImageFormat::from_path(&args.output).is_none() {
        return Err(bad(format!(
            "cannot write {}: unknown image format; use one of the extensions .{}",
            args.output.display(),
            ImageFormat::EXTENSIONS.join(", .")
        )));
    }
    let mut desc = match &args.scene {
        Some(path) => penumbra::scene::read_scene(path).map_err(|e| Failure::BadInput(e.into()))?,
        None => penumbra::default_scene(),
    };
    apply_overrides(&mut desc, &args)?;
    for warning in &desc.warnings {
        eprintln!("warning: {warning}");
    }

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // A second interrupt ends the process at once.
        let _ = ctrlc::set_handler(move || {
            if cancel.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
            eprintln!("\ninterrupted: finishing the tiles in flight and writing what is done (Ctrl-C again to abort)");
        });
    }

    let r = &desc.render;
    let reporter = Reporter::new(r.width as u64 * r.height as u64, args.quiet);
    let threads = args.threads.map_or(0, |t| t as usize);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Failure::Internal(format!("cannot start worker threads: {e}")))?;
    let control = RenderControl {
        progress: &reporter,
        cancel: &cancel,
    };
    let result = pool
        .install(|| penumbra::render(&desc, &control))
        .map_err(|e| Failure::BadInput(e.into()))?;
    reporter.finish();

    let film = &result.film;
    let pixels = film.image();
    write_image(
        &args.output,
        &Image {
            width: film.width,
            height: film.height,
            pixels: &pixels,
        },
        args.exposure,
    )
    .map_err(|e| Failure::Internal(format!("cannot write {}: {e}", args.output.display())))?;

    let s = &result.stats;
    let secs = s.elapsed.as_secs_f64().max(1e-9);
    if !args.quiet {
        eprintln!(
            "rendered {}x{} at {} spp in {:.2} s: {:.2} Msamples/s, {:.2} Mrays/s ({} camera, {} secondary, {} shadow rays){}",
            film.width,
            film.height,
            r.spp,
            secs,
            s.samples as f64 / secs * 1e-6,
            s.rays.total() as f64 / secs * 1e-6,
            s.rays.camera,
            s.rays.secondary,
            s.rays.shadow,
            if film.rejected > 0 { format!(", {} NaN/Inf samples rejected", film.rejected) } else { String::new() }
        );
    }
    if s.cancelled {
        eprintln!(
            "interrupted: {} of {} pixels rendered; the rest of the image is black",
            film.samples() / r.spp as u64,
            film.width as u64 * film.height as u64
        );
    }
    println!("wrote {}", args.output.display());
    Ok(())
}
