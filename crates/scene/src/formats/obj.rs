//! Wavefront OBJ meshes, read with `tobj`: polygons are triangulated, vertices with
//! distinct position/normal/texture-coordinate combinations are split so that every
//! attribute is per vertex. All groups and objects of the file form one mesh.

use glam::{Vec2, Vec3};
use penumbra_geometry::TriangleMesh;
use std::path::Path;

/// Loads every model of the OBJ file at `path` as one triangle mesh.
pub fn load(path: &Path) -> Result<TriangleMesh, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| e.to_string())?;
    let mut mesh = TriangleMesh::default();
    let all_normals = models.iter().all(|m| !m.mesh.normals.is_empty());
    let all_uvs = models.iter().all(|m| !m.mesh.texcoords.is_empty());
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for model in &models {
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
