//! The format-neutral scene description every reader produces and the builder consumes.
//! Values are validated by the readers; each item keeps the location it came from so that
//! the builder's errors point into the scene file too.

use crate::Location;
use glam::Vec3;
use penumbra_core::{Rgb, SamplerKind, Transform};
use penumbra_geometry::{AccelKind, TriangleMesh};
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::{DirectOptions, Integrator, IntegratorKind, IntegratorOptions};
use penumbra_render::media::{Medium, MediumInterface};
use penumbra_render::spectral::{MaterialSpectra, SpectrumValue};
use penumbra_render::{Filter, Material, Texture};
use std::sync::Arc;

#[derive(Clone, Debug)]
pub struct SceneDesc {
    pub render: RenderDesc,
    pub camera: CameraDesc,
    pub background: Rgb,
    pub ambient: Rgb,
    pub materials: Vec<MaterialDesc>,
    /// Meshes that instances share.
    pub meshes: Vec<Arc<TriangleMesh>>,
    pub shapes: Vec<ShapeDesc>,
    pub lights: Vec<LightDesc>,
    pub environment: Option<EnvironmentDesc>,
    /// The participating media, which shapes and the camera refer to by index.
    pub media: Vec<MediumDesc>,
    /// The medium the camera sits in (an index into `media`).
    pub camera_medium: Option<u32>,
    /// Every camera of a file that defines several (glTF), in its order, with the image size
    /// each asks for; `camera` is the first. Empty when the file defines one or none.
    pub cameras: Vec<CameraChoice>,
    /// What the reader skipped or changed, for the user: each names the place in the file.
    pub warnings: Vec<String>,
}

/// Image and sampling settings; the command line may override them.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderDesc {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u64,
    pub integrator: IntegratorKind,
    pub max_depth: u32,
    /// The depth from which `path` plays Russian roulette.
    pub rr_depth: u32,
    pub min_weight: f32,
    pub sampler: SamplerKind,
    pub filter: Filter,
    pub accel: AccelKind,
    /// Settings of the `direct` integrator.
    pub direct: DirectOptions,
    /// Settings of the `mlt` integrator.
    pub mlt: penumbra_render::integrators::MltOptions,
    /// Settings of the `sppm` and `photon` integrators.
    pub photon: penumbra_render::integrators::PhotonOptions,
    /// Settings of the `env` integrator.
    pub env: penumbra_render::integrators::EnvOptions,
    /// Paths carry four sampled wavelengths instead of RGB (`path` and `volpath`).
    pub spectral: bool,
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            width: 640,
            height: 480,
            spp: 4,
            seed: 0,
            integrator: IntegratorKind::Whitted,
            max_depth: 5,
            rr_depth: penumbra_render::integrators::RR_DEPTH,
            min_weight: 1e-3,
            sampler: SamplerKind::default(),
            filter: Filter::default(),
            accel: AccelKind::default(),
            direct: DirectOptions::default(),
            mlt: Default::default(),
            photon: Default::default(),
            env: Default::default(),
            spectral: false,
        }
    }
}

impl RenderDesc {
    /// The integrator these settings name, with them (`debug_strategies`: `bdpt` keeps each
    /// strategy's image).
    pub fn integrator(&self, debug_strategies: bool) -> Box<dyn Integrator> {
        self.integrator.create(IntegratorOptions {
            max_depth: self.max_depth,
            min_weight: self.min_weight,
            rr_depth: self.rr_depth,
            direct: self.direct,
            debug_strategies,
            mlt: self.mlt,
            photon: self.photon,
            env: self.env,
            seed: self.seed,
        })
    }
}

#[derive(Clone, Debug)]
pub struct CameraDesc {
    pub kind: CameraKind,
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// The image's x axis runs along up x forward instead of forward x up: the view of a
    /// left-handed camera (pbrt's), whose image is the mirror of a right-handed one's.
    pub mirrored: bool,
    pub location: Option<Location>,
}

/// One of a file's cameras, with the image size it asks for.
#[derive(Clone, Debug)]
pub struct CameraChoice {
    pub camera: CameraDesc,
    pub width: u32,
    pub height: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum CameraKind {
    Perspective {
        fov: f32,
        fov_axis: FovAxis,
        /// Thin-lens radius; 0 for a pinhole.
        aperture_radius: f32,
        /// Distance of the plane in focus; `None`: the target's.
        focus_distance: Option<f32>,
    },
    Orthographic {
        height: f32,
    },
}

impl CameraDesc {
    /// A camera at the origin of `to_world`, looking along its +z with its +y up, whose
    /// image x runs along `right_sign` times its +x (pbrt's cameras: +1; Mitsuba's, whose x
    /// points left: -1); mirrored where that is not forward x up.
    pub fn from_frame(kind: CameraKind, to_world: &Transform, right_sign: f32, location: Option<Location>) -> Self {
        let position = to_world.point(Vec3::ZERO);
        let forward = to_world.vector(Vec3::Z);
        let up = to_world.vector(Vec3::Y);
        let mirrored = (to_world.vector(Vec3::X) * right_sign).dot(forward.cross(up)) < 0.0;
        CameraDesc {
            kind,
            position,
            target: position + forward,
            up,
            mirrored,
            location,
        }
    }
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            kind: CameraKind::Perspective {
                fov: 45.0,
                fov_axis: FovAxis::Y,
                aperture_radius: 0.0,
                focus_distance: None,
            },
            position: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            mirrored: false,
            location: None,
        }
    }
}

#[derive(Clone, Debug)]
pub struct MaterialDesc {
    pub name: String,
    pub material: Material,
    /// The spectra the file gives for some of the material's parameters (spectral mode
    /// evaluates them; RGB mode uses `material`'s colours, their projections).
    pub spectra: Option<MaterialSpectra>,
}

/// A named participating medium.
#[derive(Clone, Debug)]
pub struct MediumDesc {
    pub name: String,
    pub medium: Medium,
    pub location: Option<Location>,
}

#[derive(Clone, Debug)]
pub struct ShapeDesc {
    pub kind: ShapeKind,
    /// Object to world.
    pub transform: Transform,
    /// Index into [`SceneDesc::materials`]; `None` for the default material.
    pub material: Option<usize>,
    /// Light the surface emits, if it is an area light.
    pub emission: Option<Emission>,
    /// The media inside and outside the shape (indices into [`SceneDesc::media`]), if it
    /// bounds a medium.
    pub media: Option<MediumInterface>,
    pub location: Option<Location>,
}

/// Diffuse emission: radiance from the front side, or from both sides; constant, or scaled
/// by a texture over a mesh with texture coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Emission {
    pub radiance: Rgb,
    pub two_sided: bool,
    pub texture: Option<Texture>,
    /// The emitter's own spectrum and its scale (the radiance is scale × spectrum, whose
    /// colour `radiance` is; spectral mode uses it).
    pub spectrum: Option<(SpectrumValue, f32)>,
}

#[derive(Clone, Debug)]
pub enum ShapeKind {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Plane {
        point: Vec3,
        normal: Vec3,
    },
    Quad {
        corner: Vec3,
        edge1: Vec3,
        edge2: Vec3,
    },
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
    },
    Box {
        min: Vec3,
        max: Vec3,
    },
    /// A mesh in object space, copied into world space.
    Mesh(Arc<TriangleMesh>),
    /// An instance of `SceneDesc::meshes[mesh]`.
    Instance {
        mesh: usize,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub enum LightDesc {
    Point {
        position: Vec3,
        intensity: Rgb,
    },
    Spot {
        position: Vec3,
        target: Vec3,
        intensity: Rgb,
        cone_angle: f32,
        falloff_start: f32,
    },
    Directional {
        direction: Vec3,
        irradiance: Rgb,
    },
}

/// Light from every direction at infinity.
#[derive(Clone, Debug)]
pub struct EnvironmentDesc {
    pub source: EnvironmentSource,
    /// Multiplies the map (or is the radiance of a constant environment).
    pub scale: Rgb,
    /// Turns the map; a rotation.
    pub transform: Transform,
    /// Degrees the map turns about the world's +y axis per animation frame
    /// ([`SceneDesc::at_frame`]); 0 for a still map.
    pub spin: f32,
    pub location: Option<Location>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    Constant,
    /// An equirectangular image file (.exr, .hdr, .pfm), resolved against the scene's folder.
    Image(std::path::PathBuf),
    /// A square image file in pbrt-v4's equal-area octahedral mapping ([`crate::octahedral`]).
    Octahedral(std::path::PathBuf),
}

impl SceneDesc {
    /// The scene at animation frame `frame`: the environment turned by its `spin` times the
    /// frame number about +y (after its own transform). Nothing else moves yet.
    pub fn at_frame(&self, frame: u32) -> SceneDesc {
        let mut d = self.clone();
        if let Some(env) = d.environment.as_mut().filter(|e| e.spin != 0.0) {
            let degrees = (env.spin as f64 * frame as f64).rem_euclid(360.0) as f32;
            if let Some(turn) = Transform::rotate(glam::Vec3::Y, degrees) {
                env.transform = env.transform.then(turn);
            }
        }
        d
    }

    /// An empty scene: default camera and settings, nothing in it.
    pub fn empty() -> Self {
        SceneDesc {
            render: RenderDesc::default(),
            camera: CameraDesc::default(),
            background: Rgb::BLACK,
            ambient: Rgb::BLACK,
            materials: Vec::new(),
            meshes: Vec::new(),
            shapes: Vec::new(),
            lights: Vec::new(),
            environment: None,
            media: Vec::new(),
            camera_medium: None,
            cameras: Vec::new(),
            warnings: Vec::new(),
        }
    }
}
