//! The pinhole perspective camera.
//!
//! Native format: `type = "perspective"`, `fov` (degrees, default 45), `fov_axis`
//! (`"x"`, `"y"`, `"smaller"` or `"larger"` image side the field of view spans, default `"y"`).

use glam::{Vec2, Vec3};
use penumbra_core::{Ray, Transform};

/// Which image side the field of view spans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FovAxis {
    X,
    #[default]
    Y,
    Smaller,
    Larger,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Perspective {
    to_world: Transform,
    /// Half-extent of the image plane at distance 1, in x and y.
    tan_half: Vec2,
    resolution: Vec2,
}

impl Perspective {
    /// `fov` in degrees, in (0, 180).
    pub fn new(to_world: Transform, fov: f32, axis: FovAxis, width: u32, height: u32) -> Self {
        let aspect = width as f32 / height as f32;
        let t = (0.5 * fov.to_radians()).tan();
        let spans_x = match axis {
            FovAxis::X => true,
            FovAxis::Y => false,
            FovAxis::Smaller => width <= height,
            FovAxis::Larger => width > height,
        };
        let tan_half = if spans_x {
            Vec2::new(t, t / aspect)
        } else {
            Vec2::new(t * aspect, t)
        };
        Perspective {
            to_world,
            tan_half,
            resolution: Vec2::new(width as f32, height as f32),
        }
    }

    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let ndc = film / self.resolution * 2.0 - Vec2::ONE;
        let d = Vec3::new(ndc.x * self.tan_half.x, -ndc.y * self.tan_half.y, -1.0);
        Ray::new(self.to_world.point(Vec3::ZERO), self.to_world.vector(d).normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_span_the_field_of_view() {
        let eye = Transform::look_at(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y).unwrap();
        let cam = Perspective::new(eye, 90.0, FovAxis::Y, 200, 100);
        let centre = cam.generate_ray(Vec2::new(100.0, 50.0));
        assert!((centre.dir - Vec3::NEG_Z).length() < 1e-6);
        let top = cam.generate_ray(Vec2::new(100.0, 0.0)).dir;
        assert!((top.y / -top.z - 1.0).abs() < 1e-5, "45 degrees up at the top edge");
        let right = cam.generate_ray(Vec2::new(200.0, 50.0)).dir;
        assert!((right.x / -right.z - 2.0).abs() < 1e-5, "aspect 2");
    }
}
