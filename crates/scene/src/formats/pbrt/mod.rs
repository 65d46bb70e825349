//! pbrt-v4 scenes (`.pbrt`): a tokenizer (`tokens.rs`), parameter lists (`params.rs`) and
//! the directives, with pbrt's graphics state: the current transform (each step applied
//! before the ones already there, as pbrt multiplies on the right), `AttributeBegin/End`,
//! named coordinate systems, `ReverseOrientation`, named materials, textures, the area
//! light, `ObjectBegin/End/Instance`, `Include`/`Import`. The objects themselves are made
//! in `objects.rs` and `shapes.rs`.
//!
//! pbrt's camera is left-handed (image x along camera +x, looking down +z): its view is
//! rendered with [`crate::desc::CameraDesc::mirrored`] where our right-handed look-at would
//! mirror it. Errors name the file, line and column of the token at fault.

mod materials;
mod media;
mod objects;
mod params;
mod shapes;
#[cfg(test)]
mod tests;
mod tokens;

use crate::desc::{CameraDesc, CameraKind, Emission, RenderDesc, ShapeDesc};
use crate::{Location, SceneDesc, SceneError, SourceFile};
use glam::{Mat4, Vec3};
use params::{Param, Params, Values};
use penumbra_core::{SamplerKind, Transform};
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::IntegratorKind;
use penumbra_render::{Filter, Texture};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tokens::{Tok, Token};

type Result<T> = std::result::Result<T, SceneError>;

/// Reads the pbrt-v4 scene at `path`.
pub fn read(path: &Path) -> Result<SceneDesc> {
    let mut r = Reader {
        desc: SceneDesc::empty(),
        root: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
        state: State::default(),
        saved: Vec::new(),
        named_coords: HashMap::new(),
        named_materials: HashMap::new(),
        media: HashMap::new(),
        textures: HashMap::new(),
        objects: HashMap::new(),
        object: None,
        files: Vec::new(),
        warned: BTreeMap::new(),
        default_material: None,
        exposure_time: 1.0,
        iso: 100.0,
    };
    r.desc.render = RenderDesc {
        width: 1280,
        height: 720,
        spp: 16,
        integrator: IntegratorKind::Path,
        max_depth: 6,
        sampler: SamplerKind::Sobol,
        filter: Filter::Gaussian {
            radius: 1.5,
            sigma: 0.5,
        },
        ..RenderDesc::default()
    };
    r.desc.camera = CameraDesc {
        kind: CameraKind::Perspective {
            fov: 90.0,
            fov_axis: FovAxis::Smaller,
            aperture_radius: 0.0,
            focus_distance: None,
        },
        position: Vec3::ZERO,
        target: Vec3::Z,
        up: Vec3::Y,
        mirrored: true,
        location: None,
    };
    r.file(path, None)?;
    if r.desc.shapes.is_empty() {
        r.warn(
            "scene",
            "the scene has no shape: the image shows only its lights".into(),
        );
    }
    r.desc.warnings = r.warned.into_values().collect();
    Ok(r.desc)
}

/// pbrt's graphics state: what `AttributeBegin` saves.
#[derive(Clone)]
struct State {
    ctm: Transform,
    reverse: bool,
    /// Index of the current material; `None`: pbrt's default (diffuse 0.5).
    material: Option<usize>,
    area: Option<Emission>,
    /// The current `MediumInterface`: the media inside and outside.
    media: (Option<u32>, Option<u32>),
}

impl Default for State {
    fn default() -> Self {
        State {
            ctm: Transform::IDENTITY,
            reverse: false,
            material: None,
            area: None,
            media: (None, None),
        }
    }
}

struct Reader {
    desc: SceneDesc,
    root: PathBuf,
    state: State,
    saved: Vec<(State, Location)>,
    named_coords: HashMap<String, Transform>,
    named_materials: HashMap<String, usize>,
    /// Media by name: their index in the scene's media, `None` for kinds not read.
    media: HashMap<String, Option<u32>>,
    textures: HashMap<String, Texture>,
    objects: HashMap<String, Vec<ShapeDesc>>,
    /// The instance being defined, and the shapes before it began.
    object: Option<(String, Vec<ShapeDesc>)>,
    files: Vec<PathBuf>,
    warned: BTreeMap<String, String>,
    /// The grey diffuse of shapes without a material, once made.
    default_material: Option<usize>,
    /// pbrt-v4's imaging ratio, exposure time × ISO / 100 (the camera's `shutterclose` -
    /// `shutteropen` and the film's `iso`): its sensor scales the image by it; we scale
    /// every emitter instead, which is the same for light transport that is linear.
    exposure_time: f32,
    iso: f32,
}

impl Reader {
    fn imaging_ratio(&self) -> f32 {
        self.exposure_time * self.iso / 100.0
    }
}

/// A cursor over one file's tokens.
struct Cursor<'t> {
    file: Arc<SourceFile>,
    toks: &'t [Token],
    i: usize,
}

impl Cursor<'_> {
    fn at(&self, span: std::ops::Range<usize>) -> Location {
        Location::new(&self.file, span)
    }

    fn error_here(&self, message: impl Into<String>) -> SceneError {
        let span = match self.toks.get(self.i) {
            Some(t) => t.span.clone(),
            None => self.file.text.len()..self.file.text.len(),
        };
        SceneError::at(self.at(span), message)
    }

    fn string(&mut self, what: &str) -> Result<String> {
        match self.toks.get(self.i).map(|t| &t.tok) {
            Some(Tok::Str(s)) => {
                self.i += 1;
                Ok(s.clone())
            }
            _ => Err(self.error_here(format!("expected {what} (a quoted string)"))),
        }
    }

    /// `n` numbers, bare or in brackets.
    fn numbers(&mut self, n: usize, what: &str) -> Result<Vec<f64>> {
        let bracket = matches!(self.toks.get(self.i).map(|t| &t.tok), Some(Tok::Open));
        if bracket {
            self.i += 1;
        }
        let mut out = Vec::with_capacity(n);
        while out.len() < n {
            match self.toks.get(self.i).map(|t| &t.tok) {
                Some(Tok::Num(x)) => {
                    out.push(*x);
                    self.i += 1;
                }
                _ => return Err(self.error_here(format!("{what} takes {n} numbers, found {}", out.len()))),
            }
        }
        if bracket {
            match self.toks.get(self.i).map(|t| &t.tok) {
                Some(Tok::Close) => self.i += 1,
                _ => return Err(self.error_here(format!("{what} takes {n} numbers: expected `]`"))),
            }
        }
        Ok(out)
    }

    /// A parameter list: `"type name" value` pairs until the next directive.
    fn params(&mut self) -> Result<Params> {
        let mut list = Vec::new();
        while let Some(Token {
            tok: Tok::Str(decl),
            span,
        }) = self.toks.get(self.i)
        {
            let start = span.start;
            let mut words = decl.split_whitespace();
            let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
                return Err(self.error_here(format!("`{decl}` is not a parameter declaration (\"type name\")")));
            };
            let (ty, name) = (ty.to_string(), name.to_string());
            self.i += 1;
            let mut nums = Vec::new();
            let mut strs = Vec::new();
            let mut bools = Vec::new();
            let bracket = matches!(self.toks.get(self.i).map(|t| &t.tok), Some(Tok::Open));
            if bracket {
                self.i += 1;
            }
            while let Some(t) = self.toks.get(self.i) {
                match &t.tok {
                    Tok::Num(x) => nums.push(*x),
                    Tok::Str(s) if ty == "bool" && (s == "true" || s == "false") => bools.push(s == "true"),
                    Tok::Str(s) => strs.push(s.clone()),
                    Tok::Word(w) if w == "true" || w == "false" => bools.push(w == "true"),
                    Tok::Close if bracket => {
                        self.i += 1;
                        break;
                    }
                    _ if bracket => return Err(self.error_here(format!("unexpected token in the values of `{name}`"))),
                    _ => break,
                }
                self.i += 1;
                if !bracket {
                    break;
                }
            }
            let end = self.toks[self.i - 1].span.end;
            let values = match (nums.is_empty(), strs.is_empty(), bools.is_empty()) {
                (false, true, true) => Values::Nums(nums),
                (true, false, true) => Values::Strs(strs),
                (true, true, false) => Values::Bools(bools),
                (true, true, true) => {
                    return Err(SceneError::at(self.at(start..end), format!("`{name}` has no value")));
                }
                _ => {
                    return Err(SceneError::at(
                        self.at(start..end),
                        format!("`{name}` mixes numbers and strings"),
                    ))
                }
            };
            list.push(Param::new(ty, name, values, start..end));
        }
        Ok(Params {
            list,
            file: self.file.clone(),
        })
    }
}

impl Reader {
    fn warn(&mut self, kind: &str, text: String) {
        self.warned.entry(kind.to_string()).or_insert(text);
    }

    /// A file named in the scene: relative to the main file's folder, else to `file`'s.
    fn resolve(&self, file: &SourceFile, name: &str) -> PathBuf {
        let main = self.root.join(name);
        if main.exists() {
            return main;
        }
        let here = file.path.parent().unwrap_or(Path::new(".")).join(name);
        if here.exists() {
            here
        } else {
            main
        }
    }

    fn file(&mut self, path: &Path, from: Option<Location>) -> Result<()> {
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        let fail = |message: String| match &from {
            Some(l) => SceneError::at(l.clone(), message),
            None => SceneError::io(path, message),
        };
        if self.files.contains(&canonical) {
            return Err(fail(format!("{} includes itself", path.display())));
        }
        let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read {}: {e}", path.display())))?;
        let file = SourceFile::new(path, text);
        let toks = tokens::tokenize(&file.text).map_err(|(span, m)| SceneError::at(Location::new(&file, span), m))?;
        self.files.push(canonical);
        let mut c = Cursor {
            file,
            toks: &toks,
            i: 0,
        };
        while c.i < c.toks.len() {
            self.directive(&mut c)?;
        }
        self.files.pop();
        Ok(())
    }

    fn directive(&mut self, c: &mut Cursor) -> Result<()> {
        let Token { tok, span } = c.toks[c.i].clone();
        let Tok::Word(name) = tok else {
            return Err(c.error_here("expected a directive (e.g. Shape, LookAt, WorldBegin)"));
        };
        c.i += 1;
        let here = c.at(span);
        match name.as_str() {
            "WorldBegin" => {
                self.state.ctm = Transform::IDENTITY;
                self.named_coords.insert("world".into(), Transform::IDENTITY);
            }
            "MakeNamedMedium" => {
                let n = c.string("a medium name")?;
                let p = c.params()?;
                media::make_named(self, n, &p, here)?;
            }
            "MediumInterface" => {
                let inside = c.string("a medium name")?;
                let outside = match c.toks.get(c.i).map(|t| &t.tok) {
                    Some(Tok::Str(s)) => {
                        let s = s.clone();
                        c.i += 1;
                        s
                    }
                    _ => inside.clone(),
                };
                self.state.media = (
                    media::named(self, &inside, &here)?,
                    media::named(self, &outside, &here)?,
                );
            }
            "WorldEnd" | "Accelerator" | "Option" | "ColorSpace" => {
                let (what, args) = match name.as_str() {
                    "Option" => ("options", c.params().map(|_| ())),
                    "ColorSpace" => ("color spaces", c.string("a colour space").map(|_| ())),
                    "Accelerator" => (
                        "accelerator choices",
                        c.string("a type").and_then(|_| c.params()).map(|_| ()),
                    ),
                    _ => ("WorldEnd", Ok(())),
                };
                args?;
                if name != "WorldEnd" {
                    self.warn(&name, format!("{here}: {what} are not supported: `{name}` is ignored"));
                }
            }
            "AttributeBegin" | "TransformBegin" => self.saved.push((self.state.clone(), here)),
            "AttributeEnd" | "TransformEnd" => {
                let (state, _) = self
                    .saved
                    .pop()
                    .ok_or_else(|| SceneError::at(here, format!("`{name}` without a matching `AttributeBegin`")))?;
                if name == "TransformEnd" {
                    self.state.ctm = state.ctm;
                } else {
                    self.state = state;
                }
            }
            "Attribute" => {
                c.string("a target")?;
                c.params()?;
                self.warn(
                    "Attribute",
                    format!("{here}: `Attribute` defaults are not supported: ignored"),
                );
            }
            "Identity" => self.state.ctm = Transform::IDENTITY,
            "Translate" => {
                let v = c.numbers(3, "Translate")?;
                self.concat(Transform::translate(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)));
            }
            "Scale" => {
                let v = c.numbers(3, "Scale")?;
                let t = Transform::scale(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32))
                    .ok_or_else(|| SceneError::at(here, "a Scale by zero"))?;
                self.concat(t);
            }
            "Rotate" => {
                let v = c.numbers(4, "Rotate")?;
                let t = Transform::rotate(Vec3::new(v[1] as f32, v[2] as f32, v[3] as f32), v[0] as f32)
                    .ok_or_else(|| SceneError::at(here, "a Rotate about a zero axis"))?;
                self.concat(t);
            }
            "LookAt" => {
                let v: Vec<f32> = c.numbers(9, "LookAt")?.into_iter().map(|x| x as f32).collect();
                let (eye, look, up) = (
                    Vec3::new(v[0], v[1], v[2]),
                    Vec3::new(v[3], v[4], v[5]),
                    Vec3::new(v[6], v[7], v[8]),
                );
                let t = look_at(eye, look, up)
                    .ok_or_else(|| SceneError::at(here, "LookAt: the view direction is zero or parallel to up"))?;
                self.concat(t);
            }
            "Transform" | "ConcatTransform" => {
                let v: Vec<f32> = c.numbers(16, &name)?.into_iter().map(|x| x as f32).collect();
                let m = Mat4::from_cols_array(&v.try_into().expect("16 numbers"));
                let t = Transform::from_matrix(m)
                    .ok_or_else(|| SceneError::at(here, format!("{name}: a singular or projective matrix")))?;
                if name == "Transform" {
                    self.state.ctm = t;
                } else {
                    self.concat(t);
                }
            }
            "CoordinateSystem" => {
                let n = c.string("a name")?;
                self.named_coords.insert(n, self.state.ctm);
            }
            "CoordSysTransform" => {
                let n = c.string("a name")?;
                match self.named_coords.get(&n) {
                    Some(&t) => self.state.ctm = t,
                    None => self.warn(
                        &format!("coordsys {n}"),
                        format!("{here}: no coordinate system `{n}`: ignored"),
                    ),
                }
            }
            "ReverseOrientation" => self.state.reverse = !self.state.reverse,
            "Include" | "Import" => {
                let n = c.string("a file name")?;
                let path = self.resolve(&c.file, &n);
                self.file(&path, Some(here))?;
            }
            "Camera" => {
                let kind = c.string("a camera type")?;
                let p = c.params()?;
                objects::camera(self, &kind, &p, here)?;
                self.desc.camera_medium = self.state.media.1;
            }
            "Film" | "Sampler" | "PixelFilter" | "Integrator" => {
                let kind = c.string("a type")?;
                let p = c.params()?;
                objects::setting(self, &name, &kind, &p, here)?;
            }
            "MakeNamedMaterial" => {
                let n = c.string("a material name")?;
                let p = c.params()?;
                let kind = p
                    .string("type")?
                    .ok_or_else(|| SceneError::at(here.clone(), "MakeNamedMaterial needs a \"string type\""))?;
                let index = materials::material(self, &kind, &p, here)?;
                self.named_materials.insert(n, index);
            }
            "Material" => {
                let kind = c.string("a material type")?;
                let p = c.params()?;
                self.state.material = Some(materials::material(self, &kind, &p, here)?);
            }
            "NamedMaterial" => {
                let n = c.string("a material name")?;
                let index = *self.named_materials.get(&n).ok_or_else(|| {
                    SceneError::at(
                        here,
                        format!("no material is named `{n}` (MakeNamedMaterial comes first)"),
                    )
                })?;
                self.state.material = Some(index);
            }
            "Texture" => {
                let n = c.string("a texture name")?;
                c.string("a texture type (float or spectrum)")?;
                let class = c.string("a texture class")?;
                let p = c.params()?;
                let t = objects::texture(self, &class, &p, &c.file, here)?;
                self.textures.insert(n, t);
            }
            "LightSource" => {
                let kind = c.string("a light type")?;
                let p = c.params()?;
                objects::light(self, &kind, &p, &c.file, here)?;
            }
            "AreaLightSource" => {
                let kind = c.string("an area light type")?;
                let p = c.params()?;
                self.state.area = objects::area_light(self, &kind, &p, here)?;
            }
            "Shape" => {
                let kind = c.string("a shape type")?;
                let p = c.params()?;
                if let Some(shape) = shapes::shape(self, &kind, &p, &c.file, here)? {
                    self.desc.shapes.push(shape);
                }
            }
            "ObjectBegin" => {
                let n = c.string("an object name")?;
                self.saved.push((self.state.clone(), here.clone()));
                let before = std::mem::take(&mut self.desc.shapes);
                if self.object.replace((n, before)).is_some() {
                    return Err(SceneError::at(here, "ObjectBegin inside another object"));
                }
            }
            "ObjectEnd" => {
                let (n, before) = self
                    .object
                    .take()
                    .ok_or_else(|| SceneError::at(here.clone(), "ObjectEnd without ObjectBegin"))?;
                let shapes = std::mem::replace(&mut self.desc.shapes, before);
                self.objects.insert(n, shapes);
                let (state, _) = self
                    .saved
                    .pop()
                    .ok_or_else(|| SceneError::at(here, "ObjectEnd without ObjectBegin"))?;
                self.state = state;
            }
            "ObjectInstance" => {
                let n = c.string("an object name")?;
                let shapes = self
                    .objects
                    .get(&n)
                    .ok_or_else(|| SceneError::at(here, format!("no object is named `{n}`")))?;
                let placed: Vec<ShapeDesc> = shapes
                    .iter()
                    .map(|s| ShapeDesc {
                        transform: s.transform.then(self.state.ctm),
                        ..s.clone()
                    })
                    .collect();
                self.desc.shapes.extend(placed);
            }
            other => return Err(SceneError::at(here, format!("unknown directive `{other}`"))),
        }
        Ok(())
    }

    /// The current transform followed by `t` on the object side (pbrt's `ctm * t`).
    fn concat(&mut self, t: Transform) {
        self.state.ctm = t.then(self.state.ctm);
    }
}

/// pbrt's `LookAt`: the camera-from-world transform of a camera at `eye` looking at
/// `look`, its x axis `up x dir` (left-handed).
fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Option<Transform> {
    let dir = (look - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0));
    Transform::from_matrix(world_from_camera).map(Transform::inverse)
}
