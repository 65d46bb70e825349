//! Penumbra, a physically based CPU renderer.
//!
//! This crate is the library's front door: it re-exports the layers (`penumbra_core`,
//! `penumbra_geometry`, `penumbra_render`, `penumbra_scene`) and adds the few calls a
//! program needs to go from a scene description to an image:
//!
//! ```no_run
//! let desc = penumbra::default_scene();
//! let result = penumbra::render(&desc, penumbra::RenderControl::default()).unwrap();
//! let pixels = result.film.image();
//! penumbra::scene::image_io::write_image(
//!     std::path::Path::new("out.png"),
//!     &penumbra::scene::image_io::Image { width: result.film.width, height: result.film.height, pixels: &pixels },
//!     0.0,
//! )
//! .unwrap();
//! ```

pub mod bench;
pub mod metrics;
pub mod state;

pub use penumbra_core as math;
pub use penumbra_geometry as geometry;
pub use penumbra_render as renderer;
pub use penumbra_scene as scene;

use penumbra_render::integrators::Integrator;
use penumbra_render::{Film, Progress, RenderOptions, RenderResult};
use penumbra_scene::{build_scene, SceneDesc, SceneError, SourceFile};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// The source of the built-in default scene: the classic Whitted scene.
pub const DEFAULT_SCENE_TOML: &str = include_str!("../scenes/whitted.toml");

/// The built-in default scene.
pub fn default_scene() -> SceneDesc {
    let file = SourceFile::new("<built-in>/whitted.toml", DEFAULT_SCENE_TOML.to_string());
    penumbra_scene::formats::native::read(&file).expect("the built-in scene is valid")
}

/// How a render is run: progress reporting, cancellation, time budget, AOVs, and a saved
/// film to resume.
pub struct RenderControl<'a> {
    pub progress: &'a dyn Progress,
    /// Set to stop the render after the pass in flight; what is done is kept.
    pub cancel: &'a AtomicBool,
    /// Stop once the next pass would end beyond this much time.
    pub time_limit: Option<Duration>,
    /// Accumulate the albedo, shading normal and depth AOVs too.
    pub aovs: bool,
    /// A film to continue (see [`state`]); it must fit the scene.
    pub resume: Option<Film>,
    /// Sees the film after every pass (for checkpoints).
    pub after_pass: Option<&'a (dyn Fn(&Film) + Sync)>,
    /// `bdpt` keeps each strategy's image in a film layer of its own.
    pub debug_strategies: bool,
}

static NEVER: AtomicBool = AtomicBool::new(false);

impl Default for RenderControl<'_> {
    fn default() -> Self {
        RenderControl {
            progress: &(),
            cancel: &NEVER,
            time_limit: None,
            aovs: false,
            resume: None,
            after_pass: None,
            debug_strategies: false,
        }
    }
}

/// Builds `desc` and renders it with the integrator and settings it names, in the current
/// rayon thread pool.
pub fn render(desc: &SceneDesc, control: RenderControl) -> Result<RenderResult, SceneError> {
    let integrator = integrator(desc, control.debug_strategies);
    render_with(desc, integrator.as_ref(), control)
}

/// The integrator `desc` names, with its settings (`debug_strategies`: `bdpt` keeps each
/// strategy's image).
pub fn integrator(desc: &SceneDesc, debug_strategies: bool) -> Box<dyn Integrator> {
    desc.render.integrator(debug_strategies)
}

/// Builds `desc` and renders it with `integrator` (made by [`integrator`] for this or an
/// earlier frame of the same animation: integrators that carry samples from frame to frame
/// keep them in it), in the current rayon thread pool.
pub fn render_with(
    desc: &SceneDesc,
    integrator: &dyn Integrator,
    control: RenderControl,
) -> Result<RenderResult, SceneError> {
    let scene = build_scene(desc)?;
    let r = &desc.render;
    let options = RenderOptions {
        spp: r.spp,
        seed: r.seed,
        sampler: r.sampler,
        time_limit: control.time_limit,
        aovs: control.aovs,
        ..RenderOptions::default()
    };
    let film = match control.resume {
        Some(film) => {
            if (film.width, film.height) != (scene.width, scene.height) || film.aovs.is_some() != control.aovs {
                return Err(SceneError::Io {
                    path: "<resume>".into(),
                    message: format!(
                        "the saved render is {}x{}{}, the scene asks for {}x{}{}",
                        film.width,
                        film.height,
                        if film.aovs.is_some() { " with AOVs" } else { "" },
                        scene.width,
                        scene.height,
                        if control.aovs { " with AOVs" } else { "" }
                    ),
                });
            }
            film
        }
        None => Film::new(scene.width, scene.height, control.aovs),
    };
    let mut after_pass = |f: &Film| {
        if let Some(callback) = control.after_pass {
            callback(f)
        }
    };
    Ok(penumbra_render::render(
        &scene,
        integrator,
        &options,
        film,
        control.progress,
        control.cancel,
        &mut after_pass,
    ))
}
