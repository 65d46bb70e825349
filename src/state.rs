//! The saved state of a progressive render, for `--resume`: the film's double-precision
//! sums (and AOV sums), its samples per pixel and rejected-sample count, the sample count
//! the render was planned for, and a fingerprint of the scene and settings it belongs to.
//!
//! Written beside the output as `<output>.state`, atomically (a temporary file renamed into
//! place), at every checkpoint and at the end. Little-endian binary:
//! `PENUMBRA-STATE 2\n`, then u64 fingerprint, u32 width, height, samples per pixel,
//! planned spp, u8 has-AOVs, u8 has-splats, u64 rejected, then per pixel 4 f64 (R, G, B,
//! weight sums); with AOVs, 7 f64 more per pixel; with splats, 3 f64 more per pixel (the
//! splat layer's sums).

use penumbra_render::film::{FilmPixel, AOV_CHANNELS};
use penumbra_render::Film;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

const MAGIC: &[u8] = b"PENUMBRA-STATE 2\n";

/// A saved render.
pub struct SavedRender {
    pub film: Film,
    /// The sample count the render was planned for (samplers may depend on it).
    pub planned_spp: u32,
    /// Of the scene and the settings that shape the image.
    pub fingerprint: u64,
}

/// Where the state of a render written to `output` is kept.
pub fn state_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".state");
    PathBuf::from(name)
}

/// Writes `film` as the state of a render planned for `planned_spp`, atomically.
pub fn write_state(path: &Path, film: &Film, planned_spp: u32, fingerprint: u64) -> io::Result<()> {
    penumbra_scene::image_io::write_file_atomically(path, |file| {
        let mut w = io::BufWriter::new(file);
        w.write_all(MAGIC)?;
        w.write_all(&fingerprint.to_le_bytes())?;
        for v in [film.width, film.height, film.samples_per_pixel, planned_spp] {
            w.write_all(&v.to_le_bytes())?;
        }
        w.write_all(&[film.aovs.is_some() as u8, !film.splats.is_empty() as u8])?;
        w.write_all(&film.rejected.to_le_bytes())?;
        for p in film.pixels() {
            for v in [p.sum[0], p.sum[1], p.sum[2], p.weight] {
                w.write_all(&v.to_le_bytes())?;
            }
        }
        for a in film.aovs.iter().flatten() {
            for v in a {
                w.write_all(&v.to_le_bytes())?;
            }
        }
        for v in film.splats.iter().flatten() {
            w.write_all(&v.to_le_bytes())?;
        }
        w.flush()
    })
}

/// Reads a state written by [`write_state`]; the error says what is wrong with it.
pub fn read_state(path: &Path) -> io::Result<SavedRender> {
    let bad = |m: &str| io::Error::new(io::ErrorKind::InvalidData, m.to_string());
    let mut r = io::BufReader::new(std::fs::File::open(path)?);
    let mut magic = vec![0u8; MAGIC.len()];
    r.read_exact(&mut magic)
        .map_err(|_| bad("too short to be a Penumbra render state"))?;
    if magic != MAGIC {
        return Err(bad("not a Penumbra render state (or of another version)"));
    }
    let u64s = |r: &mut dyn Read| -> io::Result<u64> {
        let mut b = [0u8; 8];
        r.read_exact(&mut b)?;
        Ok(u64::from_le_bytes(b))
    };
    let truncated = |_| bad("the state is truncated");
    let fingerprint = u64s(&mut r).map_err(truncated)?;
    let mut u32s = [0u32; 4];
    for v in &mut u32s {
        let mut b = [0u8; 4];
        r.read_exact(&mut b).map_err(truncated)?;
        *v = u32::from_le_bytes(b);
    }
    let [width, height, samples_per_pixel, planned_spp] = u32s;
    let mut flag = [0u8; 2];
    r.read_exact(&mut flag).map_err(truncated)?;
    let rejected = u64s(&mut r).map_err(truncated)?;
    let n = width as u64 * height as u64;
    // Refuse absurd sizes before allocating (the largest image a scene may ask for).
    if n == 0 || n > penumbra_scene::formats::native::MAX_PIXELS {
        return Err(bad("the state's image size is out of range"));
    }
    let mut film = Film::new(width, height, flag[0] != 0);
    film.samples_per_pixel = samples_per_pixel;
    film.rejected = rejected;
    let f64s = |r: &mut dyn Read| -> io::Result<f64> { u64s(r).map(f64::from_bits) };
    for p in film.pixels_mut() {
        let mut v = [0.0; 4];
        for x in &mut v {
            *x = f64s(&mut r).map_err(truncated)?;
        }
        *p = FilmPixel {
            sum: [v[0], v[1], v[2]],
            weight: v[3],
        };
    }
    if let Some(aovs) = &mut film.aovs {
        for a in aovs.iter_mut() {
            for x in a.iter_mut().take(AOV_CHANNELS) {
                *x = f64s(&mut r).map_err(truncated)?;
            }
        }
    }
    if flag[1] != 0 {
        film.splats = vec![[0.0; 3]; n as usize];
        for x in film.splats.iter_mut().flatten() {
            *x = f64s(&mut r).map_err(truncated)?;
        }
    }
    if r.read(&mut [0u8; 1])? != 0 {
        return Err(bad("the state has data past its end"));
    }
    Ok(SavedRender {
        film,
        planned_spp,
        fingerprint,
    })
}
