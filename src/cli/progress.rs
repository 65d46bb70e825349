//! Progress on stderr: an indicatif bar with percentage, ETA and rays per second on a
//! terminal; a plain line at every tenth otherwise; nothing when quiet.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::renderer::Progress;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

pub enum Reporter {
    Quiet,
    Bar {
        bar: ProgressBar,
        rays: AtomicU64,
        start: Instant,
    },
    Lines {
        total: u64,
        done: AtomicU64,
        rays: AtomicU64,
        start: Instant,
    },
}

impl Reporter {
    pub fn new(total_pixels: u64, quiet: bool) -> Self {
        if quiet {
            Reporter::Quiet
        } else if std::io::stderr().is_terminal() {
            let bar = ProgressBar::with_draw_target(Some(total_pixels), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("{bar:40} {percent:>3}%  ETA {eta:>4}  {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
            bar.set_style(style);
            Reporter::Bar {
                bar,
                rays: AtomicU64::new(0),
                start: Instant::now(),
            }
        } else {
            Reporter::Lines {
                total: total_pixels,
                done: AtomicU64::new(0),
                rays: AtomicU64::new(0),
                start: Instant::now(),
            }
        }
    }

    pub fn finish(&self) {
        if let Reporter::Bar { bar, .. } = self {
            bar.finish_and_clear();
        }
    }
}

fn rays_per_second(rays: u64, start: Instant) -> f64 {
    rays as f64 / start.elapsed().as_secs_f64().max(1e-9)
}

impl Progress for Reporter {
    fn advance(&self, pixels: u64, new_rays: u64) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar { bar, rays, start } => {
                let total = rays.fetch_add(new_rays, Ordering::Relaxed) + new_rays;
                bar.set_message(format!("{:.2} Mrays/s", rays_per_second(total, *start) * 1e-6));
                bar.inc(pixels);
            }
            Reporter::Lines {
                total,
                done,
                rays,
                start,
            } => {
                let all_rays = rays.fetch_add(new_rays, Ordering::Relaxed) + new_rays;
                let before = done.fetch_add(pixels, Ordering::Relaxed);
                let after = before + pixels;
                let (t0, t1) = (before * 10 / total.max(&1), after * 10 / total.max(&1));
                if t1 > t0 && after < *total {
                    let elapsed = start.elapsed().as_secs_f64();
                    let eta = elapsed * (*total - after) as f64 / after as f64;
                    eprintln!(
                        "progress: {:3}%  elapsed {:.1} s  ETA {:.1} s  {:.2} Mrays/s",
                        after * 100 / total,
                        elapsed,
                        eta,
                        rays_per_second(all_rays, *start) * 1e-6
                    );
                }
            }
        }
    }
}
