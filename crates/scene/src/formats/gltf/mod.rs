//! glTF 2.0 scenes (`.gltf` with external or embedded buffers, and `.glb`): the default
//! scene's node hierarchy with its transforms, triangle meshes (indices, normals, texture
//! coordinates), metallic-roughness materials mapped onto our BSDFs (`looks.rs`), cameras
//! and KHR_lights_punctual lights. The binary data is read and checked in `data.rs`;
//! every error names the JSON member at fault by line and column (`locate.rs`; in a
//! `.glb`, lines and columns of its JSON chunk).
//!
//! What the file does not say, we choose as a glTF viewer would: without a camera, one that
//! frames the scene; without punctual lights, the sky and key light of a bare mesh
//! ([`super::bare_mesh`]); path traced, 64 samples per pixel, 600 pixels high and as wide
//! as the camera's aspect ratio asks (800 without one).

mod data;
mod locate;
mod looks;
#[cfg(test)]
pub(crate) mod tests;
mod view;

use super::bare_mesh;
use crate::desc::{ShapeDesc, ShapeKind};
use crate::{Location, SceneDesc, SceneError, SourceFile};
use data::Buffers;
use glam::{Mat4, Vec2, Vec3};
use gltf::json::validation::{Error as Invalid, Validate};
use gltf::mesh::{Mode, Semantic};
use penumbra_core::{Aabb, Transform};
use penumbra_geometry::TriangleMesh;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// Extensions that change geometry we cannot read: a file that requires one fails.
const GEOMETRY_EXTENSIONS: [&str; 3] = [
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "EXT_mesh_gpu_instancing",
];

/// Extensions the reader applies.
const SUPPORTED: [&str; 5] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_mesh_quantization",
];

/// Something wrong at a JSON path of the document (located in the text when reported).
#[derive(Debug)]
pub(crate) struct Fail {
    path: String,
    message: String,
}

impl Fail {
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Fail {
            path: path.into(),
            message: message.into(),
        }
    }
}

/// Reads the glTF 2.0 scene at `path` (`.gltf` or `.glb`).
pub fn read(path: &Path) -> Result<SceneDesc> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::io(path, e))?;
    let (json, blob) = match bytes.starts_with(b"glTF") {
        true => split_glb(&bytes).map_err(|m| SceneError::io(path, m))?,
        false => (bytes, None),
    };
    let text = String::from_utf8(json).map_err(|_| SceneError::io(path, "the glTF JSON is not UTF-8 text"))?;
    let file = SourceFile::new(path, text);
    let root: gltf::json::Root = gltf::json::deserialize::from_str(&file.text).map_err(|e| {
        let offset = offset_of(&file.text, e.line(), e.column());
        SceneError::at(
            Location::new(&file, offset..offset),
            format!("malformed glTF JSON: {e}"),
        )
    })?;
    let mut r = Reader {
        file,
        dir: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
        desc: SceneDesc::empty(),
        warned: BTreeMap::new(),
        images: HashMap::new(),
        looks: HashMap::new(),
        shared: HashMap::new(),
        buffers: Buffers::empty(),
    };
    r.validate(&root)?;
    let doc = gltf::Document::from_json_without_validation(root);
    r.buffers = Buffers::load(&doc, blob, &r.dir).map_err(|f| r.fail(f))?;
    r.read(&doc)?;
    r.desc.warnings = std::mem::take(&mut r.warned).into_values().collect();
    Ok(r.desc)
}

/// The JSON and binary chunks of a GLB container (glTF 2.0 spec, section 4.4), checked.
fn split_glb(bytes: &[u8]) -> std::result::Result<(Vec<u8>, Option<Vec<u8>>), String> {
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let version = word(4).ok_or("a GLB file cut short in its header")?;
    if version != 2 {
        return Err(format!("GLB version {version}: only glTF 2.0 is supported"));
    }
    let length = word(8).ok_or("a GLB file cut short in its header")?;
    if length > bytes.len() {
        return Err(format!(
            "the GLB header claims {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    let (mut at, mut json, mut bin) = (12, None, None);
    while at + 8 <= length {
        let (size, kind) = (word(at).unwrap_or(0), word(at + 4).unwrap_or(0));
        let body = at
            .checked_add(8 + size)
            .filter(|&end| end <= length)
            .map(|end| &bytes[at + 8..end])
            .ok_or_else(|| format!("the GLB chunk at byte {at} claims {size} bytes, past the file's end"))?;
        match kind {
            0x4E4F_534A if json.is_none() => json = Some(body.to_vec()),
            0x004E_4942 if bin.is_none() => bin = Some(body.to_vec()),
            _ => {}
        }
        at += 8 + size.next_multiple_of(4).max(size);
    }
    Ok((json.ok_or("the GLB file has no JSON chunk")?, bin))
}

/// The byte offset of one-based `line` and `column` in `text`.
fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    (start + column.saturating_sub(1)).min(text.len())
}

struct Reader {
    file: Arc<SourceFile>,
    dir: PathBuf,
    desc: SceneDesc,
    /// One warning per kind.
    warned: BTreeMap<String, String>,
    buffers: Buffers,
    /// Decoded images, by index.
    images: HashMap<usize, Arc<data::RawImage>>,
    /// Materials made, by glTF material (`None`: the default): index in the scene's
    /// materials and the emission.
    looks: HashMap<Option<usize>, (usize, Option<crate::desc::Emission>)>,
    /// Meshes used by several nodes: per glTF mesh, its primitives' shared meshes.
    shared: HashMap<usize, Vec<(usize, Option<usize>)>>,
}

impl Reader {
    fn location(&self, path: &str) -> Location {
        let path = path.split(" = ").next().unwrap_or(path);
        Location::new(&self.file, locate::locate(&self.file.text, path))
    }

    fn fail(&self, f: Fail) -> SceneError {
        SceneError::at(self.location(&f.path), f.message)
    }

    /// A warning of `kind`, the first of which is kept, at the member `path`.
    fn warn(&mut self, kind: &str, path: &str, text: impl std::fmt::Display) {
        if !self.warned.contains_key(kind) {
            let at = self.location(path);
            self.warned.insert(kind.to_string(), format!("{at}: {text}"));
        }
    }

    /// The `gltf` crate's checks of the document (indices in range, required members),
    /// errors located; required extensions we can do without are warnings.
    fn validate(&mut self, root: &gltf::json::Root) -> Result<()> {
        // The crate's own validation indexes the accessors by each primitive's POSITION
        // unchecked (a panic found by fuzzing): every attribute's accessor is checked first.
        for (m, mesh) in root.meshes.iter().enumerate() {
            for (p, prim) in mesh.primitives.iter().enumerate() {
                for (semantic, index) in &prim.attributes {
                    if index.value() >= root.accessors.len() {
                        let name = match semantic {
                            gltf::json::validation::Checked::Valid(s) => s.to_string(),
                            gltf::json::validation::Checked::Invalid => "?".into(),
                        };
                        let path = format!("meshes[{m}].primitives[{p}].attributes[\"{name}\"]");
                        let message = format!(
                            "invalid glTF: accessor {} does not exist (the file has {})",
                            index.value(),
                            root.accessors.len()
                        );
                        return Err(self.fail(Fail::new(path, message)));
                    }
                }
            }
        }
        let mut found = Vec::new();
        root.validate(
            root,
            gltf::json::Path::new,
            &mut |path: &dyn Fn() -> gltf::json::Path, e: Invalid| found.push((path().0, e)),
        );
        for (index, ext) in root.extensions_used.iter().enumerate() {
            if !SUPPORTED.contains(&ext.as_str()) && !GEOMETRY_EXTENSIONS.contains(&ext.as_str()) {
                self.warn(
                    ext,
                    &format!("extensionsUsed[{index}]"),
                    format!("the extension {ext} is not supported: ignored"),
                );
            }
        }
        for (path, e) in found {
            let name = path
                .strip_prefix("extensionsRequired[")
                .and_then(|rest| rest.split(']').next()?.parse::<usize>().ok())
                .and_then(|i| root.extensions_required.get(i).cloned());
            match (e, name) {
                (Invalid::Unsupported, Some(name)) if !GEOMETRY_EXTENSIONS.contains(&name.as_str()) => self.warn(
                    &name,
                    &path,
                    format!("the required extension {name} is not supported: the scene is drawn without it"),
                ),
                (Invalid::Unsupported, Some(name)) => {
                    return Err(self.fail(Fail::new(
                        path,
                        format!("the file requires {name}, which compresses or instances its geometry: not supported"),
                    )))
                }
                (e, _) => {
                    let what = match e {
                        Invalid::IndexOutOfBounds => "an index out of range",
                        Invalid::Invalid => "an invalid value",
                        Invalid::Missing => "a required member is missing",
                        Invalid::Oversize => "a size beyond what this machine can address",
                        Invalid::Unsupported => "something this reader does not support",
                    };
                    let path = path.split(" = ").next().unwrap_or(&path).to_string();
                    return Err(self.fail(Fail::new(path.clone(), format!("invalid glTF: {what} at `{path}`"))));
                }
            }
        }
        Ok(())
    }

    /// Builds the scene from the document's default scene (else its first; else every
    /// node that is no other's child).
    fn read(&mut self, doc: &gltf::Document) -> Result<()> {
        if doc.animations().next().is_some() {
            self.warn(
                "animations",
                "animations",
                "animations are not played: the scene is drawn at rest",
            );
        }
        if doc.skins().next().is_some() {
            self.warn(
                "skins",
                "skins",
                "skins are not applied: skinned meshes are drawn in their bind pose",
            );
        }
        let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(scene) => scene.nodes().collect(),
            None => {
                let children: Vec<usize> = doc.nodes().flat_map(|n| n.children().map(|c| c.index())).collect();
                doc.nodes().filter(|n| !children.contains(&n.index())).collect()
            }
        };
        // Every node under the roots with its node-to-world matrix, each at most once.
        let mut placed = Vec::new();
        let mut seen = vec![false; doc.nodes().len()];
        let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY)).collect();
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut seen[node.index()], true) {
                return Err(self.fail(Fail::new(
                    format!("nodes[{}]", node.index()),
                    format!(
                        "node {} is reached twice: nodes must form trees (no cycles, one parent each)",
                        node.index()
                    ),
                )));
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            stack.extend(
                node.children()
                    .map(|c| (c, world))
                    .collect::<Vec<_>>()
                    .into_iter()
                    .rev(),
            );
            placed.push((node, world));
        }
        let mut uses = HashMap::<usize, usize>::new();
        for (node, _) in &placed {
            if let Some(m) = node.mesh() {
                *uses.entry(m.index()).or_default() += 1;
            }
        }
        let mut bounds = Aabb::EMPTY;
        let mut cameras = Vec::new();
        for (node, world) in &placed {
            let path = format!("nodes[{}]", node.index());
            let Some(t) = Transform::from_matrix(*world).filter(|t| t.m.is_finite()) else {
                self.warn(
                    "singular",
                    &path,
                    format!("node {} has a singular transform: it is not drawn", node.index()),
                );
                continue;
            };
            if let Some(mesh) = node.mesh() {
                bounds = bounds.union(self.place_mesh(&mesh, &t, uses[&mesh.index()] > 1)?);
            }
            if let Some(camera) = node.camera() {
                cameras.push((camera, t, path.clone()));
            }
            if let Some(light) = node.light() {
                self.light(&light, &t, &path);
            }
        }
        self.desc.render = bare_mesh::default_render();
        if !bounds.min.is_finite() || !bounds.max.is_finite() {
            return Err(SceneError::io(&self.file.path, "the scene has no triangles to draw"));
        }
        let mut choices = Vec::new();
        for (camera, t, _) in &cameras {
            choices.push(self.camera(camera, t)?);
        }
        match choices.first() {
            Some(first) => {
                if let (true, Some((_, _, path))) = (choices.len() > 1, cameras.first()) {
                    self.warn(
                        "cameras",
                        path,
                        format!(
                            "the scene has {} camera nodes: the first is the default (--camera N picks another, from 0)",
                            choices.len()
                        ),
                    );
                }
                self.desc.camera = first.camera.clone();
                (self.desc.render.width, self.desc.render.height) = (first.width, first.height);
                if choices.len() > 1 {
                    self.desc.cameras = choices;
                }
            }
            None => self.desc.camera = bare_mesh::frame(bounds),
        }
        if self.desc.lights.is_empty() {
            bare_mesh::default_lighting(&mut self.desc);
        }
        Ok(())
    }

    /// The shapes of glTF mesh `mesh` placed by `t`: each primitive a mesh of its own
    /// material, shared between nodes as instances when several nodes use it. Returns the
    /// world bounds.
    fn place_mesh(&mut self, mesh: &gltf::Mesh, t: &Transform, shared: bool) -> Result<Aabb> {
        let mut bounds = Aabb::EMPTY;
        if shared {
            if !self.shared.contains_key(&mesh.index()) {
                let mut parts = Vec::new();
                for (m, material) in self.primitives(mesh)? {
                    self.desc.meshes.push(Arc::new(m));
                    parts.push((self.desc.meshes.len() - 1, material));
                }
                self.shared.insert(mesh.index(), parts);
            }
            for (k, material) in self.shared[&mesh.index()].clone() {
                let (material, emission) = self.look(material, mesh)?;
                bounds = self.desc.meshes[k]
                    .positions
                    .iter()
                    .fold(bounds, |b, &p| b.grow(t.point(p)));
                self.push_shape(ShapeKind::Instance { mesh: k }, t, material, emission);
            }
        } else {
            for (m, material) in self.primitives(mesh)? {
                let (material, emission) = self.look(material, mesh)?;
                bounds = m.positions.iter().fold(bounds, |b, &p| b.grow(t.point(p)));
                self.push_shape(ShapeKind::Mesh(Arc::new(m)), t, material, emission);
            }
        }
        Ok(bounds)
    }

    fn push_shape(&mut self, kind: ShapeKind, t: &Transform, material: usize, emission: Option<crate::desc::Emission>) {
        self.desc.shapes.push(ShapeDesc {
            kind,
            transform: *t,
            material: Some(material),
            emission,
            media: None,
            location: None,
        });
    }

    /// The material and emission of glTF material `material` (of a primitive of `mesh`).
    fn look(&mut self, material: Option<usize>, mesh: &gltf::Mesh) -> Result<(usize, Option<crate::desc::Emission>)> {
        if let Some(made) = self.looks.get(&material) {
            return Ok(made.clone());
        }
        let doc_material = mesh
            .primitives()
            .map(|p| p.material())
            .find(|m| m.index() == material)
            .expect("the material came from one of the mesh's primitives");
        let made = self.material(&doc_material).map_err(|f| self.fail(f))?;
        self.looks.insert(material, made.clone());
        Ok(made)
    }

    /// The triangle primitives of `mesh` as meshes in its own space, each with its glTF
    /// material index; primitives of points or lines are skipped with a warning.
    fn primitives(&mut self, mesh: &gltf::Mesh) -> Result<Vec<(TriangleMesh, Option<usize>)>> {
        let mut out = Vec::new();
        for prim in mesh.primitives() {
            let path = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
            if !matches!(prim.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
                self.warn(
                    "mode",
                    &format!("{path}.mode"),
                    format!("primitives of {:?} are not drawn (only triangles are)", prim.mode()),
                );
                continue;
            }
            if prim.morph_targets().next().is_some() {
                self.warn("morph", &format!("{path}.targets"), "morph targets are not applied");
            }
            let Some(m) = self.primitive(&prim, &path).map_err(|f| self.fail(f))? else {
                self.warn("position", &path, "a primitive without POSITION is not drawn");
                continue;
            };
            let mut m = m;
            if let Some(w) =
                super::drop_degenerate(&mut m, &format!("mesh {} (primitive {})", mesh.index(), prim.index()))
            {
                self.warn("degenerate", &path, w);
            }
            if !m.indices.is_empty() {
                out.push((m, prim.material().index()));
            }
        }
        Ok(out)
    }

    /// One primitive's mesh: positions, normals and texture coordinates (v flipped: glTF's
    /// v runs down the image, ours up) and its triangles; `None` without positions.
    fn primitive(&self, prim: &gltf::Primitive, path: &str) -> std::result::Result<Option<TriangleMesh>, Fail> {
        use gltf::accessor::Dimensions::{Vec2 as D2, Vec3 as D3};
        let Some(acc) = prim.get(&Semantic::Positions) else {
            return Ok(None);
        };
        let v3 = |f: Vec<f32>| {
            f.chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect::<Vec<_>>()
        };
        let positions = v3(self.buffers.floats(&acc, D3)?);
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(Fail::new(
                format!("accessors[{}]", acc.index()),
                "a vertex position is not a finite number",
            ));
        }
        let n = positions.len();
        let attribute = |semantic: Semantic, dims| -> std::result::Result<Option<Vec<f32>>, Fail> {
            let Some(acc) = prim.get(&semantic) else {
                return Ok(None);
            };
            let values = self.buffers.floats(&acc, dims)?;
            if acc.count() != n {
                return Err(Fail::new(
                    format!("accessors[{}].count", acc.index()),
                    format!("{} values for {n} vertices", acc.count()),
                ));
            }
            Ok(Some(values))
        };
        let normals = attribute(Semantic::Normals, D3)?.map(v3);
        let uvs = attribute(Semantic::TexCoords(0), D2)?
            .map(|f| f.chunks_exact(2).map(|c| Vec2::new(c[0], 1.0 - c[1])).collect());
        let order: Vec<u32> = match prim.indices() {
            Some(acc) => {
                let order = self.buffers.indices(&acc)?;
                if let Some(&bad) = order.iter().find(|&&i| i as usize >= n) {
                    return Err(Fail::new(
                        format!("{path}.indices"),
                        format!("vertex index {bad} is out of range: the primitive has {n} vertices"),
                    ));
                }
                order
            }
            None => (0..n as u32).collect(),
        };
        let indices = match prim.mode() {
            Mode::TriangleStrip => (2..order.len())
                .map(|k| match k % 2 {
                    0 => [order[k - 2], order[k - 1], order[k]],
                    _ => [order[k - 1], order[k - 2], order[k]],
                })
                .collect(),
            Mode::TriangleFan => (2..order.len()).map(|k| [order[k - 1], order[k], order[0]]).collect(),
            _ => order.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        };
        Ok(Some(TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        }))
    }
}
