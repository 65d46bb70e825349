//! Turns a [`SceneDesc`] into a renderable [`Scene`]: shapes placed in world space, shared
//! meshes given one accelerator each, the top-level accelerator built, lights and camera
//! set up.

use crate::desc::{CameraKind, EnvironmentDesc, EnvironmentSource, LightDesc, RenderDesc, SceneDesc, ShapeKind};
use crate::emitters::area_lights;
use crate::{Location, SceneError};
use penumbra_core::{Draw, SamplerKind, Transform};
use penumbra_geometry::shapes::{Cuboid, Disk, Plane, Quad, Sphere};
use penumbra_geometry::{GeometryBuilder, Instance, MeshAccel, Shape};
use penumbra_render::cameras::{Orthographic, Perspective};
use penumbra_render::integrators::IntegratorKind;
use penumbra_render::lights::{Directional, Environment, LightSetBuilder, Point, Spot};
use penumbra_render::materials::{Phong, MAX_NESTING};
use penumbra_render::spectral::EmitterSpectrum;
use penumbra_render::texture::TextureImage;
use penumbra_render::{Camera, Light, Material, Scene};
use std::sync::Arc;

/// Builds the scene with the accelerator the description asks for.
pub fn build_scene(desc: &SceneDesc) -> Result<Scene, SceneError> {
    let fail = |loc: &Option<Location>, message: &str| match loc {
        Some(l) => SceneError::at(l.clone(), message),
        None => SceneError::Io {
            path: "<scene>".into(),
            message: message.to_string(),
        },
    };

    desc.render.direct.check().map_err(|e| fail(&None, &e))?;
    let mut materials: Vec<Material> = desc.materials.iter().map(|m| m.material.clone()).collect();
    let default_material = materials.len() as u32;
    materials.push(Material::Phong(Phong::default()));

    // Descriptions built in code skip the reader's checks: check the references here.
    let bad_medium = |m: Option<u32>| m.is_some_and(|m| m as usize >= desc.media.len());
    if bad_medium(desc.camera_medium) {
        return Err(fail(
            &desc.camera.location,
            "the camera is in a medium the scene does not define",
        ));
    }
    for s in &desc.shapes {
        if s.media.is_some_and(|m| bad_medium(m.inside) || bad_medium(m.outside)) {
            return Err(fail(
                &s.location,
                "a shape refers to a medium the scene does not define",
            ));
        }
        let bad_material = s.material.is_some_and(|m| m >= desc.materials.len());
        let bad_mesh = matches!(s.kind, ShapeKind::Instance { mesh } if mesh >= desc.meshes.len());
        if bad_material || bad_mesh {
            return Err(fail(
                &s.location,
                "a shape refers to a material or mesh the scene does not define",
            ));
        }
        if let Some(m) = s.material.map(|m| &desc.materials[m]) {
            let depth = m.material.nesting();
            if depth > MAX_NESTING {
                return Err(fail(
                    &s.location,
                    &format!(
                        "material '{}' nests blends, two-sided and normal-mapped materials {depth} deep; at most {MAX_NESTING} are supported",
                        m.name
                    ),
                ));
            }
        }
    }
    let shared: Vec<Arc<MeshAccel>> = desc
        .meshes
        .iter()
        .map(|m| Arc::new(MeshAccel::new(m.clone(), desc.render.accel)))
        .collect();
    let mut builder = GeometryBuilder::new();
    let mut object_materials = Vec::with_capacity(desc.shapes.len());
    let mut object_media = Vec::with_capacity(desc.shapes.len());
    let mut emitters = Vec::new();
    for s in &desc.shapes {
        let t = &s.transform;
        let degenerate = |what: &str| fail(&s.location, &format!("the {what} is degenerate under its transform"));
        let shape = match &s.kind {
            ShapeKind::Sphere { center, radius } => Some(Shape::Sphere(
                Sphere::new(*center, *radius, t).ok_or_else(|| degenerate("sphere"))?,
            )),
            ShapeKind::Plane { point, normal } => Some(Shape::Plane(
                Plane::new(*point, *normal, t).ok_or_else(|| degenerate("plane"))?,
            )),
            ShapeKind::Quad { corner, edge1, edge2 } => Some(Shape::Quad(
                Quad::new(*corner, *edge1, *edge2, t).ok_or_else(|| degenerate("quad"))?,
            )),
            ShapeKind::Disk { center, normal, radius } => Some(Shape::Disk(
                Disk::new(*center, *normal, *radius, t).ok_or_else(|| degenerate("disk"))?,
            )),
            ShapeKind::Box { min, max } => Some(Shape::Cuboid(
                Cuboid::new(*min, *max, t).ok_or_else(|| degenerate("box"))?,
            )),
            ShapeKind::Mesh(_) | ShapeKind::Instance { .. } => None,
        };
        let object = match (shape, &s.kind) {
            (Some(shape), _) => builder.add_shape(shape),
            (None, ShapeKind::Mesh(mesh)) => builder.add_mesh(mesh.transformed(t)),
            (None, ShapeKind::Instance { mesh }) => builder.add_instance(Instance::new(shared[*mesh].clone(), t)),
            (None, _) => unreachable!("every analytic shape was converted above"),
        };
        debug_assert_eq!(object as usize, object_materials.len());
        object_materials.push(s.material.map_or(default_material, |m| m as u32));
        object_media.push(s.media);
        if let Some(emission) = &s.emission {
            let area = area_lights(&s.kind, t, emission, &desc.meshes).map_err(|e| fail(&s.location, &e))?;
            let spectrum = emission.spectrum.clone().map(|(spectrum, scale)| EmitterSpectrum {
                spectrum,
                scale,
                rgb: emission.radiance,
            });
            emitters.push((object, area, spectrum));
        }
    }
    let geometry = Arc::new(builder.build());
    let accel = geometry.accel(desc.render.accel);
    // The finite part of the scene's extent sizes the power of directional lights.
    let extent = geometry.finite_bounds();
    let scene_radius = if extent.is_finite() && !extent.is_empty() {
        0.5 * extent.extent().length()
    } else {
        1.0
    };

    let r = &desc.render;
    let c = &desc.camera;
    let to_world = Transform::look_at(c.position, c.target, c.up).ok_or_else(|| {
        fail(
            &c.location,
            "the camera's view direction is zero or parallel to its up vector",
        )
    })?;
    let to_world = match c.mirrored {
        true => Transform::scale(glam::Vec3::new(-1.0, 1.0, 1.0))
            .expect("a mirror is invertible")
            .then(to_world),
        false => to_world,
    };
    let camera = match c.kind {
        CameraKind::Perspective {
            fov,
            fov_axis,
            aperture_radius,
            focus_distance,
        } => {
            let focus = focus_distance.unwrap_or_else(|| (c.target - c.position).length());
            Camera::Perspective(
                Perspective::new(to_world, fov, fov_axis, r.width, r.height).with_lens(aperture_radius, focus),
            )
        }
        CameraKind::Orthographic { height } => {
            Camera::Orthographic(Orthographic::new(to_world, height, r.width, r.height))
        }
    };

    let mut lights = LightSetBuilder::new(scene_radius);
    // The emitters' spectra, per light: the emitters' lights come first, in this order.
    let mut light_spectra = Vec::new();
    for (object, area, spectrum) in emitters {
        light_spectra.extend(std::iter::repeat_n(spectrum, area.len()));
        lights.add_emitter(object, area);
    }
    for light in desc.lights.iter().map(|l| match *l {
        LightDesc::Point { position, intensity } => Light::Point(Point { position, intensity }),
        LightDesc::Spot {
            position,
            target,
            intensity,
            cone_angle,
            falloff_start,
        } => Light::Spot(Spot::new(
            position,
            target - position,
            intensity,
            cone_angle,
            falloff_start,
        )),
        LightDesc::Directional { direction, irradiance } => Light::Directional(Directional {
            direction: direction.normalize(),
            irradiance,
        }),
    }) {
        lights.add(light);
    }
    let environment = match &desc.environment {
        Some(e) => Some(lights.add(Light::Environment(
            environment(e, &desc.render).map_err(|m| fail(&e.location, &m))?,
        ))),
        None => None,
    };
    let lights = lights.build();

    Ok(Scene {
        camera,
        width: r.width,
        height: r.height,
        filter: r.filter,
        geometry,
        accel,
        materials,
        object_materials,
        lights,
        environment,
        background: desc.background,
        ambient: desc.ambient,
        sphere: (glam::Vec3::ZERO, 1.0),
        media: desc.media.iter().map(|m| m.medium.clone()).collect(),
        object_media,
        camera_medium: desc.camera_medium,
        null_materials: Vec::new(),
        // Only `path` and `volpath` trace spectral paths; the others render RGB colours.
        spectral: desc.render.spectral
            && matches!(desc.render.integrator, IntegratorKind::Path | IntegratorKind::Volpath),
        material_spectra: desc.materials.iter().map(|m| m.spectra.clone().map(Arc::new)).collect(),
        light_spectra,
    }
    .prepared())
}

/// The environment light `e` describes, its map loaded; the error names the map. Its
/// cells are drawn by the alias method when the integrator takes the pixel sampler's
/// numbers and the sampler gives independent ones (faster, nothing to keep stratified);
/// else by inverting the CDFs, which keeps a stratified or low-discrepancy sampler's
/// numbers stratified over the map, and keeps near numbers near for an integrator that
/// draws its own (`Capabilities::own_numbers`: Metropolis' small mutations, Kelemen et
/// al. 2002; sppm's and smc's Sobol sequences).
fn environment(e: &EnvironmentDesc, render: &RenderDesc) -> Result<Environment, String> {
    let (path, octahedral) = match &e.source {
        EnvironmentSource::Constant => return Ok(Environment::constant(e.scale)),
        EnvironmentSource::Image(path) => (path, false),
        EnvironmentSource::Octahedral(path) => (path, true),
    };
    let image = crate::image_input::read_input_image(path, false)
        .map_err(|err| format!("cannot read the environment map {}: {err}", path.display()))?;
    let mut image = TextureImage {
        width: image.width as usize,
        height: image.height as usize,
        pixels: image.pixels,
        wrap: Default::default(),
    };
    if octahedral {
        if image.width != image.height {
            return Err(format!(
                "the environment map {} is {} x {}: pbrt's equal-area maps are square",
                path.display(),
                image.width,
                image.height
            ));
        }
        image = crate::octahedral::to_equirect(&image);
    }
    // The map's frame: the transform's rotation (its columns made unit length).
    let m = glam::Mat3::from_mat4(e.transform.m);
    let rotation = glam::Mat3::from_cols(m.x_axis.normalize(), m.y_axis.normalize(), m.z_axis.normalize());
    let own_numbers = render.integrator(false).capabilities().own_numbers.is_some();
    let draw = match render.sampler {
        SamplerKind::Independent if !own_numbers => Draw::Alias,
        _ => Draw::Inverted,
    };
    Environment::image(image, e.scale, rotation, draw)
        .map_err(|m| format!("the environment map {}: {m}", path.display()))
}
