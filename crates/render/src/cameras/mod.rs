//! Cameras: map a position on the film (in pixels, y down) to a ray into the scene.
//!
//! Both cameras are placed by a look-at: `position`, `target`, `up` (default `[0, 1, 0]`).
//! Adding a camera: a new file with `generate_ray`, one variant and one match arm (and an
//! [`ImagePlane`] if light paths may reach it).

mod importance;
mod orthographic;
mod perspective;

pub use importance::{CameraSample, ImagePlane};
pub use orthographic::Orthographic;
pub use perspective::{FovAxis, Perspective};

use glam::Vec2;
use penumbra_core::Ray;

#[derive(Clone, Debug, PartialEq)]
pub enum Camera {
    Perspective(Perspective),
    Orthographic(Orthographic),
}

impl Camera {
    /// The ray through film position `film` (pixels; (0, 0) is the top-left corner of the
    /// image, (width, height) the bottom-right), leaving a thin lens at the point `u_lens`
    /// picks (ignored by pinholes). Directions are unit length.
    pub fn generate_ray(&self, film: Vec2, u_lens: Vec2) -> Ray {
        match self {
            Camera::Perspective(c) => c.generate_ray(film, u_lens),
            Camera::Orthographic(c) => c.generate_ray(film),
        }
    }

    /// The camera as a sensor that light paths can be connected to; `None` for the
    /// orthographic camera, whose rays are all parallel (a delta in direction).
    pub fn image_plane(&self) -> Option<&ImagePlane> {
        match self {
            Camera::Perspective(c) => Some(c.plane()),
            Camera::Orthographic(_) => None,
        }
    }

    /// Whether rays need a lens sample.
    pub fn has_lens(&self) -> bool {
        matches!(self, Camera::Perspective(c) if c.has_lens())
    }
}
