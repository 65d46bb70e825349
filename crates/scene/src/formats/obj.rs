//! Wavefront OBJ meshes, read with `tobj`: polygons are triangulated, vertices with
//! distinct position/normal/texture-coordinate combinations are split so that every
//! attribute is per vertex. [`load`] makes all groups and objects one mesh; [`load_parts`]
//! keeps one mesh per MTL material, with the materials the file's `mtllib` defines.

use glam::{Vec2, Vec3};
use penumbra_geometry::TriangleMesh;
use std::path::Path;

/// The meshes of an OBJ file grouped by material (`None`: faces without one), the
/// materials of its MTL library, and why that library could not be read, if it could not.
pub struct ObjParts {
    pub parts: Vec<(TriangleMesh, Option<usize>)>,
    pub materials: Vec<tobj::Material>,
    pub mtl_error: Option<String>,
}

fn read(path: &Path) -> Result<(Vec<tobj::Model>, tobj::MTLLoadResult), String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    check_indices(&String::from_utf8_lossy(&bytes))?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj(path, &options).map_err(|e| e.to_string())?;
    Ok((models, materials.map(|m| (m, Default::default()))))
}

/// Checks that vertex, texture coordinate and normal lines hold numbers, and every index of
/// the face, line and point elements of OBJ `text` against the
/// vertices, texture coordinates and normals defined before it (one-based, or negative:
/// counted back from the last), naming the line and column of the first that is out of
/// range or not a number. (tobj, which reads the file next, assumes this.) An index of an
/// attribute the file has none of is ignored, as tobj ignores it.
fn check_indices(text: &str) -> Result<(), String> {
    let names = ["vertex", "texture coordinate", "normal"];
    let mut counts = [0i64; 3];
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let keyword = words.next();
        if let Some(k @ ("v" | "vt" | "vn")) = keyword {
            for word in words.clone() {
                if word.parse::<f64>().is_err() {
                    let column = word.as_ptr() as usize - line.as_ptr() as usize + 1;
                    return Err(format!(
                        "line {}, column {column}: `{word}` in a `{k}` line is not a number",
                        n + 1
                    ));
                }
            }
        }
        match keyword {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f" | "l" | "p") => {
                for word in words {
                    let column = word.as_ptr() as usize - line.as_ptr() as usize + 1;
                    for (k, part) in word.split('/').enumerate().take(3) {
                        if part.is_empty() && k > 0 {
                            continue;
                        }
                        // (The place is written out only for an error: this runs per index.)
                        let at = || format!("line {}, column {column}", n + 1);
                        let i: i64 = part.parse().map_err(|_| {
                            let at = at();
                            format!("{at}: `{word}` is not a vertex reference (v, v/vt, v/vt/vn or v//vn)")
                        })?;
                        let count = counts[k];
                        if count == 0 && k > 0 {
                            continue;
                        }
                        let index = if i < 0 { count.saturating_add(i) } else { i - 1 };
                        if i == 0 || !(0..count).contains(&index) {
                            return Err(format!(
                                "{}: {} index {i} is out of range: {count} defined before it",
                                at(),
                                names[k]
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// One mesh of `models`; normals and texture coordinates only if every model has them.
fn merge(models: &[&tobj::Model]) -> Result<TriangleMesh, String> {
    let mut mesh = TriangleMesh::default();
    let all_normals = models.iter().all(|m| !m.mesh.normals.is_empty());
    let all_uvs = models.iter().all(|m| !m.mesh.texcoords.is_empty());
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for model in models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend(m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])));
        if all_normals {
            normals.extend(m.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2])));
        }
        if all_uvs {
            uvs.extend(m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], t[1])));
        }
        mesh.indices.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    mesh.normals = (all_normals && !models.is_empty()).then_some(normals);
    mesh.uvs = (all_uvs && !models.is_empty()).then_some(uvs);
    if mesh.indices.is_empty() {
        return Err("the file contains no faces".into());
    }
    mesh.validate().map_err(|e| e.to_string())?;
    Ok(mesh)
}

/// Loads every model of the OBJ file at `path` as one triangle mesh.
pub fn load(path: &Path) -> Result<TriangleMesh, String> {
    let (models, _materials) = read(path)?;
    merge(&models.iter().collect::<Vec<_>>())
}

/// Loads the OBJ file at `path` as one mesh per material.
pub fn load_parts(path: &Path) -> Result<ObjParts, String> {
    let (models, materials) = read(path)?;
    let mut ids: Vec<Option<usize>> = models.iter().map(|m| m.mesh.material_id).collect();
    ids.sort_unstable();
    ids.dedup();
    let mut parts = Vec::new();
    for id in ids {
        let group: Vec<&tobj::Model> = models
            .iter()
            .filter(|m| m.mesh.material_id == id && !m.mesh.indices.is_empty())
            .collect();
        if !group.is_empty() {
            parts.push((merge(&group)?, id));
        }
    }
    if parts.is_empty() {
        return Err("the file contains no faces".into());
    }
    let (materials, mtl_error) = match materials {
        Ok((m, _)) => (m, None),
        Err(e) => (Vec::new(), Some(e.to_string())),
    };
    Ok(ObjParts {
        parts,
        materials,
        mtl_error,
    })
}
