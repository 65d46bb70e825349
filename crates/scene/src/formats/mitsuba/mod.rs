//! Mitsuba 3 XML scenes (`version="3.x"`), read with `roxmltree`: `<default>` parameters
//! and `$name` substitution (also set from the command line, `-D name=value`),
//! `<include>`, ids and `<ref>`, transforms, and the shapes, BSDFs, textures, emitters,
//! sensor, film, sampler and integrator (`plugins.rs`, `bsdfs.rs`, `emitters.rs`,
//! `shapes.rs`). Spectra become linear sRGB as in Mitsuba's RGB variants ([`spectrum`]).
//!
//! Every error names the file, line and column of the element or attribute at fault, in
//! included files too. A plugin or parameter we do not support is one warning per kind,
//! saying what we do instead; only what leaves nothing meaningful to render is an error.

mod bsdfs;
mod emitters;
mod media;
mod plugins;
mod props;
mod shapes;
pub mod spectrum;
#[cfg(test)]
mod tests;

use crate::{Location, SceneDesc, SceneError, SourceFile};
use penumbra_render::{Material, Texture};
use props::Props;
use roxmltree::Node;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// Reads the Mitsuba scene at `path`; `defines` set parameters as `-D name=value` does
/// (before the file's `<default>`s, which they override).
pub fn read(path: &Path, defines: &[(String, String)]) -> Result<SceneDesc> {
    let mut reader = Reader {
        desc: SceneDesc::empty(),
        params: defines.iter().cloned().collect(),
        bsdfs: HashMap::new(),
        textures: HashMap::new(),
        media: HashMap::new(),
        warned: BTreeMap::new(),
        stack: Vec::new(),
        seen_sensor: false,
        folders: vec![path.parent().unwrap_or(Path::new(".")).to_path_buf()],
        area_emitters: HashMap::new(),
        pending: Vec::new(),
        default_material: None,
        spectra: Default::default(),
        sampled_spectra: false,
    };
    reader.desc.render = plugins::default_render();
    reader.desc.camera = plugins::default_camera();
    reader.file(path, None)?;
    reader.resolve_pending()?;
    if reader.desc.shapes.is_empty() {
        reader.warn_once(
            "scene",
            "the scene has no shape: the image shows only its lights and background",
        );
    }
    reader.desc.warnings = reader.warned.into_values().collect();
    // Spectra given by wavelength ask for spectral rendering (as `cbox-spectral.xml`,
    // written for Mitsuba's spectral variants); `--rgb` overrides.
    reader.desc.render.spectral = reader.sampled_spectra;
    Ok(reader.desc)
}

/// An element in its file: what every error and warning needs.
#[derive(Clone, Copy)]
struct At<'a, 'input> {
    pub file: &'a Arc<SourceFile>,
    pub node: Node<'a, 'input>,
}

impl<'a, 'input> At<'a, 'input> {
    pub fn with(self, node: Node<'a, 'input>) -> Self {
        At { file: self.file, node }
    }

    pub fn location(&self) -> Location {
        Location::new(self.file, self.node.range())
    }

    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::at(self.location(), message)
    }

    /// `file:line:column` of the element, for warnings.
    pub fn place(&self) -> String {
        self.location().to_string()
    }

    /// The element's name (`shape`, `float`, ...).
    pub fn tag(&self) -> &'a str {
        self.node.tag_name().name()
    }
}

struct Reader {
    pub desc: SceneDesc,
    /// `$name` values: the command line's, then the `<default>`s.
    params: HashMap<String, String>,
    /// BSDFs by id: their material index.
    pub bsdfs: HashMap<String, usize>,
    /// Textures by id.
    pub textures: HashMap<String, Texture>,
    /// Media by id: their index in the scene's media.
    pub media: HashMap<String, u32>,
    /// One warning per kind: kind -> text, in kind order.
    warned: BTreeMap<String, String>,
    /// The files being read, for cyclic includes.
    stack: Vec<PathBuf>,
    seen_sensor: bool,
    /// Where files are looked for: the scene's folder, then each `<path>`.
    folders: Vec<PathBuf>,
    /// Area emitters defined at the top level with an id, for shapes that refer to them.
    pub area_emitters: HashMap<String, crate::desc::Emission>,
    /// References of shapes to ids not defined yet (Mitsuba resolves them after reading
    /// the whole scene): shape index, id, where.
    pub pending: Vec<(usize, String, Location)>,
    /// The grey diffuse of shapes without a BSDF, once made.
    pub default_material: Option<usize>,
    /// The spectra of the material being read, by parameter (taken by `add_material`).
    pub spectra: penumbra_render::spectral::MaterialSpectra,
    /// Whether any spectrum was given by wavelength (the scene asks for spectral rendering).
    pub sampled_spectra: bool,
}

impl Reader {
    /// Warns once for `kind` (a plugin or parameter name), however often it comes.
    pub fn warn_once(&mut self, kind: &str, text: impl Into<String>) {
        self.warned.entry(kind.to_string()).or_insert_with(|| text.into());
    }

    /// Attribute `name` of the element with `$parameters` substituted.
    pub fn attr(&self, at: At, name: &str) -> Result<Option<String>> {
        let Some(attr) = at.node.attribute_node(name) else {
            return Ok(None);
        };
        let raw = attr.value();
        if !raw.contains('$') {
            return Ok(Some(raw.to_string()));
        }
        let mut out = String::new();
        let mut rest = raw;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let tail = &rest[i + 1..];
            let len = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(tail.len());
            let key = &tail[..len];
            match self.params.get(key) {
                Some(v) if !key.is_empty() => out.push_str(v),
                _ => {
                    return Err(SceneError::at(
                        Location::new(at.file, attr.range_value()),
                        format!(
                        "`${key}` is not defined: give it a <default name=\"{key}\" value=\"...\"/> or -D {key}=VALUE"
                    ),
                    )
                    .label("this parameter"))
                }
            }
            rest = &tail[len..];
        }
        out.push_str(rest);
        Ok(Some(out))
    }

    /// Attribute `name`, which must be there.
    pub fn require(&self, at: At, name: &str) -> Result<String> {
        self.attr(at, name)?
            .ok_or_else(|| at.error(format!("<{}> needs a `{name}` attribute", at.tag())))
    }

    /// An error at attribute `name` of the element (or at the element without it).
    pub fn attr_error(&self, at: At, name: &str, message: impl Into<String>) -> SceneError {
        match at.node.attribute_node(name) {
            Some(a) => SceneError::at(Location::new(at.file, a.range_value()), message),
            None => at.error(message),
        }
    }

    /// Reads one file: the top level of a scene, or an included one.
    fn file(&mut self, path: &Path, included_at: Option<At>) -> Result<()> {
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        if self.stack.contains(&canonical) {
            let at = included_at.expect("the first file includes nothing yet");
            return Err(self.attr_error(at, "filename", format!("{} includes itself", path.display())));
        }
        let text = std::fs::read_to_string(path).map_err(|e| match included_at {
            Some(at) => self.attr_error(at, "filename", format!("cannot read {}: {e}", path.display())),
            None => SceneError::io(path, e),
        })?;
        let file = SourceFile::new(path, text);
        let doc = roxmltree::Document::parse(&file.text).map_err(|e| {
            let pos = e.pos();
            let offset = line_col_offset(&file.text, pos.row as usize, pos.col as usize);
            SceneError::at(
                Location::new(&file, offset..offset),
                format!("not well-formed XML: {e}"),
            )
        })?;
        let root = doc.root_element();
        let at = At {
            file: &file,
            node: root,
        };
        if root.tag_name().name() != "scene" {
            return Err(at.error(format!(
                "the root element is <{}>; a Mitsuba scene is a <scene>",
                at.tag()
            )));
        }
        match self.attr(at, "version")? {
            Some(v) if v.split('.').next() == Some("3") => {}
            Some(v) => self.warn_once(
                "version",
                format!(
                    "{}: scene version {v}: read as Mitsuba 3 (0.x and 2.x plugin names may differ)",
                    at.place()
                ),
            ),
            None => return Err(at.error("<scene> needs a `version` attribute (e.g. version=\"3.0.0\")")),
        }
        self.stack.push(canonical);
        for child in root.children().filter(Node::is_element) {
            self.top_level(at.with(child))?;
        }
        self.stack.pop();
        Ok(())
    }

    /// One element at the top level of a scene.
    fn top_level(&mut self, at: At) -> Result<()> {
        match at.tag() {
            "default" => {
                let name = self.require(at, "name")?;
                let value = self.require(at, "value")?;
                self.params.entry(name).or_insert(value);
            }
            "path" => {
                let folder = self.require(at, "value")?;
                let folder = self.folders[0].join(folder);
                self.folders.push(folder);
            }
            "include" => {
                let name = self.require(at, "filename")?;
                let path = self.resolve(at, &name);
                self.file(&path, Some(at))?;
            }
            "integrator" => plugins::integrator(self, at)?,
            "sensor" => {
                if self.seen_sensor {
                    self.warn_once(
                        "second sensor",
                        format!("{}: only the first <sensor> is used", at.place()),
                    );
                } else {
                    self.seen_sensor = true;
                    plugins::sensor(self, at)?;
                }
            }
            "bsdf" => {
                let material = bsdfs::bsdf(self, at)?;
                self.add_material(at, material)?;
            }
            "texture" => {
                let id = self.require(at, "id")?;
                let texture = bsdfs::texture(self, at, false)?;
                self.textures.insert(id, texture);
            }
            "shape" => shapes::shape(self, at)?,
            "emitter" => emitters::emitter(self, at)?,
            "medium" => {
                media::medium(self, at)?;
            }
            "phase" | "volume" => self.warn_once(
                at.tag(),
                format!(
                    "{}: a <{}> at the top level is not used (give it inside its medium): skipped",
                    at.place(),
                    at.tag()
                ),
            ),
            other => self.warn_once(
                other,
                format!("{}: <{other}> at the top level is not supported: skipped", at.place()),
            ),
        }
        Ok(())
    }

    /// A material made at `at`, registered under its id when it has one; its index.
    pub fn add_material(&mut self, at: At, material: Material) -> Result<usize> {
        let index = self.desc.materials.len();
        let id = self.attr(at, "id")?;
        self.desc.materials.push(crate::desc::MaterialDesc {
            name: id.clone().unwrap_or_else(|| format!("bsdf at {}", at.place())),
            material,
            spectra: (!self.spectra.by_role.is_empty()).then(|| std::mem::take(&mut self.spectra)),
        });
        if let Some(id) = id {
            self.bsdfs.insert(id, index);
        }
        Ok(index)
    }

    /// The file `name` refers to, as Mitsuba's resolver finds it: relative to the scene's
    /// folder, then to each `<path>`, then to the folder of the file `at` is in; the first
    /// that exists (the first candidate when none does, for the error message).
    pub fn resolve(&self, at: At, name: &str) -> PathBuf {
        let here = at.file.path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let candidates: Vec<PathBuf> = self.folders.iter().chain([&here]).map(|f| f.join(name)).collect();
        candidates.iter().find(|c| c.exists()).unwrap_or(&candidates[0]).clone()
    }

    /// Gives the shapes that referred to ids defined after them their BSDF or emitter.
    fn resolve_pending(&mut self) -> Result<()> {
        for (shape, id, location) in std::mem::take(&mut self.pending) {
            if let Some(&m) = self.bsdfs.get(&id) {
                self.desc.shapes[shape].material = Some(m);
            } else if let Some(e) = self.area_emitters.get(&id).cloned() {
                self.desc.shapes[shape].emission = Some(e);
            } else {
                return Err(SceneError::at(
                    location,
                    format!("no bsdf or area emitter has the id `{id}`"),
                ));
            }
        }
        Ok(())
    }

    /// The child elements of a plugin, gathered by property name.
    pub fn props<'a, 'input>(&self, at: At<'a, 'input>) -> Props<'a, 'input> {
        Props::new(at)
    }
}

/// The byte offset of one-based `line` and `col` in `text`.
fn line_col_offset(text: &str, line: usize, col: usize) -> usize {
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    (start + col.saturating_sub(1)).min(text.len())
}

/// Parameters of a plugin that were never read: one warning per plugin type and name.
fn warn_unused(reader: &mut Reader, props: &Props, what: &str) {
    let unused: HashSet<&str> = props.unused();
    let mut unused: Vec<&str> = unused.into_iter().collect();
    unused.sort_unstable();
    for name in unused {
        reader.warn_once(
            &format!("{what}.{name}"),
            format!(
                "{}: {what}: parameter `{name}` is not supported: ignored",
                props.at.place()
            ),
        );
    }
}
