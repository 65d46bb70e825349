//! The orthographic camera: parallel rays, no perspective.
//!
//! Native format: `type = "orthographic"`, `height` (world-space height of the visible
//! area, default 2); the width follows the image's aspect ratio.

use glam::{Vec2, Vec3};
use penumbra_core::{Ray, Transform};

#[derive(Clone, Debug, PartialEq)]
pub struct Orthographic {
    to_world: Transform,
    half_extent: Vec2,
    resolution: Vec2,
}

impl Orthographic {
    pub fn new(to_world: Transform, height: f32, width_px: u32, height_px: u32) -> Self {
        let aspect = width_px as f32 / height_px as f32;
        Orthographic {
            to_world,
            half_extent: Vec2::new(0.5 * height * aspect, 0.5 * height),
            resolution: Vec2::new(width_px as f32, height_px as f32),
        }
    }

    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let ndc = film / self.resolution * 2.0 - Vec2::ONE;
        let o = Vec3::new(ndc.x * self.half_extent.x, -ndc.y * self.half_extent.y, 0.0);
        Ray::new(self.to_world.point(o), self.to_world.vector(Vec3::NEG_Z).normalize())
    }
}
