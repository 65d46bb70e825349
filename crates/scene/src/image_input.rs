//! Images a scene reads: textures and environment maps, in any of the formats people have
//! (PNG, JPEG, OpenEXR, Radiance HDR, PFM), as linear RGB.

use crate::image_io::{read_image, OwnedImage};
use penumbra_core::Rgb;
use penumbra_render::texture::{TextureImage, Wrap};
use penumbra_render::Texture;
use std::io;
use std::path::Path;
use std::sync::Arc;

/// The inverse of [`crate::image_io::srgb_encode`].
pub fn srgb_decode(x: f32) -> f32 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// The largest image a scene may load (2^28 pixels, as for rendered images).
pub const MAX_INPUT_PIXELS: u64 = 1 << 28;

/// Reads an image a scene uses (a texture or an environment map) as linear RGB, rows from
/// the top: OpenEXR, PFM and Radiance HDR as stored; PNG and JPEG (8 or 16 bits) decoded
/// with sRGB's transfer function when `srgb` (colours), else as they are (data such as
/// roughness). The error says what is wrong; the caller names the file.
pub fn read_input_image(path: &Path, srgb: bool) -> io::Result<OwnedImage> {
    let bad = |m: String| io::Error::new(io::ErrorKind::InvalidData, m);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "exr" | "pfm" => read_image(path),
        "hdr" | "png" | "jpg" | "jpeg" => {
            let mut reader = image::ImageReader::open(path)?
                .with_guessed_format()
                .map_err(|e| bad(e.to_string()))?;
            let mut limits = image::Limits::default();
            limits.max_alloc = Some(MAX_INPUT_PIXELS * 16);
            reader.limits(limits);
            let decoded = reader.decode().map_err(|e| bad(format!("cannot decode it: {e}")))?;
            let linear = ext == "hdr";
            let rgb = decoded.to_rgb32f();
            let decode = |x: f32| if srgb && !linear { srgb_decode(x) } else { x };
            Ok(OwnedImage {
                width: rgb.width(),
                height: rgb.height(),
                pixels: rgb
                    .pixels()
                    .map(|p| Rgb::new(decode(p[0]), decode(p[1]), decode(p[2])))
                    .collect(),
            })
        }
        _ => Err(bad(
            "unsupported image format: use .exr, .hdr, .pfm, .png, .jpg or .jpeg".into(),
        )),
    }
}

/// The image texture in the file at `path`, repeated every 1/`scale` texture units: read by
/// [`read_input_image`], refused when it is empty or has a pixel that is not a finite
/// number. The error names the file (every scene reader's textures come through here).
pub fn image_texture(path: &Path, srgb: bool, scale: f32) -> Result<Texture, String> {
    let image = read_input_image(path, srgb).map_err(|e| format!("cannot read the texture {}: {e}", path.display()))?;
    if image.width == 0 || image.height == 0 {
        return Err(format!("the texture {} is empty", path.display()));
    }
    if let Some(i) = image.pixels.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "the texture {} has a pixel that is not a finite number at ({}, {})",
            path.display(),
            i % image.width as usize,
            i / image.width as usize
        ));
    }
    Ok(Texture::Image(penumbra_render::texture::ImageTexture {
        image: Arc::new(TextureImage {
            wrap: Default::default(),
            width: image.width as usize,
            height: image.height as usize,
            pixels: image.pixels,
        }),
        scale,
    }))
}

/// `texture` with `wrap` (along u, v) beyond its image, if it is an image.
pub fn with_wrap(texture: Texture, wrap: [Wrap; 2]) -> Texture {
    match texture {
        Texture::Image(penumbra_render::texture::ImageTexture { mut image, scale }) => {
            Arc::make_mut(&mut image).wrap = wrap;
            Texture::Image(penumbra_render::texture::ImageTexture { image, scale })
        }
        other => other,
    }
}
