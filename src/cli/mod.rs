//! Command-line arguments and dispatch.

mod bench;
mod bench_render;
mod diff;
mod frames;
mod progress;
mod render;

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Penumbra: a physically based CPU renderer.
///
/// Without a subcommand, works as `penumbra render`: with no arguments at all it renders
/// the built-in default scene (the classic Whitted scene) to render.png in the current
/// directory.
#[derive(Parser, Debug)]
#[command(
    name = "penumbra",
    version,
    about,
    long_about,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    render: RenderArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene file to an image.
    Render(Box<RenderArgs>),
    /// Measure: `penumbra bench accel MESH_OR_SCENE` races the acceleration structures.
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Compare images: `penumbra diff A B [--ref R]` prints RMSE, relative MSE and mean
    /// absolute relative error, and can draw the error.
    Diff(diff::DiffArgs),
}

/// Options of `penumbra render`; each overrides what the scene file says.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file: .toml (the native format), .xml (Mitsuba 3), .pbrt (pbrt-v4), .gltf or
    /// .glb (glTF 2.0), or a bare .obj or .ply mesh (shown by a default camera framing it, a
    /// grey material, a sky and a key light); the built-in default scene when omitted.
    pub scene: Option<PathBuf>,
    /// Sets the Mitsuba scene parameter `$NAME` (overriding its `<default>`); repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Output image; the format follows the extension: .png (8-bit sRGB), .exr (linear
    /// 32-bit float), .pfm (linear 32-bit float).
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
    /// Samples per pixel.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: Option<u32>,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Random seed; the same seed, scene and sample count give the same image.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Integrator: whitted (the default scene's), direct (Monte Carlo direct lighting),
    /// path (path tracing), bdpt (bidirectional path tracing), mlt (Metropolis light
    /// transport over bidirectional paths; --spp counts mutations per pixel).
    #[arg(long)]
    pub integrator: Option<String>,
    /// Render spectrally: each path carries four sampled wavelengths (path and volpath
    /// integrators); the default when the scene gives spectra by wavelength.
    #[arg(long, conflicts_with = "rgb")]
    pub spectral: bool,
    /// Render in RGB even where the scene gives spectra (they become their colours).
    #[arg(long)]
    pub rgb: bool,
    /// How `direct` samples the lights: mis (default), grid, uniform, stratified,
    /// solid-angle, bsdf.
    #[arg(long)]
    pub light_sampling: Option<String>,
    /// Shadow rays per light per pixel sample for `direct` (default 1; a square for grid).
    #[arg(long, value_parser = parse_light_samples)]
    pub light_samples: Option<u32>,
    /// Weighting of `mis` light sampling: power (default) or balance.
    #[arg(long)]
    pub mis_heuristic: Option<String>,
    /// Which light each shadow ray goes to: power (default; picked in proportion to its
    /// power), uniform (light objects equally likely), all (every light object gets its own).
    #[arg(long)]
    pub light_selection: Option<String>,
    /// Maximum number of reflection/refraction bounces after the camera ray (default 5, at
    /// most 256).
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=penumbra::renderer::integrators::MAX_DEPTH_LIMIT as i64))]
    pub max_depth: Option<u32>,
    /// Path depth from which `path` plays Russian roulette (default: the scene's, else 5,
    /// Mitsuba's; 1 to 256; at max-depth or above, never).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=penumbra::renderer::integrators::MAX_DEPTH_LIMIT as i64))]
    pub rr_depth: Option<u32>,
    /// Stop tracing rays whose accumulated weight falls below this (default 1e-3).
    #[arg(long, value_parser = parse_non_negative)]
    pub min_weight: Option<f32>,
    /// Which of the scene's cameras to render through, counting from 0 in the file's order
    /// (glTF files may define several; the first is the default), with the image size it
    /// asks for unless --res is given.
    #[arg(long, value_name = "N")]
    pub camera: Option<usize>,
    /// Image resolution, WIDTHxHEIGHT (e.g. 1280x720).
    #[arg(long, value_parser = parse_resolution, value_name = "WxH")]
    pub res: Option<(u32, u32)>,
    /// Acceleration structure: bvh (default), grid, nested-grid, octree, octree-keep, kdtree, list.
    #[arg(long)]
    pub accel: Option<String>,
    /// Sampler: sobol (default), stratified, halton, independent.
    #[arg(long)]
    pub sampler: Option<String>,
    /// Exposure in stops applied to PNG output (the image is multiplied by 2^EV).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = parse_finite)]
    pub exposure: f32,
    /// No progress bar and no summary line.
    #[arg(short, long)]
    pub quiet: bool,
    /// Wall-clock budget in seconds: passes (one sample per pixel each) stop when the next
    /// would end beyond it, or when --spp is reached, whichever comes first.
    #[arg(long, value_parser = parse_positive, value_name = "SECONDS")]
    pub time: Option<f32>,
    /// Rewrite the output image (and its .state file) every SECONDS while rendering.
    #[arg(long, value_parser = parse_positive, value_name = "SECONDS")]
    pub checkpoint: Option<f32>,
    /// Continue the render saved in OUTPUT.state (same scene and settings) up to --spp,
    /// ending exactly where an uninterrupted render would.
    #[arg(long)]
    pub resume: bool,
    /// Also write the albedo, shading normal and depth of the first hit as layers of the
    /// EXR output (albedo.R/G/B, normal.X/Y/Z, depth.Z).
    #[arg(long)]
    pub aovs: bool,
    /// With `bdpt`: also write the image of each strategy (s light vertices joined to t
    /// camera vertices), weighted by multiple importance sampling and not, as OpenEXR
    /// files beside the output (OUTPUT_d<segments>_s<s>_t<t>[_unweighted].exr).
    #[arg(long)]
    pub debug_strategies: bool,
    /// `mlt`: probability of a large step (every primary sample afresh) [default: 0.3].
    #[arg(long, value_parser = parse_unit)]
    pub mlt_large_step: Option<f32>,
    /// `mlt`: standard deviation of a small step's offsets [default: 0.01].
    #[arg(long, value_parser = parse_unit)]
    pub mlt_sigma: Option<f32>,
    /// `mlt`: number of Markov chains [default: 1000].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    pub mlt_chains: Option<u32>,
    /// `mlt`: bootstrap samples (per path length when multiplexed) [default: 100000].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000_000))]
    pub mlt_bootstrap: Option<u32>,
    /// `mlt`: Kelemen's plain form (each state a whole bidirectional sample) instead of
    /// the multiplexed one (chains choose the strategy).
    #[arg(long)]
    pub mlt_plain: bool,
    /// `sppm`: photons emitted per pass [default: one per pixel]; `photon`: photons kept
    /// in the global map [default: 200000].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=1_000_000_000))]
    pub photons: Option<u64>,
    /// `photon`: photons kept in the caustic map [default: 100000].
    #[arg(long, value_parser = clap::value_parser!(u64).range(0..=1_000_000_000))]
    pub caustic_photons: Option<u64>,
    /// `sppm`: initial gather radius; `photon`: largest lookup radius (a quarter of it for
    /// caustics), in scene units [default: two pixel footprints at the visible point;
    /// 5% of the scene's size].
    #[arg(long, value_parser = parse_positive, value_name = "RADIUS")]
    pub photon_radius: Option<f32>,
    /// `sppm`: share of a pass's photons a pixel keeps as its radius shrinks (α, in
    /// (0, 1]) [default: 0.667].
    #[arg(long, value_parser = parse_unit)]
    pub sppm_alpha: Option<f32>,
    /// `photon`: photons per density estimate (k nearest) [default: 100].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub photon_lookup: Option<u32>,
    /// `photon`: final-gathering rays per camera sample [default: 4].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub gather_rays: Option<u32>,
    /// Render frames A..B (B not included; A..=B includes it) of an animation (an
    /// environment with `spin`), one numbered image per frame: OUTPUT_0000.exr, ...;
    /// --time is then per frame.
    #[arg(long, value_parser = frames::parse_frames, value_name = "A..B")]
    pub frames: Option<(u32, u32)>,
    /// `env`: how the environment's light is sampled: mis, light (the map), bsdf, sir
    /// (resampled toward their product) or smc (particles carried across --frames)
    /// [default: mis].
    #[arg(long)]
    pub env_sampling: Option<String>,
    /// `env`: shadow rays per pixel sample (N) [default: 4].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub env_samples: Option<u32>,
    /// `env` with sir or smc: candidates per pixel sample (M) [default: 8].
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=65536))]
    pub env_candidates: Option<u32>,
    /// `env` with smc: Metropolis moves per particle per frame [default: 4].
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=1024))]
    pub smc_moves: Option<u32>,
    /// `env` with smc: memory the particles carried to the next frame may take, in MiB;
    /// the pixel samples of passes beyond it start afresh in each frame [default: 512].
    #[arg(long, value_name = "MIB", value_parser = clap::value_parser!(u32).range(0..=1 << 20))]
    pub smc_memory: Option<u32>,
}

fn parse_positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("`{s}` is not a positive number")),
    }
}

fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT, e.g. 640x480"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{v}` is not a whole number"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    let max = penumbra::scene::formats::native::MAX_RESOLUTION;
    if w == 0 || h == 0 || w as i64 > max || h as i64 > max {
        return Err(format!("{w}x{h}: width and height must be between 1 and {max}"));
    }
    let max_pixels = penumbra::scene::formats::native::MAX_PIXELS;
    if w as u64 * h as u64 > max_pixels {
        return Err(format!("{w}x{h} is more than {max_pixels} pixels"));
    }
    Ok((w, h))
}

fn parse_light_samples(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(n) if (1..=1 << 16).contains(&n) => Ok(n),
        Ok(0) => Err("at least one shadow ray per light is needed (e.g. 1, 4, 16)".into()),
        _ => Err(format!("`{s}` is not a whole number from 1 to 65536")),
    }
}

fn parse_finite(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("`{s}` is not a finite number")),
    }
}

fn parse_non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x >= 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("`{s}` is not a non-negative number")),
    }
}

/// Why a command failed.
pub enum Failure {
    /// The user's input is wrong: exit code 2.
    BadInput(miette::Report),
    /// Something went wrong on our side or the system's: exit code 1.
    Internal(String),
}

pub fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Some(Command::Render(args)) => render::run(*args),
        Some(Command::Bench(command)) => bench::run(command),
        Some(Command::Diff(args)) => diff::run(args),
        None => render::run(cli.render),
    }
}

/// `NAME=VALUE` of `-D`: a name of letters, digits and underscores.
fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s.split_once('=').ok_or("expected NAME=VALUE")?;
    if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
        return Err(format!("`{name}` is not a parameter name (letters, digits, _)"));
    }
    Ok((name.to_string(), value.to_string()))
}

/// A number in [0, 1].
fn parse_unit(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v} is not between 0 and 1"))
    }
}
