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
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj(path, &options).map_err(|e| e.to_string())?;
    Ok((models, materials.map(|m| (m, Default::default()))))
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
