//! pbrt-v4's shapes: `trianglemesh` (and `loopsubdiv` as its control mesh),
//! `bilinearmesh` (two triangles a patch), `plymesh`, `sphere`, `disk`; each with the
//! current transform, material, area light and orientation.

use super::objects::unused;
use super::params::Params;
use super::{Reader, Result};
use crate::desc::{ShapeDesc, ShapeKind};
use crate::formats::{default_material, drop_degenerate, flipped, ply};
use crate::{Location, SceneError, SourceFile};
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;
use penumbra_geometry::TriangleMesh;
use penumbra_render::materials::DiffuseMaterial;
use penumbra_render::{Material, Texture};
use std::sync::Arc;

pub fn shape(r: &mut Reader, kind: &str, p: &Params, file: &SourceFile, here: Location) -> Result<Option<ShapeDesc>> {
    let kind_of = match kind {
        "trianglemesh" | "loopsubdiv" => {
            if kind == "loopsubdiv" {
                r.warn(
                    "loopsubdiv",
                    format!("{here}: `loopsubdiv` is rendered as its control mesh"),
                );
            }
            ShapeKind::Mesh(Arc::new(triangle_mesh(p, &here)?))
        }
        "bilinearmesh" => ShapeKind::Mesh(Arc::new(bilinear_mesh(p, &here)?)),
        "plymesh" => {
            let name = p
                .string("filename")?
                .ok_or_else(|| SceneError::at(here.clone(), "a plymesh needs a \"string filename\""))?;
            let path = r.resolve(file, &name);
            let mut mesh = ply::load(&path)
                .map_err(|e| SceneError::at(here.clone(), format!("cannot read {}: {e}", path.display())))?;
            if let Some(w) = drop_degenerate(&mut mesh, &format!("{here} ({})", path.display())) {
                r.warn(&format!("degenerate {}", path.display()), w);
            }
            ShapeKind::Mesh(Arc::new(mesh))
        }
        "sphere" => ShapeKind::Sphere {
            center: Vec3::ZERO,
            radius: p.float("radius", 1.0)?,
        },
        "disk" => {
            if p.float("innerradius", 0.0)? > 0.0 {
                r.warn(
                    "disk.innerradius",
                    format!("{here}: a disk's `innerradius` is not supported: a full disk"),
                );
            }
            ShapeKind::Disk {
                center: Vec3::new(0.0, 0.0, p.float("height", 0.0)?),
                normal: Vec3::Z,
                radius: p.float("radius", 1.0)?,
            }
        }
        other => {
            r.warn(
                &format!("shape {other}"),
                format!("{here}: shape `{other}` is not supported: skipped"),
            );
            return Ok(None);
        }
    };
    if kind == "sphere" {
        // pbrt's defaults: the whole sphere (zmin -radius, zmax radius, phimax 360).
        let radius = p.float("radius", 1.0)?;
        for (partial, whole) in [("zmin", -radius), ("zmax", radius), ("phimax", 360.0)] {
            if p.float(partial, whole)? != whole {
                r.warn(
                    "partial sphere",
                    format!("{here}: partial spheres (zmin, zmax, phimax) are rendered whole"),
                );
            }
        }
    }
    if p.texture_name("alpha").is_some() || p.float("alpha", 1.0).is_ok_and(|a| a != 1.0) {
        r.warn(
            "alpha",
            format!("{here}: alpha cut-outs are not supported: the shape is opaque"),
        );
    }
    unused(r, p, &format!("shape {kind}"), &here);
    let kind_of = match (kind_of, r.state.reverse) {
        (ShapeKind::Mesh(m), true) => ShapeKind::Mesh(Arc::new(flipped(&m))),
        (k, _) => k,
    };
    // pbrt's default material: a diffuse of 0.5 (two-sided, as pbrt's BSDFs are).
    let material = match r.state.material {
        Some(m) => m,
        None => default_material(&mut r.desc, &mut r.default_material, || {
            Material::TwoSided(Box::new(Material::Diffuse(DiffuseMaterial {
                reflectance: Texture::Constant(Rgb::splat(0.5)),
            })))
        }),
    };
    Ok(Some(ShapeDesc {
        kind: kind_of,
        transform: r.state.ctm,
        material: Some(material),
        emission: r.state.area.clone(),
        media: super::media::of_shape(r.state.media.0, r.state.media.1),
        location: Some(here),
    }))
}

/// The points `P` of a mesh of `what` and its `indices` (optional for a single one of
/// `corners` points).
fn points_and_indices(p: &Params, here: &Location, what: &str, corners: usize) -> Result<(Vec<Vec3>, Vec<i64>)> {
    let positions: Vec<Vec3> = p
        .points("P", 3)?
        .ok_or_else(|| SceneError::at(here.clone(), format!("a {what} needs \"point3 P\"")))?
        .iter()
        .map(|v| Vec3::new(v[0], v[1], v[2]))
        .collect();
    let indices = match p.ints("indices")? {
        Some(i) => i,
        None if positions.len() == corners => (0..corners as i64).collect(),
        None => {
            return Err(SceneError::at(
                here.clone(),
                format!("a {what} of more than {corners} points needs \"integer indices\""),
            ))
        }
    };
    Ok((positions, indices))
}

fn triangle_mesh(p: &Params, here: &Location) -> Result<TriangleMesh> {
    let (positions, indices) = points_and_indices(p, here, "triangle mesh", 3)?;
    mesh_from(p, here, positions, &indices)
}

/// Bilinear patches (four points each, in the order p00 p10 p01 p11), split into two
/// triangles each.
fn bilinear_mesh(p: &Params, here: &Location) -> Result<TriangleMesh> {
    let (positions, quads) = points_and_indices(p, here, "bilinear mesh", 4)?;
    if quads.len() % 4 != 0 {
        return Err(SceneError::at(here.clone(), "a bilinear mesh's indices come in fours"));
    }
    let tris: Vec<i64> = quads
        .chunks(4)
        .flat_map(|q| [q[0], q[1], q[3], q[0], q[3], q[2]])
        .collect();
    mesh_from(p, here, positions, &tris)
}

fn mesh_from(p: &Params, here: &Location, positions: Vec<Vec3>, indices: &[i64]) -> Result<TriangleMesh> {
    if !indices.len().is_multiple_of(3) {
        return Err(SceneError::at(
            here.clone(),
            format!("{} indices: not a multiple of 3", indices.len()),
        ));
    }
    let count = positions.len();
    let index = |i: i64| -> Result<u32> {
        if (0..count as i64).contains(&i) {
            Ok(i as u32)
        } else {
            Err(SceneError::at(
                here.clone(),
                format!("index {i} is out of range: the mesh has {count} points"),
            ))
        }
    };
    let mut mesh = TriangleMesh {
        positions,
        normals: None,
        uvs: None,
        indices: indices
            .chunks(3)
            .map(|t| Ok([index(t[0])?, index(t[1])?, index(t[2])?]))
            .collect::<Result<_>>()?,
    };
    if let Some(normals) = p.points("N", 3)? {
        if normals.len() != count {
            return Err(SceneError::at(
                here.clone(),
                format!("{} normals for {count} points", normals.len()),
            ));
        }
        mesh.normals = Some(normals.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect());
    }
    let uv = match p.points("uv", 2)? {
        Some(uv) => Some(uv),
        None => p.points("st", 2)?,
    };
    if let Some(uv) = uv {
        if uv.len() != count {
            return Err(SceneError::at(
                here.clone(),
                format!("{} uvs for {count} points", uv.len()),
            ));
        }
        mesh.uvs = Some(uv.iter().map(|v| Vec2::new(v[0], v[1])).collect());
    }
    p.ints("faceIndices")?;
    p.points("S", 3)?;
    mesh.validate()
        .map_err(|e| SceneError::at(here.clone(), e.to_string()))?;
    Ok(mesh)
}
