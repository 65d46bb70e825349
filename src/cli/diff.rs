//! `penumbra diff A B [--ref R] [--error-image OUT.png]`: how far images are apart.

use super::Failure;
use clap::Args;
use penumbra::metrics::{compare, error_image};
use penumbra::scene::image_io::{read_image, write_image, Image, OwnedImage};
use std::path::{Path, PathBuf};

/// Compare linear images (.exr, .pfm): RMSE, relative MSE (mean of (a - r)² / (r² + 0.01))
/// and mean absolute relative error.
#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The image to judge.
    pub a: PathBuf,
    /// The image to compare it with (the reference, unless --ref is given).
    pub b: PathBuf,
    /// A reference: report A and B each against it.
    #[arg(long = "ref", value_name = "R")]
    pub reference: Option<PathBuf>,
    /// Write a false-colour image of A's per-pixel relative error (against R, else B).
    #[arg(long, value_name = "OUT.png")]
    pub error_image: Option<PathBuf>,
}

fn load(path: &Path) -> Result<OwnedImage, Failure> {
    read_image(path).map_err(|e| Failure::BadInput(miette::miette!("cannot read {}: {e}", path.display())))
}

pub fn run(args: DiffArgs) -> Result<(), Failure> {
    let a = load(&args.a)?;
    let b = load(&args.b)?;
    let r = args.reference.as_deref().map(load).transpose()?;
    let reference = r.as_ref().unwrap_or(&b);
    for (img, path) in [(&a, &args.a), (&b, &args.b)] {
        if (img.width, img.height) != (reference.width, reference.height) {
            return Err(Failure::BadInput(miette::miette!(
                "{} is {}x{}, the reference is {}x{}",
                path.display(),
                img.width,
                img.height,
                reference.width,
                reference.height
            )));
        }
    }
    let judged: Vec<(&Path, &OwnedImage)> = match &args.reference {
        Some(_) => vec![(&args.a, &a), (&args.b, &b)],
        None => vec![(&args.a, &a)],
    };
    let against = args.reference.as_deref().unwrap_or(&args.b);
    println!("against {}:", against.display());
    println!(
        "{:<40} {:>12} {:>12} {:>12}  mean ratio (R, G, B)",
        "image", "RMSE", "relMSE", "mean |rel|"
    );
    for (path, img) in judged {
        let e = compare(&img.pixels, &reference.pixels);
        let [r, g, b] = e.mean_ratio;
        println!(
            "{:<40} {:>12.4e} {:>12.4e} {:>12.4e}  {r:.5} {g:.5} {b:.5}",
            path.display(),
            e.rmse,
            e.rel_mse,
            e.mean_abs_rel
        );
    }
    if let Some(out) = &args.error_image {
        let pixels = error_image(&a.pixels, &reference.pixels);
        let image = Image {
            width: a.width,
            height: a.height,
            pixels: &pixels,
        };
        write_image(out, &image, 0.0).map_err(|e| Failure::Internal(format!("cannot write {}: {e}", out.display())))?;
        println!("wrote {}", out.display());
    }
    Ok(())
}
