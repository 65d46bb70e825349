//! Image output: PNG (8-bit sRGB, with exposure), OpenEXR (linear 32-bit float) and PFM
//! (linear 32-bit float), chosen by extension. Every file is written to a temporary name
//! in the target directory and renamed into place, so a reader never sees a partial image.
//! Linear images (EXR, PFM) can be read back, for comparisons.

use penumbra_core::Rgb;
use std::io::{self, Write};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Exr,
    Pfm,
}

impl ImageFormat {
    pub const EXTENSIONS: [&'static str; 3] = ["png", "exr", "pfm"];

    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "png" => Some(ImageFormat::Png),
            "exr" => Some(ImageFormat::Exr),
            "pfm" => Some(ImageFormat::Pfm),
            _ => None,
        }
    }
}

/// A linear RGB image, rows from the top.
pub struct Image<'a> {
    pub width: u32,
    pub height: u32,
    pub pixels: &'a [Rgb],
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Writes `image` to `path` in the format its extension names, atomically. `exposure`
/// (in stops) scales the values written to PNG.
pub fn write_image(path: &Path, image: &Image, exposure: f32) -> io::Result<()> {
    let format = ImageFormat::from_path(path).ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "unsupported image extension (expected .png, .exr or .pfm): {}",
                path.display()
            ),
        )
    })?;
    write_file_atomically(path, |file| match format {
        ImageFormat::Png => write_png(&mut io::BufWriter::new(file), image, exposure),
        ImageFormat::Exr => write_exr(file, image, &[]),
        ImageFormat::Pfm => write_pfm(&mut io::BufWriter::new(file), image),
    })
}

/// Writes `image` as OpenEXR with extra channels, each a full channel name ("albedo.R")
/// and one value per pixel, atomically.
pub fn write_exr_layers(path: &Path, image: &Image, extra: &[(&str, Vec<f32>)]) -> io::Result<()> {
    write_file_atomically(path, |file| write_exr(file, image, extra))
}

/// Writes `path` through a temporary file in its directory, renamed into place once
/// complete: a reader never sees a partial file.
pub fn write_file_atomically(path: &Path, write: impl FnOnce(&mut std::fs::File) -> io::Result<()>) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".penumbra-").suffix(".partial");
    // Ordinary file permissions rather than the temporary file's owner-only ones.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let mut tmp = builder.tempfile_in(dir)?;
    write(tmp.as_file_mut())?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// A linear RGB image that owns its pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct OwnedImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Rgb>,
}

/// Reads a linear image: OpenEXR (its first RGB(A) layer) or PFM. The error says what is
/// wrong; the caller names the file.
pub fn read_image(path: &Path) -> io::Result<OwnedImage> {
    let bad = |m: String| io::Error::new(io::ErrorKind::InvalidData, m);
    match ImageFormat::from_path(path) {
        Some(ImageFormat::Exr) => {
            let image = exr::prelude::read_first_rgba_layer_from_file(
                path,
                |size, _| (size.width(), vec![Rgb::BLACK; size.width() * size.height()]),
                |(w, px): &mut (usize, Vec<Rgb>), p, (r, g, b, _a): (f32, f32, f32, f32)| {
                    px[p.y() * *w + p.x()] = Rgb::new(r, g, b)
                },
            )
            .map_err(|e| bad(format!("not a readable OpenEXR image: {e}")))?;
            let size = image.layer_data.size;
            Ok(OwnedImage {
                width: size.width() as u32,
                height: size.height() as u32,
                pixels: image.layer_data.channel_data.pixels.1,
            })
        }
        Some(ImageFormat::Pfm) => read_pfm(&std::fs::read(path)?).map_err(bad),
        _ => Err(bad("only linear images can be compared: .exr or .pfm".into())),
    }
}

/// Parses a colour PFM ("PF", width, height, scale whose sign gives the byte order, then
/// rows from the bottom).
fn read_pfm(bytes: &[u8]) -> Result<OwnedImage, String> {
    let mut fields = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while fields.len() < 4 && i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            if i > start {
                fields.push(String::from_utf8_lossy(&bytes[start..i]).to_string());
            }
            start = i + 1;
        }
        i += 1;
    }
    if fields.len() < 4 || fields[0] != "PF" {
        return Err("not a colour PFM image (it must start with `PF`)".into());
    }
    let parse = |s: &str| s.parse::<u32>().map_err(|_| format!("bad PFM size `{s}`"));
    let (width, height) = (parse(&fields[1])?, parse(&fields[2])?);
    let scale: f32 = fields[3]
        .parse()
        .map_err(|_| format!("bad PFM scale `{}`", fields[3]))?;
    let data = &bytes[start..];
    let n = width as usize * height as usize;
    if data.len() != n * 12 {
        return Err(format!(
            "PFM data holds {} bytes, {width}x{height} needs {}",
            data.len(),
            n * 12
        ));
    }
    let value = |k: usize| {
        let b = [data[4 * k], data[4 * k + 1], data[4 * k + 2], data[4 * k + 3]];
        if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut pixels = vec![Rgb::BLACK; n];
    for (k, p) in pixels.iter_mut().enumerate() {
        let (x, y) = (k % width as usize, k / width as usize);
        let src = (height as usize - 1 - y) * width as usize + x;
        *p = Rgb::new(value(3 * src), value(3 * src + 1), value(3 * src + 2));
    }
    Ok(OwnedImage { width, height, pixels })
}

fn write_png(w: &mut impl Write, image: &Image, exposure: f32) -> io::Result<()> {
    let scale = exposure.exp2();
    let mut encoder = png::Encoder::new(w, image.width, image.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().map_err(io::Error::other)?;
    let bytes: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|c| c.to_array())
        .map(|v| {
            let v = if v.is_finite() {
                (v * scale).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (srgb_encode(v) * 255.0 + 0.5) as u8
        })
        .collect();
    writer.write_image_data(&bytes).map_err(io::Error::other)?;
    writer.finish().map_err(io::Error::other)
}

fn write_exr(file: &mut std::fs::File, image: &Image, extra: &[(&str, Vec<f32>)]) -> io::Result<()> {
    use exr::prelude::*;
    let (w, h) = (image.width as usize, image.height as usize);
    if extra.is_empty() {
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
            let c = image.pixels[p.y() * w + p.x()];
            (c.r, c.g, c.b)
        });
        let img = exr::image::Image::from_channels((w, h), channels);
        // One thread: parallel compression writes the blocks in whatever order they finish.
        return img
            .write()
            .non_parallel()
            .to_buffered(io::BufWriter::new(file))
            .map_err(io::Error::other);
    }
    let rgb = |f: fn(&Rgb) -> f32| FlatSamples::F32(image.pixels.iter().map(f).collect());
    let mut list = vec![
        AnyChannel::new("R", rgb(|c| c.r)),
        AnyChannel::new("G", rgb(|c| c.g)),
        AnyChannel::new("B", rgb(|c| c.b)),
    ];
    list.extend(
        extra
            .iter()
            .map(|(name, values)| AnyChannel::new(*name, FlatSamples::F32(values.clone()))),
    );
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(list.into()),
    );
    exr::image::Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(io::BufWriter::new(file))
        .map_err(io::Error::other)
}

/// The Portable Float Map: a text header, then little-endian floats, rows from the bottom.
fn write_pfm(w: &mut impl Write, image: &Image) -> io::Result<()> {
    write!(w, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    for row in image.pixels.chunks(image.width as usize).rev() {
        for c in row {
            for v in c.to_array() {
                w.write_all(&v.to_le_bytes())?;
            }
        }
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_images_read_back_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let pixels: Vec<Rgb> = (0..12)
            .map(|i| Rgb::new(i as f32, 0.5 * i as f32, -1.0 / (1.0 + i as f32)))
            .collect();
        let image = Image {
            width: 4,
            height: 3,
            pixels: &pixels,
        };
        for ext in ["exr", "pfm"] {
            let path = dir.path().join(format!("a.{ext}"));
            write_image(&path, &image, 0.0).unwrap();
            let back = read_image(&path).unwrap();
            assert_eq!((back.width, back.height, &back.pixels), (4, 3, &pixels), "{ext}");
        }
        let png = dir.path().join("a.png");
        write_image(&png, &image, 0.0).unwrap();
        assert!(read_image(&png).is_err());
        std::fs::write(dir.path().join("bad.pfm"), b"PF\n4 3\n-1.0\n123").unwrap();
        let e = read_image(&dir.path().join("bad.pfm")).unwrap_err();
        assert!(e.to_string().contains("needs 144"), "{e}");
    }

    fn sample() -> Vec<Rgb> {
        (0..6).map(|i| Rgb::new(i as f32 * 0.2, 0.5, 2.0)).collect()
    }

    #[test]
    fn pfm_layout() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.pfm");
        let px = sample();
        write_image(
            &p,
            &Image {
                width: 3,
                height: 2,
                pixels: &px,
            },
            0.0,
        )
        .unwrap();
        let bytes = std::fs::read(&p).unwrap();
        let header = b"PF\n3 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        assert_eq!(bytes.len(), header.len() + 6 * 12);
        // First stored row is the bottom row: pixel 3.
        let first = f32::from_le_bytes(bytes[header.len()..header.len() + 4].try_into().unwrap());
        assert_eq!(first, px[3].r);
    }

    #[test]
    fn exr_round_trip_and_png_writes() {
        let dir = tempfile::tempdir().unwrap();
        let px = sample();
        let img = Image {
            width: 3,
            height: 2,
            pixels: &px,
        };
        let p = dir.path().join("a.exr");
        write_image(&p, &img, 0.0).unwrap();
        let read = exr::prelude::read_first_rgba_layer_from_file(
            &p,
            |res, _| vec![[0f32; 3]; res.width() * res.height()],
            |buf, pos, (r, g, b, _a): (f32, f32, f32, f32)| buf[pos.y() * 3 + pos.x()] = [r, g, b],
        )
        .unwrap();
        let got = &read.layer_data.channel_data.pixels;
        assert_eq!(got[4], px[4].to_array());
        let png_path = dir.path().join("a.png");
        write_image(&png_path, &img, 1.0).unwrap();
        // Decode it: exposure +1 doubles, then clamps and sRGB-encodes.
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png_path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        let expect = |v: f32| (srgb_encode((2.0 * v).min(1.0)) * 255.0 + 0.5) as u8;
        assert_eq!(&buf[3..6], &[expect(px[1].r), expect(0.5), 255]);
        // No temporary files left behind.
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        assert!(write_image(&dir.path().join("a.bmp"), &img, 0.0).is_err());
    }

    #[test]
    fn srgb_curve() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.18) - 0.4613).abs() < 1e-3);
    }
}
