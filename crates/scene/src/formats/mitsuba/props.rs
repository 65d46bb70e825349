//! The parameters of one Mitsuba plugin element: its named children (`<float name=...>`,
//! `<rgb>`, `<spectrum>`, `<point>`, `<transform>`, nested textures and references) read
//! by type, each error pointing at the value at fault.

use super::spectrum::spectrum_to_rgb;
use super::{bsdfs, At, Reader, Result};
use glam::{Mat4, Vec3};
use penumbra_core::spectral::Tabulated;
use penumbra_core::{Rgb, Transform};
use penumbra_render::spectral::SpectrumValue;
use penumbra_render::Texture;
use roxmltree::Node;
use std::cell::RefCell;
use std::collections::HashSet;
use std::sync::Arc;

pub(super) struct Props<'a, 'input> {
    pub at: At<'a, 'input>,
    named: Vec<(&'a str, Node<'a, 'input>)>,
    used: RefCell<HashSet<&'a str>>,
}

impl<'a, 'input> Props<'a, 'input> {
    pub fn new(at: At<'a, 'input>) -> Self {
        let named = at
            .node
            .children()
            .filter(Node::is_element)
            .filter_map(|c| c.attribute("name").map(|n| (n, c)))
            .collect();
        Props {
            at,
            named,
            used: RefCell::new(HashSet::new()),
        }
    }

    /// The child named `name`, marked as read.
    pub fn get(&self, name: &str) -> Option<At<'a, 'input>> {
        let (n, node) = self.named.iter().rev().find(|(n, _)| *n == name)?;
        self.used.borrow_mut().insert(n);
        Some(self.at.with(*node))
    }

    /// Names never read.
    pub fn unused(&self) -> HashSet<&'a str> {
        let used = self.used.borrow();
        self.named
            .iter()
            .map(|(n, _)| *n)
            .filter(|n| !used.contains(n) && *n != "id")
            .collect()
    }

    /// Unnamed nested elements with tag `tag` (`bsdf`, `emitter`, `ref`, ...).
    pub fn nested(&self, tag: &str) -> Vec<At<'a, 'input>> {
        self.at
            .node
            .children()
            .filter(|c| c.is_element() && c.tag_name().name() == tag && c.attribute("name").is_none())
            .map(|c| self.at.with(c))
            .collect()
    }

    fn expect(&self, r: &Reader, v: At, tags: &[&str]) -> Result<()> {
        if tags.contains(&v.tag()) {
            return Ok(());
        }
        let name = r.attr(v, "name")?.unwrap_or_default();
        Err(v.error(format!(
            "`{name}` must be given as <{}>, found <{}>",
            tags.join("> or <"),
            v.tag()
        )))
    }

    pub fn float(&self, r: &Reader, name: &str) -> Result<Option<f32>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        self.expect(r, v, &["float", "integer"])?;
        number(r, v, "value").map(Some)
    }

    pub fn float_or(&self, r: &Reader, name: &str, default: f32) -> Result<f32> {
        Ok(self.float(r, name)?.unwrap_or(default))
    }

    pub fn int(&self, r: &Reader, name: &str) -> Result<Option<i64>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        self.expect(r, v, &["integer"])?;
        let s = r.require(v, "value")?;
        s.trim()
            .parse()
            .map(Some)
            .map_err(|_| r.attr_error(v, "value", format!("expected a whole number, found `{s}`")))
    }

    pub fn bool_or(&self, r: &Reader, name: &str, default: bool) -> Result<bool> {
        let Some(v) = self.get(name) else { return Ok(default) };
        self.expect(r, v, &["boolean"])?;
        match r.require(v, "value")?.trim() {
            "true" => Ok(true),
            "false" => Ok(false),
            s => Err(r.attr_error(v, "value", format!("expected true or false, found `{s}`"))),
        }
    }

    pub fn string(&self, r: &Reader, name: &str) -> Result<Option<(String, At<'a, 'input>)>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        self.expect(r, v, &["string"])?;
        Ok(Some((r.require(v, "value")?, v)))
    }

    /// A point or vector: `x`, `y`, `z` attributes or `value="x, y, z"`.
    pub fn vec3(&self, r: &Reader, name: &str) -> Result<Option<Vec3>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        self.expect(r, v, &["point", "vector"])?;
        vec3_of(r, v).map(Some)
    }

    /// A colour: `<rgb>`, `<spectrum>` or a `<float>` grey.
    pub fn color(&self, r: &mut Reader, name: &str) -> Result<Option<Rgb>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        self.expect(r, v, &["rgb", "spectrum", "float"])?;
        color_of(r, v).map(Some)
    }

    pub fn color_or(&self, r: &mut Reader, name: &str, default: f32) -> Result<Rgb> {
        Ok(self.color(r, name)?.unwrap_or(Rgb::splat(default)))
    }

    /// The spectrum `name` gives by wavelength (a `<spectrum value="λ:v, ...">`), if it does.
    pub fn spectrum(&self, r: &mut Reader, name: &str) -> Result<Option<SpectrumValue>> {
        let Some(v) = self.get(name).filter(|v| v.tag() == "spectrum") else {
            return Ok(None);
        };
        if v.node.has_attribute("filename") {
            return Ok(None);
        }
        let Some(samples) = sampled(r, v)? else {
            return Ok(None);
        };
        let points: Vec<(f32, f32)> = samples.iter().map(|&(l, x)| (l as f32, x as f32)).collect();
        let t = Tabulated::new(&points).map_err(|e| r.attr_error(v, "value", e))?;
        Ok(Some(SpectrumValue::Tabulated(Arc::new(t))))
    }

    /// A colour or a texture (nested, or a `<ref>` to one); `data` textures (roughness,
    /// weights) read 8-bit images without the sRGB curve.
    pub fn texture(&self, r: &mut Reader, name: &str, default: f32, data: bool) -> Result<Texture> {
        let Some(v) = self.get(name) else {
            return Ok(Texture::Constant(Rgb::splat(default)));
        };
        match v.tag() {
            "texture" => bsdfs::texture(r, v, data),
            "ref" => {
                let id = r.require(v, "id")?;
                r.textures.get(&id).cloned().ok_or_else(|| {
                    r.attr_error(
                        v,
                        "id",
                        format!("no texture has the id `{id}` (textures are defined before use)"),
                    )
                })
            }
            _ => {
                self.expect(r, v, &["rgb", "spectrum", "float", "texture", "ref"])?;
                Ok(Texture::Constant(color_of(r, v)?))
            }
        }
    }

    /// The transform `name` (`to_world`), the identity when absent.
    pub fn transform(&self, r: &Reader, name: &str) -> Result<Transform> {
        let Some(v) = self.get(name) else {
            return Ok(Transform::IDENTITY);
        };
        self.expect(r, v, &["transform"])?;
        transform_of(r, v)
    }
}

/// The number in attribute `attr`.
pub(super) fn number(r: &Reader, v: At, attr: &str) -> Result<f32> {
    let s = r.require(v, attr)?;
    match s.trim().parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(r.attr_error(v, attr, format!("expected a number, found `{s}`"))),
    }
}

/// Numbers separated by commas and/or spaces.
fn numbers(r: &Reader, v: At, attr: &str) -> Result<Vec<f32>> {
    let s = r.require(v, attr)?;
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| match t.parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(r.attr_error(v, attr, format!("expected numbers, found `{t}`"))),
        })
        .collect()
}

fn vec3_of(r: &Reader, v: At) -> Result<Vec3> {
    if v.node.has_attribute("value") {
        let n = numbers(r, v, "value")?;
        return match n[..] {
            [x] => Ok(Vec3::splat(x)),
            [x, y, z] => Ok(Vec3::new(x, y, z)),
            _ => Err(r.attr_error(v, "value", format!("expected 3 numbers, found {}", n.len()))),
        };
    }
    let axis = |a: &str| -> Result<f32> {
        if v.node.has_attribute(a) {
            number(r, v, a)
        } else {
            Ok(0.0)
        }
    };
    Ok(Vec3::new(axis("x")?, axis("y")?, axis("z")?))
}

/// `<rgb value="r, g, b">` (or one grey value), `<spectrum value="v">` (uniform) or
/// `<spectrum value="λ1:v1, λ2:v2, ...">` (sampled; [`spectrum_to_rgb`]), `<float>` grey.
fn color_of(r: &mut Reader, v: At) -> Result<Rgb> {
    match v.tag() {
        "spectrum" => {
            if v.node.has_attribute("filename") {
                r.warn_once(
                    "spectrum.filename",
                    format!("{}: spectra from files are not supported: read as 1 (white)", v.place()),
                );
                return Ok(Rgb::WHITE);
            }
            match sampled(r, v)? {
                Some(samples) => Ok(spectrum_to_rgb(&samples)),
                None => Ok(Rgb::splat(number(r, v, "value")?)),
            }
        }
        "rgb" => {
            let n = numbers(r, v, "value")?;
            match n[..] {
                [g] => Ok(Rgb::splat(g)),
                [red, green, blue] => Ok(Rgb::new(red, green, blue)),
                _ => Err(r.attr_error(v, "value", format!("expected 3 numbers, found {}", n.len()))),
            }
        }
        _ => Ok(Rgb::splat(number(r, v, "value")?)),
    }
}

/// The wavelength:value pairs of a `<spectrum>` given by wavelength; `None` for a uniform
/// one.
fn sampled(r: &mut Reader, v: At) -> Result<Option<Vec<(f64, f64)>>> {
    let s = r.require(v, "value")?;
    if !s.contains(':') {
        return Ok(None);
    }
    let mut samples = Vec::new();
    for pair in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let parsed = pair
            .split_once(':')
            .and_then(|(l, x)| Some((l.trim().parse::<f64>().ok()?, x.trim().parse::<f64>().ok()?)));
        match parsed {
            Some((l, x)) if l.is_finite() && x.is_finite() && samples.last().is_none_or(|p: &(f64, f64)| p.0 < l) => {
                samples.push((l, x))
            }
            _ => {
                return Err(r.attr_error(
                    v,
                    "value",
                    format!("`{pair}`: expected wavelength:value pairs with increasing wavelengths"),
                ))
            }
        }
    }
    r.sampled_spectra = true;
    Ok(Some(samples))
}

/// A `<transform>`: its steps applied in order, each after the ones before.
fn transform_of(r: &Reader, v: At) -> Result<Transform> {
    let mut t = Transform::IDENTITY;
    for step in v.node.children().filter(Node::is_element) {
        let s = v.with(step);
        let singular = || s.error(format!("this <{}> is singular", s.tag()));
        let next = match s.tag() {
            "translate" => Transform::translate(vec3_of(r, s)?),
            "scale" => {
                let k = vec3_of(r, s)?;
                // `<scale x="2"/>` leaves the other axes alone.
                let k = if s.node.has_attribute("value") {
                    k
                } else {
                    Vec3::new(
                        if s.node.has_attribute("x") { k.x } else { 1.0 },
                        if s.node.has_attribute("y") { k.y } else { 1.0 },
                        if s.node.has_attribute("z") { k.z } else { 1.0 },
                    )
                };
                Transform::scale(k).ok_or_else(singular)?
            }
            "rotate" => {
                let axis = vec3_of(r, s)?;
                Transform::rotate(axis, number(r, s, "angle")?).ok_or_else(|| s.error("the rotation axis is zero"))?
            }
            "matrix" => {
                let n = numbers(r, s, "value")?;
                let m = match n.len() {
                    16 => Mat4::from_cols_array(&n.try_into().expect("16 numbers")).transpose(),
                    9 => {
                        let m3 = glam::Mat3::from_cols_array(&n.try_into().expect("9 numbers")).transpose();
                        Mat4::from_mat3(m3)
                    }
                    k => return Err(r.attr_error(s, "value", format!("expected 16 (or 9) numbers, found {k}"))),
                };
                Transform::from_matrix(m).ok_or_else(singular)?
            }
            "lookat" => {
                let p = |a: &str| -> Result<Vec3> {
                    let n = numbers(r, s, a)?;
                    match n[..] {
                        [x, y, z] => Ok(Vec3::new(x, y, z)),
                        _ => Err(r.attr_error(s, a, "expected 3 numbers")),
                    }
                };
                let origin = p("origin")?;
                let target = p("target")?;
                let up = if s.node.has_attribute("up") { p("up")? } else { Vec3::Y };
                mitsuba_look_at(origin, target, up)
                    .ok_or_else(|| s.error("the view direction is zero or parallel to `up`"))?
            }
            other => {
                return Err(s.error(format!(
                    "<{other}> is not a transform step (translate, rotate, scale, matrix, lookat)"
                )))
            }
        };
        t = t.then(next);
    }
    Ok(t)
}

/// Mitsuba's look-at: columns (up x dir, up, dir, origin), the camera looking along +z.
fn mitsuba_look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Transform> {
    let dir = (target - origin).try_normalize()?;
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Transform::from_matrix(Mat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}
