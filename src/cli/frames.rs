//! `penumbra render SCENE --frames A..B`: an animation, one image per frame, numbered
//! (`out.exr` becomes `out_0000.exr`, `out_0001.exr`, ...). The scene of frame f is
//! [`SceneDesc::at_frame`] (the environment turned by its `spin`). `env` with
//! `--env-sampling smc` renders every frame with one integrator, which carries its
//! particles; every other integrator starts each frame afresh.

use super::progress::Reporter;
use super::Failure;
use penumbra::renderer::driver::Stop;
use penumbra::scene::image_io::{write_image, Image};
use penumbra::scene::SceneDesc;
use penumbra::RenderControl;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// `A..B` (B excluded) or `A..=B` (included), as Rust writes ranges.
pub fn parse_frames(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{s}` is not a frame range: write A..B (B not included) or A..=B");
    let (a, b, inclusive) = match s.split_once("..=") {
        Some((a, b)) => (a, b, true),
        None => {
            let (a, b) = s.split_once("..").ok_or_else(bad)?;
            (a, b, false)
        }
    };
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    let end = if inclusive {
        b.checked_add(1).ok_or_else(bad)?
    } else {
        b
    };
    if end <= a {
        return Err(format!("`{s}` holds no frames"));
    }
    Ok((a, end))
}

/// `output` with the frame number before its extension: `out.exr` → `out_0007.exr`.
pub fn frame_path(output: &Path, frame: u32) -> PathBuf {
    let stem = output
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let name = match output.extension() {
        Some(ext) => format!("{stem}_{frame:04}.{}", ext.to_string_lossy()),
        None => format!("{stem}_{frame:04}"),
    };
    output.with_file_name(name)
}

/// Renders frames `first..end` of `desc` into numbered images beside `output`, each
/// with the time budget `time` if given; an interrupt stops after the frame in flight
/// (whose image is written with what it has).
#[allow(clippy::too_many_arguments)]
pub fn run(
    desc: &SceneDesc,
    (first, end): (u32, u32),
    output: &Path,
    exposure: f32,
    time: Option<Duration>,
    quiet: bool,
    pool: &rayon::ThreadPool,
    cancel: &AtomicBool,
) -> Result<(), Failure> {
    // An integrator that carries what it learnt from frame to frame (`env` with `smc`)
    // renders every frame; any other starts each frame afresh (mlt's chains and
    // normalisation belong to one frame).
    let mut integrator = penumbra::integrator(desc, false);
    let carries = integrator.capabilities().carries_frames;
    let pixels = desc.render.width as u64 * desc.render.height as u64;
    for frame in first..end {
        if cancel.load(Ordering::Relaxed) {
            eprintln!("interrupted before frame {frame}");
            break;
        }
        if !carries && frame > first {
            integrator = penumbra::integrator(desc, false);
        }
        let scene = desc.at_frame(frame);
        let reporter = Reporter::new(pixels * desc.render.spp as u64, quiet);
        let control = RenderControl {
            progress: &reporter,
            cancel,
            time_limit: time,
            ..RenderControl::default()
        };
        let result = pool
            .install(|| penumbra::render_with(&scene, integrator.as_ref(), control))
            .map_err(|e| Failure::BadInput(e.into()))?;
        reporter.finish();
        let film = &result.film;
        if film.samples_per_pixel == 0 {
            eprintln!("interrupted before frame {frame} had a sample: not written");
            break;
        }
        let pixels = film.image();
        let path = frame_path(output, frame);
        let image = Image {
            width: film.width,
            height: film.height,
            pixels: &pixels,
        };
        write_image(&path, &image, exposure)
            .map_err(|e| Failure::Internal(format!("cannot write {}: {e}", path.display())))?;
        if !quiet {
            let s = &result.stats;
            eprintln!(
                "frame {frame}: {} spp in {:.2} s",
                film.samples_per_pixel,
                s.elapsed.as_secs_f64()
            );
            for note in &s.notes {
                eprintln!("{note}");
            }
        }
        println!("wrote {}", path.display());
        if result.stats.stop == Stop::Cancelled || cancel.load(Ordering::Relaxed) {
            eprintln!("interrupted after frame {frame}");
            break;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_and_names() {
        assert_eq!(parse_frames("0..24"), Ok((0, 24)));
        assert_eq!(parse_frames("3..=5"), Ok((3, 6)));
        assert!(parse_frames("5..5").is_err());
        assert!(parse_frames("a..3").is_err());
        assert!(parse_frames("7").is_err());
        assert_eq!(frame_path(Path::new("out/a.exr"), 7), PathBuf::from("out/a_0007.exr"));
        assert_eq!(frame_path(Path::new("a"), 12), PathBuf::from("a_0012"));
    }
}
