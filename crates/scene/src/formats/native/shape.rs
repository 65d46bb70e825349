//! `[[shape]]` and `[[mesh]]` tables, and the `transform` key.
//!
//! Every shape takes `material` (a material's name; the default is grey diffuse) and
//! `transform`: one step, or a list of steps applied in order, each `{ translate = [x, y, z] }`,
//! `{ scale = s }` or `{ scale = [x, y, z] }`, `{ rotate = degrees, axis = [x, y, z] }` or
//! `{ matrix = [16 numbers, row by row] }`.

use super::choice;
use super::medium;
use crate::desc::{Emission, MaterialDesc, MediumDesc, ShapeDesc, ShapeKind};
use crate::formats::{obj, ply};
use crate::params::{Result, Table, Value};
use crate::{SceneError, SourceFile};
use glam::{Mat4, Vec2, Vec3};
use penumbra_core::Transform;
use penumbra_geometry::TriangleMesh;
use penumbra_render::media::MediumInterface;
use std::sync::Arc;

const SHAPES: [&str; 7] = ["sphere", "plane", "quad", "disk", "box", "mesh", "instance"];

/// Reads the `[[mesh]]` tables: named meshes for instancing.
pub fn read_meshes(
    file: &Arc<SourceFile>,
    tables: &[Table],
    warnings: &mut Vec<String>,
) -> Result<Vec<(String, Arc<TriangleMesh>)>> {
    let mut out: Vec<(String, Arc<TriangleMesh>)> = Vec::new();
    for t in tables {
        let name_value = t.require("name")?;
        let name = name_value.str()?.to_string();
        if out.iter().any(|(n, _)| *n == name) {
            return Err(name_value
                .error(format!("mesh `{name}` is defined twice"))
                .label("second definition"));
        }
        let mesh = mesh_source(file, t, &format!("mesh `{name}`"), warnings)?;
        t.finish()?;
        out.push((name, Arc::new(mesh)));
    }
    Ok(out)
}

pub fn read(
    file: &Arc<SourceFile>,
    t: &Table,
    materials: &[MaterialDesc],
    media: &[MediumDesc],
    meshes: &[(String, Arc<TriangleMesh>)],
    warnings: &mut Vec<String>,
) -> Result<ShapeDesc> {
    let kind_value = t.require("type")?;
    let kind = choice(&kind_value, "shape type", &SHAPES, |s| {
        SHAPES.iter().find(|&&n| n == s).copied()
    })?;
    let kind = match kind {
        "sphere" => ShapeKind::Sphere {
            center: t.vec3_or("center", Vec3::ZERO)?,
            radius: t.positive_or("radius", 1.0)?,
        },
        "plane" => ShapeKind::Plane {
            point: t.vec3_or("point", Vec3::ZERO)?,
            normal: nonzero(t, "normal", Vec3::Y)?,
        },
        "quad" => {
            let edge1 = nonzero(t, "edge1", Vec3::new(2.0, 0.0, 0.0))?;
            let edge2 = nonzero(t, "edge2", Vec3::new(0.0, 2.0, 0.0))?;
            if edge1.cross(edge2).length_squared() == 0.0 {
                let at = t.get("edge2").map_or_else(|| t.location(), |v| v.location());
                return Err(SceneError::at(at, "a quad's edges must not be parallel").label("parallel to edge1"));
            }
            ShapeKind::Quad {
                corner: t.vec3_or("corner", Vec3::new(-1.0, -1.0, 0.0))?,
                edge1,
                edge2,
            }
        }
        "disk" => ShapeKind::Disk {
            center: t.vec3_or("center", Vec3::ZERO)?,
            normal: nonzero(t, "normal", Vec3::Y)?,
            radius: t.positive_or("radius", 1.0)?,
        },
        "box" => {
            let min = t.vec3_or("min", Vec3::splat(-1.0))?;
            let max = t.vec3_or("max", Vec3::ONE)?;
            if !min.cmplt(max).all() {
                let at = t.get("max").map_or_else(|| t.location(), |v| v.location());
                return Err(
                    SceneError::at(at, "a box's `max` must exceed its `min` on every axis").label("not above min")
                );
            }
            ShapeKind::Box { min, max }
        }
        "mesh" => ShapeKind::Mesh(Arc::new(mesh_source(file, t, "mesh shape", warnings)?)),
        _ => {
            let v = t.require("mesh")?;
            let name = v.str()?;
            let mesh = meshes.iter().position(|(n, _)| n == name).ok_or_else(|| {
                v.error(format!("no mesh named `{name}`"))
                    .label("unknown mesh")
                    .help(format!(
                        "define it in a [[mesh]] table; defined: {}",
                        names(meshes.iter().map(|m| &m.0))
                    ))
            })?;
            ShapeKind::Instance { mesh }
        }
    };
    let material = match t.get("material") {
        None => None,
        Some(v) => {
            let name = v.str()?;
            Some(materials.iter().position(|m| m.name == name).ok_or_else(|| {
                v.error(format!("no material named `{name}`"))
                    .label("unknown material")
                    .help(format!(
                        "defined materials: {}",
                        names(materials.iter().map(|m| &m.name))
                    ))
            })?)
        }
    };
    let transform = match t.get("transform") {
        Some(v) => transform(&v)?,
        None => Transform::IDENTITY,
    };
    let emission = emission(file, t, &kind, warnings)?;
    let (inside, outside) = (
        medium::reference(t, "interior", media)?,
        medium::reference(t, "exterior", media)?,
    );
    Ok(ShapeDesc {
        kind,
        transform,
        material,
        emission,
        media: (inside.is_some() || outside.is_some()).then_some(MediumInterface { inside, outside }),
        location: Some(t.location()),
    })
}

/// `emission = colour` (radiance) and `two_sided = bool` (default false): an area light.
/// Planes (infinite) and boxes cannot emit.
fn emission(file: &SourceFile, t: &Table, kind: &ShapeKind, warnings: &mut Vec<String>) -> Result<Option<Emission>> {
    let two_sided = t.get("two_sided");
    let Some(v) = t.get("emission") else {
        return match two_sided {
            Some(v) => Err(v
                .error("`two_sided` applies to emitting shapes only")
                .label("no `emission` in this shape")),
            None => Ok(None),
        };
    };
    if matches!(kind, ShapeKind::Plane { .. } | ShapeKind::Box { .. }) {
        return Err(v
            .error("only quads, disks, spheres and meshes can emit light")
            .label("this shape cannot be an area light")
            .help("build the light from quads, or a mesh"));
    }
    let radiance = v.rgb()?;
    if !radiance.is_finite() {
        return Err(v.error("emitted radiance must be finite").label("not finite"));
    }
    if radiance.is_black() {
        let (line, _) = file.line_col(v.location().span.start);
        warnings.push(format!(
            "{}:{line}: this shape's emission is zero: it gives no light",
            file.path.display()
        ));
    }
    Ok(Some(Emission {
        radiance,
        two_sided: two_sided.map_or(Ok(false), |v| v.bool())?,
        texture: None,
        spectrum: None,
    }))
}

pub(super) fn names<'a>(it: impl Iterator<Item = &'a String>) -> String {
    let v: Vec<&str> = it.map(String::as_str).collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

fn nonzero(t: &Table, key: &str, default: Vec3) -> Result<Vec3> {
    super::nonzero(t, key, default)
}

/// A mesh from `file = "..."` (OBJ or PLY) or inline `positions`, `indices` and optional
/// `normals` and `uvs`; `smooth = true` gives a mesh without normals smooth ones.
/// Triangles without area are dropped with a warning naming the mesh (`what`).
fn mesh_source(file: &Arc<SourceFile>, t: &Table, what: &str, warnings: &mut Vec<String>) -> Result<TriangleMesh> {
    let smooth = match t.get("smooth") {
        Some(v) => v.bool()?,
        None => false,
    };
    let mut mesh = mesh_data(file, t)?;
    let (line, _) = file.line_col(t.location().span.start);
    let place = format!("{}:{line}: {what}", file.path.display());
    warnings.extend(crate::formats::drop_degenerate(&mut mesh, &place));
    if smooth {
        mesh.compute_smooth_normals();
    }
    Ok(mesh)
}

fn mesh_data(file: &Arc<SourceFile>, t: &Table) -> Result<TriangleMesh> {
    if let Some(v) = t.get("file") {
        let rel = v.str()?;
        let base = file.path.parent().unwrap_or(std::path::Path::new("."));
        let path = base.join(rel);
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let loaded = match ext.as_deref() {
            Some("obj") => obj::load(&path),
            Some("ply") => ply::load(&path),
            _ => return Err(v.error("unsupported mesh format").label("expected a .obj or .ply file")),
        };
        return loaded.map_err(|e| {
            let what = if path.exists() {
                "cannot load mesh"
            } else {
                "mesh file not found"
            };
            v.error(format!("{what} {}: {e}", path.display())).label(what)
        });
    }
    let positions = points(&t.require("positions")?)?;
    let indices_value = t.require("indices")?;
    let indices = indices_value
        .array()?
        .iter()
        .map(|tri| {
            let items = tri.array()?;
            if items.len() != 3 {
                return Err(tri.error(format!("a triangle has 3 vertex indices, found {}", items.len())));
            }
            Ok([items[0].u32()?, items[1].u32()?, items[2].u32()?])
        })
        .collect::<Result<Vec<_>>>()?;
    let normals = t.get("normals").map(|v| points(&v)).transpose()?;
    let uvs = match t.get("uvs") {
        Some(v) => Some(
            v.array()?
                .iter()
                .map(|p| p.numbers(2).map(|n| Vec2::new(n[0], n[1])))
                .collect::<Result<Vec<_>>>()?,
        ),
        None => None,
    };
    let mesh = TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
    };
    mesh.validate()
        .map_err(|e| indices_value.error(format!("invalid mesh: {e}")))?;
    Ok(mesh)
}

fn points(v: &Value) -> Result<Vec<Vec3>> {
    v.array()?.iter().map(Value::vec3).collect()
}

/// A `transform`: one step or a list of steps, applied in order.
pub(super) fn transform(v: &Value) -> Result<Transform> {
    let steps = if v.is_table() {
        vec![v.table()?]
    } else {
        v.array()?.iter().map(Value::table).collect::<Result<_>>()?
    };
    let mut total = Transform::IDENTITY;
    for step in steps {
        let singular = |v: Value| {
            v.error("this transform step is singular (it collapses space)")
                .label("singular")
        };
        let next = if let Some(v) = step.get("translate") {
            Transform::translate(v.vec3()?)
        } else if let Some(v) = step.get("scale") {
            let s = if v.is_number() {
                Vec3::splat(v.f32()?)
            } else {
                v.vec3()?
            };
            Transform::scale(s).ok_or_else(|| singular(v))?
        } else if let Some(v) = step.get("rotate") {
            let axis = step.require("axis")?;
            let a = axis.vec3()?;
            Transform::rotate(a, v.f32()?).ok_or_else(|| axis.error("the rotation axis has zero length"))?
        } else if let Some(v) = step.get("matrix") {
            let m = v.numbers(16)?;
            Transform::from_matrix(Mat4::from_cols_slice(&m).transpose()).ok_or_else(|| {
                v.error("the matrix is singular or its last row is not [0, 0, 0, 1]")
                    .label("not affine")
            })?
        } else {
            return Err(
                step.error("a transform step needs one of `translate`, `scale`, `rotate` (with `axis`) or `matrix`")
            );
        };
        step.finish()?;
        total = total.then(next);
    }
    Ok(total)
}
