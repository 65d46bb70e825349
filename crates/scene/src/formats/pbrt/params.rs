//! A pbrt-v4 parameter list (`"float radius" [ 2 ]`, `"rgb L" [ 1 1 1 ]`,
//! `"blackbody L" 6500`, `"texture reflectance" "wood"`) and its typed getters. Spectra
//! become linear sRGB: `rgb` as given, sampled and named spectra by the CIE integral of
//! [`crate::formats::mitsuba::spectrum`], blackbodies by Planck's law; illuminants other
//! than `rgb` are scaled to a luminance of 1, as pbrt-v4 scales lights to 1 nit.

use crate::formats::mitsuba::spectrum::{cie_xyz, spectrum_to_rgb, xyz_to_linear_srgb};
use crate::{Location, SceneError, SourceFile};
use penumbra_core::Rgb;
use std::cell::Cell;
use std::ops::Range;
use std::sync::Arc;

#[derive(Clone, Debug)]
pub enum Values {
    Nums(Vec<f64>),
    Strs(Vec<String>),
    Bools(Vec<bool>),
}

#[derive(Debug)]
pub struct Param {
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub span: Range<usize>,
    used: Cell<bool>,
}

impl Param {
    pub fn new(ty: String, name: String, values: Values, span: Range<usize>) -> Self {
        Param {
            ty,
            name,
            values,
            span,
            used: Cell::new(false),
        }
    }
}

pub struct Params {
    pub list: Vec<Param>,
    pub file: Arc<SourceFile>,
}

type Result<T> = std::result::Result<T, SceneError>;

/// What a colour parameter holds: a reflectance-like value, or an illuminant (which pbrt
/// scales to unit luminance unless it is given as `rgb`).
#[derive(Clone, Copy, PartialEq)]
pub enum ColorKind {
    Albedo,
    Illuminant,
}

impl Params {
    fn find(&self, name: &str) -> Option<&Param> {
        let p = self.list.iter().rev().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    pub fn error(&self, p: &Param, message: impl Into<String>) -> SceneError {
        SceneError::at(Location::new(&self.file, p.span.clone()), message)
    }

    /// Names of parameters nobody read.
    pub fn unused(&self) -> Vec<&str> {
        self.list
            .iter()
            .filter(|p| !p.used.get())
            .map(|p| p.name.as_str())
            .collect()
    }

    fn nums(&self, p: &Param, types: &[&str]) -> Result<Vec<f64>> {
        match (&p.values, types.contains(&p.ty.as_str())) {
            (Values::Nums(v), true) => Ok(v.clone()),
            _ => Err(self.error(p, format!("`{}` must be {}", p.name, types.join(" or ")))),
        }
    }

    pub fn float(&self, name: &str, default: f32) -> Result<f32> {
        match self.find(name) {
            None => Ok(default),
            Some(p) => match self.nums(p, &["float", "integer"])?[..] {
                [x] => Ok(x as f32),
                _ => Err(self.error(p, format!("`{name}` takes one number"))),
            },
        }
    }

    /// A list of numbers (`float` or `integer`).
    pub fn floats(&self, name: &str) -> Result<Option<Vec<f32>>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        Ok(Some(
            self.nums(p, &["float", "integer"])?
                .into_iter()
                .map(|x| x as f32)
                .collect(),
        ))
    }

    pub fn ints(&self, name: &str) -> Result<Option<Vec<i64>>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        let v = self.nums(p, &["integer"])?;
        if v.iter().any(|x| x.fract() != 0.0) {
            return Err(self.error(p, format!("`{name}` takes whole numbers")));
        }
        Ok(Some(v.into_iter().map(|x| x as i64).collect()))
    }

    pub fn int(&self, name: &str, default: i64) -> Result<i64> {
        match self.ints(name)? {
            None => Ok(default),
            Some(v) if v.len() == 1 => Ok(v[0]),
            Some(_) => Err(self.error(
                self.find(name).expect("read above"),
                format!("`{name}` takes one number"),
            )),
        }
    }

    pub fn string(&self, name: &str) -> Result<Option<String>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        match &p.values {
            Values::Strs(v) if v.len() == 1 && matches!(p.ty.as_str(), "string" | "texture" | "spectrum") => {
                Ok(Some(v[0].clone()))
            }
            _ => Err(self.error(p, format!("`{name}` takes one string"))),
        }
    }

    pub fn strings(&self, name: &str) -> Result<Option<Vec<String>>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        match &p.values {
            Values::Strs(v) => Ok(Some(v.clone())),
            _ => Err(self.error(p, format!("`{name}` takes strings"))),
        }
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool> {
        let Some(p) = self.find(name) else { return Ok(default) };
        match &p.values {
            Values::Bools(v) if v.len() == 1 => Ok(v[0]),
            _ => Err(self.error(p, format!("`{name}` takes true or false"))),
        }
    }

    /// `point3`, `normal`, `vector3` (or `point2`) lists as triples (pairs).
    pub fn points(&self, name: &str, dims: usize) -> Result<Option<Vec<Vec<f32>>>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        let types: &[&str] = if dims == 3 {
            &["point3", "normal", "normal3", "vector3", "point", "vector"]
        } else {
            &["point2", "float", "vector2"]
        };
        let v = self.nums(p, types)?;
        if v.len() % dims != 0 {
            return Err(self.error(p, format!("`{name}` has {} numbers, not a multiple of {dims}", v.len())));
        }
        Ok(Some(
            v.chunks(dims).map(|c| c.iter().map(|&x| x as f32).collect()).collect(),
        ))
    }

    /// Whether `name` is given as a texture reference: its name.
    pub fn texture_name(&self, name: &str) -> Option<String> {
        let p = self.list.iter().rev().find(|p| p.name == name && p.ty == "texture")?;
        p.used.set(true);
        match &p.values {
            Values::Strs(v) => v.first().cloned(),
            _ => None,
        }
    }

    /// A colour: `rgb`, `spectrum` (λ value pairs, a named spectrum, or one value),
    /// `blackbody` (a temperature), or a `float` grey.
    pub fn color(&self, name: &str, kind: ColorKind, named: &dyn Fn(&str) -> Option<Rgb>) -> Result<Option<Rgb>> {
        let Some(p) = self.list.iter().rev().find(|p| p.name == name && p.ty != "texture") else {
            return Ok(None);
        };
        p.used.set(true);
        let unit = |rgb: Rgb| {
            if kind == ColorKind::Illuminant {
                let y = rgb.luminance();
                if y > 0.0 {
                    return rgb * (1.0 / y);
                }
            }
            rgb
        };
        let rgb = match (p.ty.as_str(), &p.values) {
            ("rgb" | "color", Values::Nums(v)) if v.len() == 3 => Rgb::new(v[0] as f32, v[1] as f32, v[2] as f32),
            ("float", Values::Nums(v)) if v.len() == 1 => Rgb::splat(v[0] as f32),
            ("blackbody", Values::Nums(v)) if v.len() == 1 && v[0] > 0.0 => unit(blackbody(v[0])),
            // A constant spectrum: as a colour, that value; as a light, pbrt-v4's
            // equal-energy white of unit luminance (every spectral light is normalised so).
            ("spectrum", Values::Nums(v)) if v.len() == 1 && kind == ColorKind::Illuminant => {
                unit(spectrum_to_rgb(&[(360.0, v[0]), (830.0, v[0])]))
            }
            ("spectrum", Values::Nums(v)) if v.len() == 1 => Rgb::splat(v[0] as f32),
            ("spectrum", Values::Nums(v)) if v.len() >= 4 && v.len() % 2 == 0 => {
                let samples: Vec<(f64, f64)> = v.chunks(2).map(|c| (c[0], c[1])).collect();
                if samples.windows(2).any(|w| w[0].0 >= w[1].0) {
                    return Err(self.error(p, "a spectrum's wavelengths must increase"));
                }
                unit(spectrum_to_rgb(&samples))
            }
            ("spectrum", Values::Strs(v)) if v.len() == 1 => match named(&v[0]) {
                Some(c) => unit(c),
                None => {
                    return Err(self.error(
                        p,
                        format!("`{}` is neither a named spectrum nor a readable .spd file", v[0]),
                    ))
                }
            },
            _ => {
                return Err(self.error(
                    p,
                    format!("`{name}` is not a colour pbrt-v4 reads ({} with these values)", p.ty),
                ))
            }
        };
        if !(rgb.r.is_finite() && rgb.g.is_finite() && rgb.b.is_finite()) {
            return Err(self.error(p, format!("`{name}` is not a finite colour")));
        }
        Ok(Some(rgb))
    }
}

/// The linear sRGB of a blackbody at `kelvin` (Planck's law through the CIE matching
/// functions), normalised to its largest channel.
pub fn blackbody(kelvin: f64) -> Rgb {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let mut xyz = [0.0; 3];
    for nm in 360..=830 {
        let l = nm as f64 * 1e-9;
        let planck = 2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * kelvin)).exp() - 1.0));
        let cmf = cie_xyz(nm as f64);
        for c in 0..3 {
            xyz[c] += planck * cmf[c];
        }
    }
    let rgb = xyz_to_linear_srgb(xyz);
    let max = rgb.r.max(rgb.g).max(rgb.b);
    rgb * (1.0 / max)
}
