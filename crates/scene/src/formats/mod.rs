//! Scene readers, one per format, chosen by file extension. Each produces a [`SceneDesc`].
//!
//! Adding a format: a new module with a `read(&Arc<SourceFile>) -> Result<SceneDesc>` and
//! one arm in [`read_scene`].

pub mod bare_mesh;
#[cfg(test)]
mod fuzz_tests;
pub mod gltf;
pub mod mitsuba;
pub mod mtl;
pub mod native;
pub mod obj;
pub mod pbrt;
pub mod ply;
#[cfg(test)]
mod test_files;
pub mod vol;

use crate::{SceneDesc, SceneError, SourceFile};
use penumbra_geometry::TriangleMesh;
use penumbra_render::Material;
use std::path::Path;

/// Drops `mesh`'s triangles without area; returns a warning about `what` (the mesh's name
/// and place) when there were any, saying whether anything is left to draw.
pub fn drop_degenerate(mesh: &mut TriangleMesh, what: &str) -> Option<String> {
    let total = mesh.indices.len();
    let dropped = mesh.remove_degenerate();
    match dropped {
        0 => None,
        _ if dropped == total => Some(format!(
            "{what} has no triangle with area ({total} degenerate): it draws nothing"
        )),
        _ => Some(format!("{what}: skipped {dropped} of {total} triangles with zero area")),
    }
}

/// The index of the material shapes get when their file gives them none (Mitsuba's and
/// pbrt's grey diffuse), added to `desc` the first time it is needed; `made` keeps it.
pub fn default_material(desc: &mut SceneDesc, made: &mut Option<usize>, material: impl FnOnce() -> Material) -> usize {
    *made.get_or_insert_with(|| {
        desc.materials.push(crate::desc::MaterialDesc {
            name: "default".into(),
            material: material(),
            spectra: None,
        });
        desc.materials.len() - 1
    })
}

/// The mesh facing the other way: reversed winding, negated normals (Mitsuba's
/// `flip_normals`, pbrt's `ReverseOrientation`).
pub fn flipped(mesh: &TriangleMesh) -> TriangleMesh {
    TriangleMesh {
        positions: mesh.positions.clone(),
        normals: mesh.normals.as_ref().map(|n| n.iter().map(|&v| -v).collect()),
        uvs: mesh.uvs.clone(),
        indices: mesh.indices.iter().map(|&[a, b, c]| [a, c, b]).collect(),
    }
}

/// Reads the scene file at `path`, choosing the reader by its extension: `.toml` the native
/// format, `.xml` Mitsuba 3, `.pbrt` pbrt-v4, `.gltf` and `.glb` glTF 2.0, `.obj` and `.ply` a bare mesh shown by a
/// default camera and light ([`bare_mesh`]).
pub fn read_scene(path: &Path) -> Result<SceneDesc, SceneError> {
    read_scene_with(path, &[])
}

/// [`read_scene`] with parameters of the scene set as `-D name=value` sets them (Mitsuba's
/// `$name`); an error for a format that takes none.
pub fn read_scene_with(path: &Path, defines: &[(String, String)]) -> Result<SceneDesc, SceneError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !defines.is_empty() && ext.as_deref() != Some("xml") {
        return Err(SceneError::io(path, "-D sets parameters of Mitsuba (.xml) scenes only"));
    }
    match ext.as_deref() {
        Some("toml") => {
            let text = std::fs::read_to_string(path).map_err(|e| SceneError::io(path, e))?;
            native::read(&SourceFile::new(path, text))
        }
        Some("xml") => mitsuba::read(path, defines),
        Some("pbrt") => pbrt::read(path),
        Some("gltf" | "glb") => gltf::read(path),
        Some("obj" | "ply") => bare_mesh::read(path),
        _ => Err(SceneError::io(
            path,
            "unsupported scene format: expected .toml (the native format), .xml (Mitsuba 3), .pbrt (pbrt-v4), .gltf or .glb (glTF 2.0) or a bare .obj or .ply mesh",
        )),
    }
}
