//! The renderable scene: camera, film settings, geometry with its accelerator, materials
//! and lights. Built from a scene description by `penumbra-scene`.

use crate::lights::{AreaLight, Environment, Light, LightSet, SceneSphere};
use crate::media::{Medium, MediumInterface};
use crate::spectral::{EmitterSpectrum, MaterialSpectra};
use crate::{Camera, Filter, Material};
use glam::Vec3;
use penumbra_core::{Ray, Rgb};
use penumbra_geometry::{Accel, Geometry, Hit, SurfaceHit};
use std::sync::Arc;

pub struct Scene {
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub filter: Filter,
    pub geometry: Arc<Geometry>,
    pub accel: Box<dyn Accel>,
    pub materials: Vec<Material>,
    /// The material of each scene object (as numbered by the geometry builder).
    pub object_materials: Vec<u32>,
    pub lights: LightSet,
    /// The index in `lights` of the environment light, if the scene has one.
    pub environment: Option<u32>,
    /// Radiance of rays that leave a scene without an environment light (seen, and
    /// reflected by the path tracer, but not sampled as a light).
    pub background: Rgb,
    /// Ambient light, reflected by the diffuse albedo of every surface.
    pub ambient: Rgb,
    /// The bounding sphere of the finite geometry, where lights at infinity send light
    /// paths; made by [`Scene::prepared`].
    pub sphere: SceneSphere,
    /// The participating media (empty for a scene in vacuum).
    pub media: Vec<Medium>,
    /// The media on the two sides of each scene object that has them (`None`: the object
    /// is no boundary, a ray crossing it stays in its medium).
    pub object_media: Vec<Option<MediumInterface>>,
    /// The medium the camera sits in.
    pub camera_medium: Option<u32>,
    /// Whether each material is [`Material::null`], a boundary between media only; made
    /// by [`Scene::prepared`] (the per-hit test reads it instead of comparing materials).
    pub null_materials: Vec<bool>,
    /// Whether paths carry four sampled wavelengths instead of RGB ([`crate::spectral`]).
    pub spectral: bool,
    /// The spectra materials give for their parameters, per material (empty, or as long as
    /// `materials`); used in spectral mode.
    pub material_spectra: Vec<Option<Arc<MaterialSpectra>>>,
    /// The emitters' own spectra, per light (empty, or as long as the light list).
    pub light_spectra: Vec<Option<EmitterSpectrum>>,
}

/// A ray's closest surface hit, with what shading needs.
pub struct Interaction<'a> {
    pub surface: SurfaceHit,
    pub material: &'a Material,
    /// Unit direction back along the ray.
    pub wo: Vec3,
}

impl Scene {
    /// The scene with its derived tables ([`Scene::sphere`], [`Scene::null_materials`])
    /// made from its fields.
    pub fn prepared(mut self) -> Self {
        self.null_materials = self.materials.iter().map(Material::is_null).collect();
        let b = self.geometry.finite_bounds();
        self.sphere = if b.is_finite() && !b.is_empty() {
            (b.centroid(), (0.5 * b.extent().length()).max(1e-3))
        } else {
            (Vec3::ZERO, 1.0)
        };
        self
    }

    /// The closest surface along `ray` in `(0, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Interaction<'_>> {
        let hit = self.accel.intersect(ray, t_max)?;
        Some(self.interaction(ray, &hit))
    }

    /// The surface at `hit`, which `ray` produced, with its material.
    pub fn interaction(&self, ray: &Ray, hit: &Hit) -> Interaction<'_> {
        let surface = self.geometry.surface(ray, hit);
        Interaction {
            material: self.material_of(surface.object),
            surface,
            wo: -ray.dir.normalize(),
        }
    }

    /// The media on the two sides of scene object `object`, if it separates media.
    pub fn media_of(&self, object: u32) -> Option<&MediumInterface> {
        self.object_media.get(object as usize)?.as_ref()
    }

    /// Whether scene object `object` is only a boundary between media ([`Material::null`]).
    pub fn is_boundary(&self, object: u32) -> bool {
        self.null_materials[self.object_materials[object as usize] as usize]
    }

    /// The spectra the material of scene object `object` gives, if any.
    pub fn spectra_of(&self, object: u32) -> Option<&MaterialSpectra> {
        let m = *self.object_materials.get(object as usize)? as usize;
        self.material_spectra.get(m)?.as_deref()
    }

    /// The spectrum of light `index`, if it has its own.
    pub fn light_spectrum(&self, index: u32) -> Option<&EmitterSpectrum> {
        self.light_spectra.get(index as usize)?.as_ref()
    }

    /// The material of scene object `object`.
    pub fn material_of(&self, object: u32) -> &Material {
        &self.materials[self.object_materials[object as usize] as usize]
    }

    /// [`Scene::occluded`] for each `(ray, t_max)` of `rays`, into `blocked`.
    pub fn occluded_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
        self.accel.occluded_batch(rays, blocked);
    }

    /// The area light at the surface `it` hit, with its index in [`Scene::lights`].
    pub fn emitter_at(&self, it: &Interaction) -> Option<(u32, &AreaLight)> {
        self.lights.emitter_of(it.surface.object, it.surface.triangle)
    }

    /// Radiance the surface `it` hit emits back along the ray.
    pub fn emitted(&self, it: &Interaction) -> Rgb {
        self.emitter_at(it).map_or(Rgb::BLACK, |(_, light)| {
            light.le(it.surface.p, light.emitter.normal_at(it.surface.p), it.wo)
        })
    }

    /// The environment light and its index in [`Scene::lights`].
    pub fn environment(&self) -> Option<(u32, &Environment)> {
        let index = self.environment?;
        match &self.lights.lights()[index as usize] {
            Light::Environment(env) => Some((index, env)),
            _ => None,
        }
    }

    /// Radiance arriving along a ray of direction `dir` that leaves the scene.
    pub fn escaped(&self, dir: Vec3) -> Rgb {
        self.environment().map_or(self.background, |(_, env)| env.le(dir))
    }

    /// Whether anything blocks `ray` in `(0, t_max)`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.accel.occluded(ray, t_max)
    }
}
