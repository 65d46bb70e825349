//! `penumbra render`: read, override, render, write.

use super::progress::Reporter;
use super::{Failure, RenderArgs};
use penumbra::geometry::AccelKind;
use penumbra::math::SamplerKind;
use penumbra::renderer::driver::Stop;
use penumbra::renderer::film::AOV_NAMES;
use penumbra::renderer::integrators::{EnvSampling, IntegratorKind, LightSampling, MisHeuristic};
use penumbra::renderer::lights::LightSelection;
use penumbra::renderer::Film;
use penumbra::scene::image_io::{write_exr_layers, write_image, Image, ImageFormat};
use penumbra::scene::SceneDesc;
use penumbra::state::{read_state, state_path, write_state};
use penumbra::RenderControl;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

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
    if let Some(k) = args.camera {
        match desc.cameras.get(k) {
            Some(choice) => {
                desc.camera = choice.camera.clone();
                (desc.render.width, desc.render.height) = (choice.width, choice.height);
            }
            None if k == 0 => {}
            None => {
                let n = desc.cameras.len().max(1);
                return Err(bad(format!(
                    "--camera {k}: the scene defines {n} camera{} (0{})",
                    if n == 1 { "" } else { "s" },
                    if n == 1 {
                        String::new()
                    } else {
                        format!(" to {}", n - 1)
                    }
                )));
            }
        }
    }
    let r = &mut desc.render;
    if args.spectral || args.rgb {
        r.spectral = args.spectral;
    }
    if let Some(spp) = args.spp {
        r.spp = spp;
    }
    if let Some(seed) = args.seed {
        r.seed = seed;
    }
    if let Some(d) = args.max_depth {
        r.max_depth = d;
    }
    if let Some(d) = args.rr_depth {
        r.rr_depth = d;
    }
    if let Some(w) = args.min_weight {
        r.min_weight = w;
    }
    let m = &mut r.mlt;
    m.large_step_probability = args.mlt_large_step.unwrap_or(m.large_step_probability);
    m.sigma = args.mlt_sigma.unwrap_or(m.sigma);
    m.chains = args.mlt_chains.unwrap_or(m.chains);
    m.bootstrap = args.mlt_bootstrap.unwrap_or(m.bootstrap);
    m.multiplexed &= !args.mlt_plain;
    let ph = &mut r.photon;
    ph.photons = args.photons.unwrap_or(ph.photons);
    ph.caustic_photons = args.caustic_photons.unwrap_or(ph.caustic_photons);
    ph.radius = args.photon_radius.unwrap_or(ph.radius);
    ph.alpha = args.sppm_alpha.unwrap_or(ph.alpha);
    ph.lookup = args.photon_lookup.unwrap_or(ph.lookup);
    ph.gather = args.gather_rays.unwrap_or(ph.gather);
    ph.check().map_err(|e| bad(format!("--sppm-alpha/--photon-*: {e}")))?;
    if let Some(s) = pick(
        &args.env_sampling,
        "env-sampling",
        &EnvSampling::NAMES,
        EnvSampling::from_name,
    )? {
        r.env.sampling = s;
    }
    r.env.samples = args.env_samples.unwrap_or(r.env.samples);
    r.env.candidates = args.env_candidates.unwrap_or(r.env.candidates);
    r.env.moves = args.smc_moves.unwrap_or(r.env.moves);
    r.env.memory_mib = args.smc_memory.unwrap_or(r.env.memory_mib);
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

/// FNV-1a, 64 bits: a fingerprint that stays the same across builds and platforms.
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// Of the renderer's version, the scene's source, every file it names (textures, maps,
/// meshes: each quoted string that is a file beside the scene) and every setting that
/// shapes the image except the sample count.
fn fingerprint(scene: Option<&std::path::Path>, source: &[u8], desc: &SceneDesc) -> u64 {
    let mut render = desc.render.clone();
    render.spp = 0;
    let c = &desc.camera;
    let settings = format!(
        "{} {render:?} {:?} {} {} {} {}",
        env!("CARGO_PKG_VERSION"),
        c.kind,
        c.position,
        c.target,
        c.up,
        c.mirrored
    );
    let mut h = fnv1a(settings.as_bytes(), fnv1a(source, 0xcbf2_9ce4_8422_2325));
    let dir = scene.and_then(|p| p.parent()).unwrap_or(std::path::Path::new("."));
    let text = String::from_utf8_lossy(source);
    for name in text.split('"').skip(1).step_by(2) {
        let path = dir.join(name);
        if !name.is_empty() && path.is_file() {
            h = fnv1a(&std::fs::read(&path).unwrap_or_default(), fnv1a(name.as_bytes(), h));
        }
    }
    h
}

/// Whether the sampler's samples depend on the planned sample count.
fn count_dependent(sampler: SamplerKind) -> bool {
    matches!(sampler, SamplerKind::Stratified | SamplerKind::Halton)
}

/// Writes the image (with its AOV layers) and, when `state` is given, the render state.
fn write_outputs(args: &RenderArgs, film: &Film, state: Option<(u32, u64)>) -> Result<(), String> {
    let pixels = film.image();
    let image = Image {
        width: film.width,
        height: film.height,
        pixels: &pixels,
    };
    let written = match film.aov_images() {
        Some(aovs) => {
            let extra: Vec<(&str, Vec<f32>)> = AOV_NAMES.iter().copied().zip(aovs).collect();
            write_exr_layers(&args.output, &image, &extra)
        }
        None => write_image(&args.output, &image, args.exposure),
    };
    written.map_err(|e| format!("cannot write {}: {e}", args.output.display()))?;
    for (path, pixels) in strategy_images(&args.output, film) {
        let image = Image {
            width: film.width,
            height: film.height,
            pixels: &pixels,
        };
        write_image(&path, &image, 0.0).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    if let Some((planned, print)) = state {
        let path = state_path(&args.output);
        write_state(&path, film, planned, print).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(())
}

/// The files of `--debug-strategies` beside `output`, with their images.
fn strategy_images(output: &std::path::Path, film: &Film) -> Vec<(std::path::PathBuf, Vec<penumbra::math::Rgb>)> {
    let stem = output.file_stem().map_or("render".into(), |s| s.to_string_lossy());
    film.layer_images()
        .into_iter()
        .map(|(layer, pixels)| {
            let (code, weighted) = ((layer - 1) / 2, (layer - 1) % 2 == 1);
            let (s, t) = (code / 256, code % 256);
            let name = format!(
                "{stem}_d{}_s{s}_t{t}{}.exr",
                s + t - 1,
                if weighted { "" } else { "_unweighted" }
            );
            (output.with_file_name(name), pixels)
        })
        .collect()
}

pub fn run(args: RenderArgs) -> Result<(), Failure> {
    let format = ImageFormat::from_path(&args.output);
    if format.is_none() {
        return Err(bad(format!(
            "cannot write {}: unknown image format; use one of the extensions .{}",
            args.output.display(),
            ImageFormat::EXTENSIONS.join(", .")
        )));
    }
    if args.aovs && format != Some(ImageFormat::Exr) {
        return Err(bad(format!(
            "--aovs: AOVs are written as layers of an OpenEXR image; {} is not .exr",
            args.output.display()
        )));
    }
    let (mut desc, source) = match &args.scene {
        Some(path) => {
            let desc = penumbra::scene::read_scene_with(path, &args.define).map_err(|e| Failure::BadInput(e.into()))?;
            let source = std::fs::read(path).unwrap_or_default();
            (desc, source)
        }
        None if !args.define.is_empty() => {
            return Err(bad(
                "-D sets parameters of a Mitsuba (.xml) scene; no scene file was given".to_string(),
            ))
        }
        None => (
            penumbra::default_scene(),
            penumbra::DEFAULT_SCENE_TOML.as_bytes().to_vec(),
        ),
    };
    apply_overrides(&mut desc, &args)?;
    if args.frames.is_some() {
        for (given, what) in [
            (args.resume, "--resume"),
            (args.checkpoint.is_some(), "--checkpoint"),
            (args.aovs, "--aovs"),
            (args.debug_strategies, "--debug-strategies"),
        ] {
            if given {
                return Err(bad(format!(
                    "{what} is not supported with --frames (each frame is rendered afresh)"
                )));
            }
        }
    }
    // What the integrator supports, as it declares it.
    let integrator = penumbra::integrator(&desc, args.debug_strategies);
    let caps = integrator.capabilities();
    let name = IntegratorKind::NAMES[desc.render.integrator as usize];
    if let Some(kept) = caps.state {
        if args.resume {
            return Err(bad(format!(
                "--resume: {name}'s {kept} are not kept in the state; render afresh (--time still stops a render when asked)",
            )));
        }
    }
    if args.aovs && !caps.pixel_samples {
        return Err(bad(format!(
            "--aovs: {name} does not estimate pixels by samples of their own; use another integrator for the AOVs",
        )));
    }
    if args.debug_strategies {
        if !caps.strategy_images {
            return Err(bad(format!(
                "--debug-strategies shows the strategies of `bdpt`, and {name} keeps none: add --integrator bdpt"
            )));
        }
        if args.resume {
            return Err(bad(
                "--debug-strategies cannot be resumed: its images are not kept in the state; render afresh",
            ));
        }
        if matches!(desc.camera.kind, penumbra::scene::desc::CameraKind::Orthographic { .. }) {
            return Err(bad(
                "--debug-strategies needs a perspective camera: light paths cannot reach an orthographic one",
            ));
        }
    }
    if matches!(desc.render.integrator, IntegratorKind::Sppm | IntegratorKind::Photon)
        && desc.environment.is_none()
        && !desc.background.is_black()
    {
        eprintln!(
            "warning: the background colour is not a light: {} sends no photons from it, so it lights surfaces directly only (give an [environment] instead to light the scene with it)",
            IntegratorKind::NAMES[desc.render.integrator as usize]
        );
    }
    if let (Some(why), Some(_)) = (caps.own_numbers, &args.sampler) {
        eprintln!("warning: --sampler does not apply: {why}");
    }
    if desc.render.integrator == IntegratorKind::Env && desc.environment.is_none() {
        eprintln!("warning: `env` lights surfaces by the environment only, and the scene has no [environment]: only emitters seen directly will show");
    }
    if desc.render.spectral && !caps.spectral {
        eprintln!(
            "warning: {} renders in RGB: spectral rendering is done by path and volpath",
            IntegratorKind::NAMES[desc.render.integrator as usize]
        );
    }
    if !desc.media.is_empty() && caps.media {
        let list: Vec<String> = desc
            .media
            .iter()
            .map(|m| format!("`{}` {}", m.name, m.medium.summary()))
            .collect();
        eprintln!("media: {}", list.join("; "));
    }
    if !desc.media.is_empty() && !caps.media {
        eprintln!(
            "warning: {} renders the scene's participating media as vacuum; `--integrator volpath` renders them",
            IntegratorKind::NAMES[desc.render.integrator as usize]
        );
    }
    for warning in &desc.warnings {
        eprintln!("warning: {warning}");
    }
    // Parameters set with -D change the scene as much as its text does.
    let mut source = source;
    source.extend(format!("{:?}", args.define).bytes());
    let print = fingerprint(args.scene.as_deref(), &source, &desc);
    let state_file = state_path(&args.output);

    // A saved render to continue.
    let resume = if args.resume {
        let saved =
            read_state(&state_file).map_err(|e| bad(format!("--resume: cannot read {}: {e}", state_file.display())))?;
        if saved.fingerprint != print {
            return Err(bad(format!(
                "--resume: {} was rendered from another scene or with other settings; render afresh without --resume",
                state_file.display()
            )));
        }
        match args.spp {
            None => desc.render.spp = saved.planned_spp,
            Some(spp) if spp != saved.planned_spp && count_dependent(desc.render.sampler) => {
                return Err(bad(format!(
                    "--resume: the {} sampler's samples depend on the sample count, planned as {}; resume with --spp {} or use the independent or sobol sampler",
                    SamplerKind::NAMES[desc.render.sampler as usize],
                    saved.planned_spp,
                    saved.planned_spp
                )))
            }
            Some(_) => {}
        }
        Some(saved.film)
    } else {
        None
    };
    let done = resume.as_ref().map_or(0, |f| f.samples_per_pixel);

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        let quiet = args.quiet;
        // A second interrupt ends the process at once.
        let _ = ctrlc::set_handler(move || {
            if cancel.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
            if !quiet {
                eprintln!(
                    "\ninterrupted: finishing the pass in flight and writing what is done (Ctrl-C again to abort)"
                );
            }
        });
    }

    if let Some(frames) = args.frames {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(args.threads.map_or(0, |t| t as usize))
            .build()
            .map_err(|e| Failure::Internal(format!("cannot start worker threads: {e}")))?;
        let time = args.time.map(Duration::from_secs_f32);
        return super::frames::run(
            &desc,
            frames,
            &args.output,
            args.exposure,
            time,
            args.quiet,
            &pool,
            &cancel,
        );
    }
    let r = &desc.render;
    let pixels = r.width as u64 * r.height as u64;
    let reporter = Reporter::new(pixels * r.spp.saturating_sub(done) as u64, args.quiet);
    let threads = args.threads.map_or(0, |t| t as usize);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Failure::Internal(format!("cannot start worker threads: {e}")))?;
    let planned = r.spp;
    // An integrator with state of its own (chains, photon statistics, particles) leaves
    // none: its film alone cannot continue the render.
    let resumable = caps.state.is_none();
    let keep_state = resumable && (args.checkpoint.is_some() || args.resume);
    // Checkpoints: the image and the state, every `--checkpoint` seconds.
    let last_checkpoint = Mutex::new(Instant::now());
    let checkpoint = |film: &Film| {
        let Some(every) = args.checkpoint else { return };
        let mut last = last_checkpoint.lock().unwrap_or_else(|e| e.into_inner());
        if last.elapsed().as_secs_f32() < every {
            return;
        }
        if let Err(e) = write_outputs(&args, film, resumable.then_some((planned, print))) {
            eprintln!("warning: checkpoint: {e}");
        }
        *last = Instant::now();
    };
    let control = RenderControl {
        progress: &reporter,
        cancel: &cancel,
        time_limit: args.time.map(Duration::from_secs_f32),
        aovs: args.aovs,
        resume,
        after_pass: Some(&checkpoint),
        debug_strategies: args.debug_strategies,
    };
    let result = pool
        .install(|| penumbra::render_with(&desc, integrator.as_ref(), control))
        .map_err(|e| Failure::BadInput(e.into()))?;
    reporter.finish();

    let film = &result.film;
    let s = &result.stats;
    // The state is kept when asked for, or when the render stopped short of its samples.
    let keep_state = resumable && (keep_state || s.stop != Stop::Done);
    write_outputs(&args, film, keep_state.then_some((planned, print))).map_err(Failure::Internal)?;
    if !keep_state && state_file.exists() {
        // A finished render leaves no stale state behind.
        let _ = std::fs::remove_file(&state_file);
    }

    let secs = s.elapsed.as_secs_f64().max(1e-9);
    if !args.quiet {
        eprintln!(
            "rendered {}x{} at {} spp in {:.2} s: {:.2} Msamples/s, {:.2} Mrays/s ({} camera, {} secondary, {} shadow rays; {} kernels){}",
            film.width,
            film.height,
            film.samples_per_pixel,
            secs,
            s.samples as f64 / secs * 1e-6,
            s.rays.total() as f64 / secs * 1e-6,
            s.rays.camera,
            s.rays.secondary,
            s.rays.shadow,
            penumbra::math::simd::level(),
            if film.rejected > 0 { format!(", {} NaN/Inf samples rejected", film.rejected) } else { String::new() }
        );
        for note in &s.notes {
            eprintln!("{note}");
        }
        match s.stop {
            Stop::Done if args.time.is_some() => eprintln!(
                "reached {} spp before the time budget; raise --spp to use the rest",
                film.samples_per_pixel
            ),
            Stop::Done => {}
            Stop::TimeLimit => eprintln!(
                "time budget spent at {} of {} spp; continue with --resume",
                film.samples_per_pixel, planned
            ),
            Stop::Cancelled => eprintln!(
                "interrupted at {} of {} spp; the image has every sample taken, and --resume continues it",
                film.samples_per_pixel, planned
            ),
        }
    }
    println!("wrote {}", args.output.display());
    for (path, _) in strategy_images(&args.output, film) {
        println!("wrote {}", path.display());
    }
    if keep_state {
        println!("wrote {}", state_file.display());
    }
    Ok(())
}
