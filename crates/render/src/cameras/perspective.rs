//! The perspective camera: a pinhole, or a thin lens for depth of field (pbrt-v4 section
//! 5.2.3; Mitsuba's `thinlens`): rays start on a disk of radius `aperture_radius` about the
//! eye and pass through the point the pinhole ray meets on the plane of focus, so that the
//! plane at `focus_distance` is sharp and the rest blurs with the distance from it.
//!
//! Native format: `type = "perspective"`, `fov` (degrees, default 45), `fov_axis`
//! (`"x"`, `"y"`, `"smaller"` or `"larger"` image side the field of view spans, default
//! `"y"`), `aperture_radius` (default 0: a pinhole), `focus_distance` (default: the distance
//! to the target).

use super::importance::ImagePlane;
use glam::{Vec2, Vec3};
use penumbra_core::{warp, Ray, Transform};

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
    /// The lens radius and focus distance of a thin lens; `None` for a pinhole.
    lens: Option<(f32, f32)>,
    /// The same camera as a sensor, in world space (for light tracing).
    plane: ImagePlane,
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
        let resolution = Vec2::new(width as f32, height as f32);
        Perspective {
            plane: ImagePlane::new(&to_world, tan_half, resolution),
            to_world,
            tan_half,
            resolution,
            lens: None,
        }
    }

    /// The camera with a thin lens of radius `aperture_radius`, focused at `focus_distance`
    /// (both positive; a zero radius keeps the pinhole).
    pub fn with_lens(mut self, aperture_radius: f32, focus_distance: f32) -> Self {
        self.lens = (aperture_radius > 0.0).then_some((aperture_radius, focus_distance));
        self.plane = self.plane.with_lens(aperture_radius, focus_distance);
        self
    }

    /// The camera as a sensor that light paths can reach.
    pub fn plane(&self) -> &ImagePlane {
        &self.plane
    }

    pub fn has_lens(&self) -> bool {
        self.lens.is_some()
    }

    /// The ray through film position `film`, leaving the lens at the point `u_lens` maps to.
    pub fn generate_ray(&self, film: Vec2, u_lens: Vec2) -> Ray {
        let ndc = film / self.resolution * 2.0 - Vec2::ONE;
        let d = Vec3::new(ndc.x * self.tan_half.x, -ndc.y * self.tan_half.y, -1.0);
        let Some((radius, focus)) = self.lens else {
            return Ray::new(self.to_world.point(Vec3::ZERO), self.to_world.vector(d).normalize());
        };
        // The pinhole ray meets the plane of focus (z = -focus) at d * focus.
        let on_lens = (radius * warp::uniform_disk(u_lens)).extend(0.0);
        let dir = d * focus - on_lens;
        Ray::new(self.to_world.point(on_lens), self.to_world.vector(dir).normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_span_the_field_of_view() {
        let eye = Transform::look_at(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y).unwrap();
        let cam = Perspective::new(eye, 90.0, FovAxis::Y, 200, 100);
        let centre = cam.generate_ray(Vec2::new(100.0, 50.0), Vec2::ZERO);
        assert!((centre.dir - Vec3::NEG_Z).length() < 1e-6);
        let top = cam.generate_ray(Vec2::new(100.0, 0.0), Vec2::ZERO).dir;
        assert!((top.y / -top.z - 1.0).abs() < 1e-5, "45 degrees up at the top edge");
        let right = cam.generate_ray(Vec2::new(200.0, 50.0), Vec2::ZERO).dir;
        assert!((right.x / -right.z - 2.0).abs() < 1e-5, "aspect 2");
    }

    #[test]
    fn a_thin_lens_focuses_its_plane_and_spreads_over_its_aperture() {
        // Eye at (1, 2, 3) looking down -z; lens radius 0.2, focus at 4. Every lens sample's
        // ray through a film point meets the pinhole ray's point on the focus plane; the
        // origins fill the aperture disk (mean radius 2/3 of it, uniform by area).
        let eye = Transform::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, 0.0), Vec3::Y).unwrap();
        let pinhole = Perspective::new(eye, 60.0, FovAxis::Y, 64, 48);
        let lens = pinhole.clone().with_lens(0.2, 4.0);
        let mut u = penumbra_testkit::Uniforms::new(3);
        let mut mean_r = 0.0;
        let n = 20_000;
        for i in 0..n {
            let film = Vec2::new((i % 64) as f32 + 0.5, (i % 48) as f32 + 0.5);
            let p = pinhole.generate_ray(film, Vec2::ZERO);
            let focus = p.origin + p.dir * (4.0 / -p.dir.z);
            let r = lens.generate_ray(film, u.next_vec2());
            let hit = r.origin + r.dir * ((r.origin.z - (3.0 - 4.0)) / -r.dir.z);
            assert!((hit - focus).length() < 1e-4, "{hit} vs {focus}");
            assert!((r.origin.z - 3.0).abs() < 1e-6);
            let off = (r.origin - Vec3::new(1.0, 2.0, 3.0)).length();
            assert!(off <= 0.2 + 1e-6);
            mean_r += off / n as f32;
        }
        assert!((mean_r - 0.2 * 2.0 / 3.0).abs() < 0.002, "{mean_r}");
        assert!(!pinhole.has_lens() && lens.has_lens());
    }
}
