//! Mitsuba's shapes: `obj` and `ply` meshes; `rectangle`, `cube` and `cylinder` as the
//! meshes Mitsuba defines them by (the square [-1, 1]² at z = 0 facing +z, the cube
//! [-1, 1]³, the open tube of radius 1 from p0 to p1); `sphere` and `disk` analytic. Each
//! with its `to_world`, its BSDF (nested or by reference; Mitsuba's grey `diffuse` when it
//! has none) and an `area` emitter.

use super::bsdfs::bsdf;
use super::{warn_unused, At, Reader, Result};
use crate::desc::{Emission, ShapeDesc, ShapeKind};
use crate::formats::{default_material, drop_degenerate, flipped, obj, ply};
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;
use penumbra_geometry::TriangleMesh;
use penumbra_render::materials::DiffuseMaterial;
use penumbra_render::{Material, Texture};
use std::f32::consts::TAU;
use std::sync::Arc;

/// Sides of the polygon a `cylinder` becomes.
const CYLINDER_SIDES: usize = 64;

pub fn shape(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = r.require(at, "type")?;
    let to_world = p.transform(r, "to_world")?;
    let flip = p.bool_or(r, "flip_normals", false)?;
    let shape = match kind.as_str() {
        "obj" | "ply" => {
            let (name, v) = p
                .string(r, "filename")?
                .ok_or_else(|| at.error(format!("a `{kind}` shape needs a `filename`")))?;
            let path = r.resolve(v, &name);
            let loaded = if kind == "obj" {
                obj::load(&path)
            } else {
                ply::load(&path)
            };
            let mut mesh =
                loaded.map_err(|e| r.attr_error(v, "value", format!("cannot read {}: {e}", path.display())))?;
            if p.bool_or(r, "face_normals", false)? {
                mesh.normals = None;
            }
            if let Some(w) = drop_degenerate(&mut mesh, &format!("{} ({})", v.place(), path.display())) {
                r.warn_once(&format!("degenerate {}", path.display()), w);
            }
            ShapeKind::Mesh(Arc::new(mesh))
        }
        "rectangle" => ShapeKind::Mesh(Arc::new(rectangle())),
        "cube" => ShapeKind::Mesh(Arc::new(cube())),
        "cylinder" => {
            let p0 = p.vec3(r, "p0")?.unwrap_or(Vec3::ZERO);
            let p1 = p.vec3(r, "p1")?.unwrap_or(Vec3::Z);
            let radius = p.float_or(r, "radius", 1.0)?;
            ShapeKind::Mesh(Arc::new(
                cylinder(p0, p1, radius).ok_or_else(|| at.error("the cylinder has no length or no radius"))?,
            ))
        }
        "sphere" => ShapeKind::Sphere {
            center: p.vec3(r, "center")?.unwrap_or(Vec3::ZERO),
            radius: p.float_or(r, "radius", 1.0)?,
        },
        "disk" => ShapeKind::Disk {
            center: Vec3::ZERO,
            normal: Vec3::Z,
            radius: 1.0,
        },
        other => {
            let text = format!("{}: shape `{other}` is not supported: skipped", at.place());
            r.warn_once(&format!("shape {other}"), text);
            return Ok(());
        }
    };
    let shape = match (shape, flip) {
        (ShapeKind::Mesh(mesh), true) => ShapeKind::Mesh(Arc::new(flipped(&mesh))),
        (s @ (ShapeKind::Sphere { .. } | ShapeKind::Disk { .. }), true) => {
            r.warn_once(
                "flip_normals",
                format!("{}: flip_normals on a sphere or disk is ignored", at.place()),
            );
            s
        }
        (s, _) => s,
    };
    let mut pending = Vec::new();
    let material = shape_material(r, &p, &mut pending)?;
    let media = super::media::shape_media(r, &p)?;
    let mut emission = None;
    for e in p.nested("emitter") {
        let ep = r.props(e);
        match r.require(e, "type")?.as_str() {
            "area" => {
                let radiance = ep.color_or(r, "radiance", 1.0)?;
                let spectrum = ep.spectrum(r, "radiance")?.map(|s| (s, 1.0));
                emission = Some(Emission {
                    radiance,
                    two_sided: false,
                    texture: None,
                    spectrum,
                });
                warn_unused(r, &ep, "emitter area");
            }
            other => return Err(e.error(format!("a shape's emitter must be `area`, found `{other}`"))),
        }
    }
    warn_unused(r, &p, &format!("shape {kind}"));
    for (id, location) in pending {
        match r.area_emitters.get(&id) {
            Some(e) => emission = Some(e.clone()),
            None => r.pending.push((r.desc.shapes.len(), id, location)),
        }
    }
    r.desc.shapes.push(ShapeDesc {
        kind: shape,
        transform: to_world,
        material: Some(material),
        emission,
        media,
        location: Some(at.location()),
    });
    Ok(())
}

/// The material of a shape: its nested `<bsdf>`, a `<ref>` to one, or Mitsuba's default
/// (a grey `diffuse` of reflectance 0.5, made once). References to ids that are not a BSDF
/// defined so far (an area emitter, or anything defined later) go to `refs`.
fn shape_material(r: &mut Reader, p: &super::props::Props, refs: &mut Vec<(String, crate::Location)>) -> Result<usize> {
    let mut material = None;
    if let Some(b) = p.nested("bsdf").into_iter().next() {
        let m = bsdf(r, b)?;
        material = Some(r.add_material(b, m)?);
    }
    for reference in p.nested("ref") {
        let id = r.require(reference, "id")?;
        match r.bsdfs.get(&id) {
            Some(&m) if material.is_none() => material = Some(m),
            _ => refs.push((id, reference.location())),
        }
    }
    if let Some(m) = material {
        return Ok(m);
    }
    Ok(default_material(&mut r.desc, &mut r.default_material, || {
        Material::Diffuse(DiffuseMaterial {
            reflectance: Texture::Constant(Rgb::splat(0.5)),
        })
    }))
}

fn rectangle() -> TriangleMesh {
    TriangleMesh {
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        normals: Some(vec![Vec3::Z; 4]),
        uvs: Some(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ]),
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// [-1, 1]³, four vertices a face with the face's outward normal.
fn cube() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let n = Vec3::from_array(std::array::from_fn(|k| if k == axis { sign } else { 0.0 }));
            // Two edges of the face such that u x v = n.
            let u = Vec3::from_array(std::array::from_fn(|k| if k == (axis + 1) % 3 { 1.0 } else { 0.0 }));
            let v = n.cross(u);
            let base = mesh.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                mesh.positions.push(n + u * a + v * b);
                normals.push(n);
                uvs.push(Vec2::new((a + 1.0) * 0.5, (b + 1.0) * 0.5));
            }
            mesh.indices.push([base, base + 1, base + 2]);
            mesh.indices.push([base, base + 2, base + 3]);
        }
    }
    mesh.normals = Some(normals);
    mesh.uvs = Some(uvs);
    mesh
}

/// The open tube of `radius` around the segment p0-p1, normals outward.
fn cylinder(p0: Vec3, p1: Vec3, radius: f32) -> Option<TriangleMesh> {
    let axis = (p1 - p0).try_normalize()?;
    if radius <= 0.0 || !radius.is_finite() {
        return None;
    }
    let (a, b) = axis.any_orthonormal_pair();
    let mut mesh = TriangleMesh::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for k in 0..=CYLINDER_SIDES {
        let phi = TAU * k as f32 / CYLINDER_SIDES as f32;
        let n = a * phi.cos() + b * phi.sin();
        for (end, v) in [(p0, 0.0), (p1, 1.0)] {
            mesh.positions.push(end + n * radius);
            normals.push(n);
            uvs.push(Vec2::new(k as f32 / CYLINDER_SIDES as f32, v));
        }
    }
    for k in 0..CYLINDER_SIDES as u32 {
        let (i, j) = (2 * k, 2 * k + 2);
        // Counter-clockwise seen from outside: (a, b, axis) is right-handed.
        mesh.indices.push([i, j, j + 1]);
        mesh.indices.push([i, j + 1, i + 1]);
    }
    mesh.normals = Some(normals);
    mesh.uvs = Some(uvs);
    Some(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mitsuba's rectangle, cube and cylinder: the winding agrees with the normals (so an
    /// area light emits on the normal's side) and the sizes are Mitsuba's.
    #[test]
    fn built_in_meshes_wind_with_their_normals() {
        for (name, mesh, area) in [
            ("rectangle", rectangle(), 4.0),
            ("cube", cube(), 24.0),
            ("cylinder", cylinder(Vec3::ZERO, Vec3::Z, 1.0).unwrap(), TAU),
        ] {
            let mut total = 0.0;
            for t in &mesh.indices {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                let n = (b - a).cross(c - a);
                total += 0.5 * n.length();
                let shading = mesh.normals.as_ref().unwrap()[t[0] as usize];
                assert!(n.dot(shading) > 0.0, "{name}: triangle {t:?} winds against its normal");
            }
            // The cylinder's polygon is a little smaller than the circle.
            assert!(
                (total - area).abs() < 0.01 * area,
                "{name}: area {total}, expected {area}"
            );
        }
    }
}
