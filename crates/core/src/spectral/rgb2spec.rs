//! Smooth spectra for RGB colours (Jakob and Hanika, "A Low-Dimensional Function Space for
//! Efficient Spectral Upsampling", Eurographics 2019): a reflectance is the sigmoid of a
//! quadratic in λ, s(λ) = S(c₀λ² + c₁λ + c₂) with S(x) = ½ + x / (2√(1 + x²)), whose
//! coefficients come from a table over the colour cube made by [`super::rgb2spec_opt`]
//! and interpolated trilinearly, as pbrt-v4's `RGBToSpectrumTable` does.
//!
//! The table (`data/rgb2spec-srgb.bin` in this crate, linear sRGB under D65) is built into
//! the binary. Its layout: the bytes `PNRGB2SP`, the resolution `res` (u32), `res` brightness
//! nodes, then `3 × res³` coefficient triples (indexed by largest channel, brightness, y, x), all
//! little-endian `f32`.

use std::sync::OnceLock;

/// A smooth spectrum: the sigmoid of c₀λ² + c₁λ + c₂ (λ in nanometres), in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sigmoid {
    pub c: [f32; 3],
}

impl Sigmoid {
    /// The spectrum's value at `lambda` nanometres.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let x = (self.c[0] * lambda + self.c[1]) * lambda + self.c[2];
        if x.is_infinite() {
            return if x > 0.0 { 1.0 } else { 0.0 };
        }
        0.5 + x / (2.0 * (1.0 + x * x).sqrt())
    }

    /// The spectrum's largest value over [360, 830] nm (at the vertex of the quadratic or an
    /// end).
    pub fn max_value(&self) -> f32 {
        let mut m = self.eval(360.0).max(self.eval(830.0));
        if self.c[0] != 0.0 {
            let vertex = -self.c[1] / (2.0 * self.c[0]);
            if (360.0..=830.0).contains(&vertex) {
                m = m.max(self.eval(vertex));
            }
        }
        m
    }
}

/// The coefficient table for one RGB colour space.
#[derive(Clone, Debug)]
pub struct RgbToSpectrum {
    res: usize,
    /// Brightness nodes (the largest channel's value at each table slice), increasing.
    z_nodes: Vec<f32>,
    /// `3 × res³ × 3` coefficients.
    coeffs: Vec<f32>,
}

/// The table file's magic bytes.
pub const MAGIC: &[u8; 8] = b"PNRGB2SP";

static SRGB_TABLE: &[u8] = include_bytes!("../../data/rgb2spec-srgb.bin");

impl RgbToSpectrum {
    /// The table from its file's bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, String> {
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err("not an rgb2spec table".into());
        }
        let res = u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize;
        let floats = res + 9 * res * res * res;
        if !(2..=256).contains(&res) || bytes.len() != 12 + 4 * floats {
            return Err(format!("an rgb2spec table of resolution {res} has the wrong length"));
        }
        let values: Vec<f32> = bytes[12..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        Ok(RgbToSpectrum {
            res,
            z_nodes: values[..res].to_vec(),
            coeffs: values[res..].to_vec(),
        })
    }

    /// The table as its file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&(self.res as u32).to_le_bytes());
        for v in self.z_nodes.iter().chain(&self.coeffs) {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// A table from its parts (the optimiser's output).
    pub fn new(res: usize, z_nodes: Vec<f32>, coeffs: Vec<f32>) -> Self {
        assert_eq!(z_nodes.len(), res);
        assert_eq!(coeffs.len(), 9 * res * res * res);
        RgbToSpectrum { res, z_nodes, coeffs }
    }

    /// The linear sRGB table, read once.
    pub fn srgb() -> &'static RgbToSpectrum {
        static TABLE: OnceLock<RgbToSpectrum> = OnceLock::new();
        TABLE.get_or_init(|| RgbToSpectrum::from_bytes(SRGB_TABLE).expect("the built-in rgb2spec table"))
    }

    /// The table's resolution and its size in bytes.
    pub fn size(&self) -> (usize, usize) {
        (self.res, 4 * (self.z_nodes.len() + self.coeffs.len()))
    }

    /// The coefficients stored for (largest channel `l`, brightness `z`, `y`, `x`).
    pub fn entry(&self, l: usize, z: usize, y: usize, x: usize) -> [f32; 3] {
        let i = 3 * (((l * self.res + z) * self.res + y) * self.res + x);
        [self.coeffs[i], self.coeffs[i + 1], self.coeffs[i + 2]]
    }

    /// The smooth spectrum of a reflectance `rgb` (each channel clamped to [0, 1]).
    pub fn sigmoid(&self, rgb: [f32; 3]) -> Sigmoid {
        let rgb = rgb.map(|c| if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) });
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            let v = rgb[0];
            return Sigmoid {
                c: [0.0, 0.0, (v - 0.5) / (v * (1.0 - v)).sqrt()],
            };
        }
        let l = if rgb[0] > rgb[1] {
            if rgb[0] > rgb[2] {
                0
            } else {
                2
            }
        } else if rgb[1] > rgb[2] {
            1
        } else {
            2
        };
        let n = (self.res - 1) as f32;
        let z = rgb[l];
        let x = rgb[(l + 1) % 3] * n / z;
        let y = rgb[(l + 2) % 3] * n / z;
        let xi = (x as usize).min(self.res - 2);
        let yi = (y as usize).min(self.res - 2);
        let zi = self.z_nodes.partition_point(|&v| v < z).clamp(1, self.res - 1) - 1;
        let (dx, dy) = (x - xi as f32, y - yi as f32);
        let dz = (z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi]);
        let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
        let c = std::array::from_fn(|k| {
            let co = |ox: usize, oy: usize, oz: usize| self.entry(l, zi + oz, yi + oy, xi + ox)[k];
            let plane = |oz: usize| {
                lerp(
                    dy,
                    lerp(dx, co(0, 0, oz), co(1, 0, oz)),
                    lerp(dx, co(0, 1, oz), co(1, 1, oz)),
                )
            };
            lerp(dz, plane(0), plane(1))
        });
        Sigmoid { c }
    }
}

/// A colour of any brightness as a spectrum: `scale` times a smooth reflectance, with the
/// scale twice the largest channel so the reflectance stays clear of 0 and 1 (pbrt-v4's
/// `RGBUnboundedSpectrum`). Illuminants are this times D65 ([`super::cie::d65_unit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unbounded {
    pub scale: f32,
    pub sigmoid: Sigmoid,
}

impl Unbounded {
    pub fn new(table: &RgbToSpectrum, rgb: [f32; 3]) -> Self {
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        let scale = 2.0 * m;
        let sigmoid = if scale > 0.0 {
            table.sigmoid(rgb.map(|c| c / scale))
        } else {
            table.sigmoid([0.0; 3])
        };
        Unbounded { scale, sigmoid }
    }

    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        self.scale * self.sigmoid.eval(lambda)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{cie, rgb2spec_opt};
    use super::*;
    use crate::Pcg32;

    /// The reflectance's colour under D65, as linear sRGB.
    fn colour(s: Sigmoid) -> [f32; 3] {
        cie::srgb_of(|l| s.eval(l) * cie::d65_unit(l))
    }

    /// Random reflectances come back as themselves through the built-in table: the colour
    /// of the uplifted spectrum under D65 (the sum per nanometre) against the RGB.
    #[test]
    fn reflectances_round_trip_through_the_table() {
        let table = RgbToSpectrum::srgb();
        let mut rng = Pcg32::new(5, 9);
        let (mut worst, mut sum) = (0f32, 0f32);
        let n = 2000;
        for _ in 0..n {
            let rgb = [rng.next_f32(), rng.next_f32(), rng.next_f32()].map(|c| 0.02 + 0.96 * c);
            let back = colour(table.sigmoid(rgb));
            let e = (0..3).map(|i| (back[i] - rgb[i]).abs()).fold(0.0, f32::max);
            worst = worst.max(e);
            sum += e;
        }
        println!("round trip: largest error {worst:.4}, mean {:.5}", sum / n as f32);
        assert!(worst < 0.02 && sum / (n as f32) < 0.002, "{worst} {}", sum / n as f32);
        // Greys are exact by construction (a constant spectrum).
        let g = colour(table.sigmoid([0.3; 3]));
        assert!(g.iter().all(|c| (c - 0.3).abs() < 2e-3), "{g:?}");
    }

    /// The table in the binary is what the optimiser in this crate makes: three columns
    /// rebuilt bit for bit.
    #[test]
    fn the_built_in_table_is_the_optimisers() {
        let table = RgbToSpectrum::srgb();
        let (res, _) = table.size();
        for (l, x, y) in [(0, 3, 17), (1, res - 1, 0), (2, 12, 29)] {
            let (column, _) = rgb2spec_opt::column(res, l, x, y);
            for (z, c) in column.iter().enumerate() {
                assert_eq!(*c, table.entry(l, z, y, x), "column {l} {x} {y}, brightness {z}");
            }
        }
    }

    /// A colour above 1 (an emitter's) keeps its colour and scale as an unbounded spectrum.
    #[test]
    fn unbounded_colours_keep_their_scale() {
        let rgb = [18.387, 13.9873, 6.75357];
        let u = Unbounded::new(RgbToSpectrum::srgb(), rgb);
        let back = cie::srgb_of(|l| u.eval(l) * cie::d65_unit(l));
        assert!((0..3).all(|i| (back[i] / rgb[i] - 1.0).abs() < 0.02), "{back:?}");
    }
}
