//! Area lights from emitting shapes: each shape's world-space geometry as
//! [`EmitterShape`]s, oriented so that the emitter's front is the side the shape's normal
//! points to (transforms that mirror space included). A textured emission needs a mesh
//! with texture coordinates: each triangle's light carries its corners' coordinates.

use crate::desc::{Emission, ShapeKind};
use glam::{Vec2, Vec3};
use penumbra_core::{Frame, Transform};
use penumbra_geometry::TriangleMesh;
use penumbra_render::lights::emitter::{Emitter, EmitterShape};
use penumbra_render::lights::{AreaLight, EmissionTexture};
use std::sync::Arc;

/// The area lights of a shape of `kind` placed by `t`: one for an analytic shape, one per
/// triangle for a mesh. The error says what is wrong, for the shape's location.
pub fn area_lights(
    kind: &ShapeKind,
    t: &Transform,
    emission: &Emission,
    meshes: &[Arc<TriangleMesh>],
) -> Result<Vec<AreaLight>, String> {
    let light = |shape: EmitterShape, uvs: Option<[Vec2; 3]>| -> Result<AreaLight, String> {
        let emitter = Emitter::new(shape).ok_or("the emitting shape has no area (under its transform)")?;
        let texture = match (&emission.texture, uvs) {
            (Some(t), Some(uvs)) => Some(Box::new(EmissionTexture::new(t.clone(), uvs))),
            (Some(_), None) => return Err("a textured emission needs a mesh with texture coordinates".into()),
            (None, _) => None,
        };
        Ok(AreaLight {
            emitter,
            radiance: emission.radiance,
            two_sided: emission.two_sided,
            texture,
        })
    };
    // Orders two edges so that their cross product faces `front`.
    let facing = |a: Vec3, b: Vec3, front: Vec3| if a.cross(b).dot(front) < 0.0 { (b, a) } else { (a, b) };
    match kind {
        ShapeKind::Quad { corner, edge1, edge2 } => {
            let (e1, e2) = facing(t.vector(*edge1), t.vector(*edge2), t.normal(edge1.cross(*edge2)));
            Ok(vec![light(
                EmitterShape::Quad {
                    corner: t.point(*corner),
                    e1,
                    e2,
                },
                None,
            )?])
        }
        ShapeKind::Disk { center, normal, radius } => {
            let f = Frame::from_normal(normal.try_normalize().ok_or("the disk's normal is zero")?);
            let (a1, a2) = facing(t.vector(f.s * *radius), t.vector(f.t * *radius), t.normal(f.n));
            Ok(vec![light(
                EmitterShape::Disk {
                    center: t.point(*center),
                    a1,
                    a2,
                },
                None,
            )?])
        }
        ShapeKind::Sphere { center, radius } => {
            let axes = [Vec3::X, Vec3::Y, Vec3::Z].map(|a| t.vector(a * *radius));
            let r = axes[0].length();
            let round = axes.iter().all(|a| (a.length() - r).abs() <= 1e-4 * r)
                && axes[0].dot(axes[1]).abs() <= 1e-4 * r * r
                && axes[1].dot(axes[2]).abs() <= 1e-4 * r * r
                && axes[0].dot(axes[2]).abs() <= 1e-4 * r * r;
            if !round {
                return Err("an emitting sphere must stay a sphere: its transform stretches or shears it".into());
            }
            Ok(vec![light(
                EmitterShape::Sphere {
                    center: t.point(*center),
                    radius: r,
                },
                None,
            )?])
        }
        ShapeKind::Mesh(mesh) => mesh_lights(&mesh.transformed(t), &light),
        ShapeKind::Instance { mesh } => mesh_lights(&meshes[*mesh].transformed(t), &light),
        ShapeKind::Plane { .. } | ShapeKind::Box { .. } => {
            Err("only quads, disks, spheres and meshes can emit light".into())
        }
    }
}

/// One light per triangle of a world-space mesh, facing its vertex normals when it has them
/// (else its winding's side).
fn mesh_lights(
    mesh: &TriangleMesh,
    light: &dyn Fn(EmitterShape, Option<[Vec2; 3]>) -> Result<AreaLight, String>,
) -> Result<Vec<AreaLight>, String> {
    if mesh.indices.is_empty() {
        return Err("the emitting mesh has no triangles with area".into());
    }
    (0..mesh.indices.len())
        .map(|tri| {
            let [v0, v1, v2] = mesh.vertices(tri);
            let winding = (v1 - v0).cross(v2 - v0);
            let flip = mesh.normals.as_ref().is_some_and(|ns| {
                let sum: Vec3 = mesh.indices[tri].iter().map(|&i| ns[i as usize]).sum();
                sum.dot(winding) < 0.0
            });
            let v = if flip { [v0, v2, v1] } else { [v0, v1, v2] };
            let uvs = mesh.uvs.as_ref().map(|uvs| {
                let [a, b, c] = mesh.indices[tri].map(|i| uvs[i as usize]);
                if flip {
                    [a, c, b]
                } else {
                    [a, b, c]
                }
            });
            light(EmitterShape::Triangle { v }, uvs).map_err(|e| format!("triangle {tri} of the emitting mesh: {e}"))
        })
        .collect()
}
