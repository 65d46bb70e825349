//! A bare mesh (`.obj` or `.ply`) as a scene: what a user who asks "what does my mesh look
//! like?" expects to see. The mesh in its OBJ file's MTL materials ([`super::mtl`]) or a
//! two-sided light grey diffuse material, under a white
//! sky with a key light from the upper left behind the camera, seen from the front (+z, y
//! up, the convention of both formats), a little from above and the right, by a camera
//! that frames its bounding box; path traced, 64 samples per pixel, 800 x 600.
//! Everything can be overridden from the command line (`--spp`, `--res`, `--max-depth`,
//! `--integrator`).

use super::{drop_degenerate, mtl, obj, ply};
use crate::desc::{
    CameraDesc, CameraKind, Emission, EnvironmentDesc, EnvironmentSource, LightDesc, MaterialDesc, ShapeDesc,
};
use crate::desc::{RenderDesc, ShapeKind};
use crate::{SceneDesc, SceneError};
use glam::Vec3;
use penumbra_core::{Aabb, Rgb, Transform};
use penumbra_geometry::TriangleMesh;
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::IntegratorKind;
use penumbra_render::materials::DiffuseMaterial;
use penumbra_render::{Material, Texture};
use std::path::Path;
use std::sync::Arc;

/// A part's MTL material and emission.
type Look = (Material, Option<Emission>);

/// The camera's vertical field of view, degrees.
const FOV: f32 = 35.0;
/// The direction from the mesh's centre to the camera: in front (+z), 20 degrees to the
/// right and 25 degrees up.
fn view_direction() -> Vec3 {
    let (yaw, pitch) = (20f32.to_radians(), 25f32.to_radians());
    Vec3::new(yaw.sin() * pitch.cos(), pitch.sin(), yaw.cos() * pitch.cos())
}

/// Reads the mesh at `path` (`.obj` or `.ply`, by extension) into a scene that shows it.
pub fn read(path: &Path) -> Result<SceneDesc, SceneError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let mut warnings = Vec::new();
    // The mesh in parts, each with its MTL material and emission (OBJ), or whole (PLY).
    let mut parts: Vec<(TriangleMesh, Option<Look>)> = Vec::new();
    if ext.as_deref() == Some("obj") {
        let obj = obj::load_parts(path).map_err(|e| SceneError::io(path, e))?;
        if let Some(e) = &obj.mtl_error {
            warnings.push(format!(
                "{}: its material library cannot be read ({e}): grey is used",
                path.display()
            ));
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        for (mesh, id) in obj.parts {
            let m = id
                .and_then(|i| obj.materials.get(i))
                .map(|m| mtl::material(m, dir, &mut |w| warnings.push(w)));
            parts.push((mesh, m));
        }
    } else {
        parts.push((ply::load(path).map_err(|e| SceneError::io(path, e))?, None));
    }
    let mut bounds = Aabb::EMPTY;
    for (mesh, _) in &mut parts {
        warnings.extend(drop_degenerate(mesh, &path.display().to_string()));
        bounds = mesh.positions.iter().fold(bounds, |b, &p| b.grow(p));
    }
    if !bounds.min.is_finite() || !bounds.max.is_finite() {
        return Err(SceneError::io(
            path,
            "the mesh has a vertex that is not a finite number",
        ));
    }
    let mut desc = SceneDesc::empty();
    desc.render = default_render();
    desc.camera = frame(bounds);
    let grey = Material::TwoSided(Box::new(Material::Diffuse(DiffuseMaterial {
        reflectance: Texture::Constant(Rgb::splat(0.7)),
    })));
    for (mesh, m) in parts {
        let (material, emission) = m.unwrap_or((grey.clone(), None));
        desc.materials.push(MaterialDesc {
            name: format!("material {}", desc.materials.len()),
            material,
            spectra: None,
        });
        desc.shapes.push(ShapeDesc {
            kind: ShapeKind::Mesh(Arc::new(mesh)),
            transform: Transform::IDENTITY,
            material: Some(desc.materials.len() - 1),
            emission,
            media: None,
            location: None,
        });
    }
    default_lighting(&mut desc);
    desc.warnings = warnings;
    Ok(desc)
}

/// How a bare mesh (and a glTF scene, which says nothing of it) is rendered: path traced,
/// 64 samples per pixel, 800 x 600, paths of up to 8 segments.
pub(crate) fn default_render() -> RenderDesc {
    RenderDesc {
        width: 800,
        height: 600,
        spp: 64,
        integrator: IntegratorKind::Path,
        max_depth: 8,
        ..RenderDesc::default()
    }
}

/// A sky of radiance 0.3 and a key light of irradiance 1.5 from the upper left behind the
/// camera of [`frame`]: a grey surface of albedo 0.7 reads about 0.7 (0.3 + 1.5/pi) = 0.54
/// where it faces the light, 0.21 or less where only the sky lights it. (Also the lighting
/// of a glTF scene without lights.)
pub(crate) fn default_lighting(desc: &mut SceneDesc) {
    desc.environment = Some(EnvironmentDesc {
        source: EnvironmentSource::Constant,
        scale: Rgb::splat(0.3),
        transform: Transform::IDENTITY,
        spin: 0.0,
        location: None,
    });
    let right = Vec3::Y.cross(view_direction()).normalize();
    desc.lights.push(LightDesc::Directional {
        direction: -(view_direction() - right * 0.8 + Vec3::Y * 0.6).normalize(),
        irradiance: Rgb::splat(1.5),
    });
}

/// A camera looking at the centre of `bounds` along [`view_direction`], as near as it can
/// be with every corner of the bounds inside 90% of the frame's height and of its width
/// (for any image at least as wide as it is high).
pub(crate) fn frame(bounds: Aabb) -> CameraDesc {
    let center = (bounds.min + bounds.max) * 0.5;
    let forward = -view_direction();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let reach = 0.9 * (FOV.to_radians() * 0.5).tan();
    let distance = (0..8)
        .map(|k| {
            let pick = |bit: usize, axis: usize| {
                if k & bit == 0 {
                    bounds.min[axis]
                } else {
                    bounds.max[axis]
                }
            };
            let o = Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2)) - center;
            o.dot(right).abs().max(o.dot(up).abs()) / reach - o.dot(forward)
        })
        .fold(0.0f32, f32::max)
        .max(1e-4 * (bounds.max - bounds.min).length());
    CameraDesc {
        kind: CameraKind::Perspective {
            fov: FOV,
            fov_axis: FovAxis::Y,
            aperture_radius: 0.0,
            focus_distance: None,
        },
        position: center + view_direction() * distance,
        target: center,
        up: Vec3::Y,
        mirrored: false,
        location: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_render::materials::{DielectricMaterial, PlasticMaterial};
    use penumbra_render::Material;

    /// The camera frames the mesh: every corner of its bounds projects inside 90% of the
    /// image (vertical field of view, any aspect of at least 1), and one touches that edge.
    #[test]
    fn the_camera_frames_the_bounds() {
        for bounds in [
            Aabb {
                min: Vec3::new(-1.0, -1.0, -1.0),
                max: Vec3::new(1.0, 1.0, 1.0),
            },
            Aabb {
                min: Vec3::new(100.0, 5.0, -3.0),
                max: Vec3::new(100.5, 5.01, -2.0),
            },
            Aabb {
                min: Vec3::new(-0.1, 0.03, -0.06),
                max: Vec3::new(0.06, 0.19, 0.06),
            },
        ] {
            let cam = frame(bounds);
            let forward = (cam.target - cam.position).normalize();
            let right = forward.cross(cam.up).normalize();
            let up = right.cross(forward);
            let tan = (FOV.to_radians() * 0.5).tan();
            let mut widest = 0.0f32;
            for k in 0..8 {
                let corner = Vec3::new(
                    if k & 1 == 0 { bounds.min.x } else { bounds.max.x },
                    if k & 2 == 0 { bounds.min.y } else { bounds.max.y },
                    if k & 4 == 0 { bounds.min.z } else { bounds.max.z },
                );
                let d = corner - cam.position;
                let z = d.dot(forward);
                assert!(z > 0.0, "corner {corner} behind the camera");
                let (x, y) = (d.dot(right) / (z * tan), d.dot(up) / (z * tan));
                assert!(
                    x.abs() <= 0.9001 && y.abs() <= 0.9001,
                    "corner {corner} outside: {x} {y}"
                );
                widest = widest.max(x.abs()).max(y.abs());
            }
            assert!(widest > 0.899, "the bounds reach only {widest} of the frame");
        }
    }

    /// An OBJ with an MTL library: one shape per material, each mapped by its
    /// illumination model, `Ke` emitting; a missing library is a warning and grey.
    #[test]
    fn obj_materials_come_from_the_mtl_library() {
        let dir = tempfile::tempdir().unwrap();
        let mut obj = String::from("mtllib m.mtl\n");
        for k in 0..4 {
            let x = k as f32 * 2.0;
            obj += &format!("v {x} 0 0\nv {} 0 0\nv {x} 1 0\n", x + 1.0);
        }
        for (k, name) in ["matte", "glossy", "glass", "lamp"].iter().enumerate() {
            obj += &format!("usemtl {name}\nf {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3);
        }
        let mtl = "newmtl matte\nKd 0.2 0.4 0.6\nillum 1\n\
                   newmtl glossy\nKd 0.5 0.5 0.5\nKs 0.3 0.3 0.3\nNs 98\nillum 2\n\
                   newmtl glass\nNi 1.33\nd 0.4\nillum 4\n\
                   newmtl lamp\nKd 0 0 0\nKe 5 4 3\n";
        std::fs::write(dir.path().join("a.obj"), &obj).unwrap();
        std::fs::write(dir.path().join("m.mtl"), mtl).unwrap();
        let desc = read(&dir.path().join("a.obj")).unwrap();
        assert_eq!(desc.shapes.len(), 4, "{:?}", desc.warnings);
        let material = |k: usize| &desc.materials[desc.shapes[k].material.unwrap()].material;
        let inner = |k: usize| match material(k) {
            Material::TwoSided(m) => (**m).clone(),
            m => m.clone(),
        };
        assert!(
            matches!(inner(0), Material::Diffuse(DiffuseMaterial { reflectance: Texture::Constant(c) }) if c == Rgb::new(0.2, 0.4, 0.6))
        );
        match inner(1) {
            Material::Plastic(PlasticMaterial { roughness: Some(r), .. }) => {
                // Ns 98: alpha = sqrt(2 / 100).
                assert!(matches!(r.alpha_u, Texture::Constant(a) if (a.r - 0.02f32.sqrt()).abs() < 1e-6));
            }
            other => panic!("glossy: {other:?}"),
        }
        assert!(matches!(inner(2), Material::Dielectric(DielectricMaterial { eta, .. }) if eta == 1.33));
        assert_eq!(
            desc.shapes[3].emission.as_ref().map(|e| e.radiance),
            Some(Rgb::new(5.0, 4.0, 3.0))
        );
        assert!(desc.shapes[..3].iter().all(|s| s.emission.is_none()));
        // Without its library: one warning, grey.
        std::fs::remove_file(dir.path().join("m.mtl")).unwrap();
        let desc = read(&dir.path().join("a.obj")).unwrap();
        assert!(
            desc.warnings.iter().any(|w| w.contains("material library")),
            "{:?}",
            desc.warnings
        );
    }
}
