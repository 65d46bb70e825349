//! A glTF node's camera (looking down its -z, +y up, +x to the image's right) and its
//! KHR_lights_punctual light (shining down its -z).

use super::{Fail, Reader, Result};
use crate::desc::{CameraChoice, CameraDesc, CameraKind, LightDesc};
use glam::Vec3;
use penumbra_core::Transform;
use penumbra_render::cameras::FovAxis;

impl Reader {
    /// The camera of a camera node placed by `t`: glTF's look down -z with +y up and +x to
    /// the right of the image.
    pub(super) fn camera(&mut self, camera: &gltf::Camera, t: &Transform) -> Result<CameraChoice> {
        let path = format!("cameras[{}]", camera.index());
        let bad = |what: &str| {
            Fail::new(
                format!("{path}.{what}"),
                format!("the camera's {what} must be a positive number"),
            )
        };
        let (kind, aspect) = match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let yfov = p.yfov();
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(self.fail(Fail::new(
                        format!("{path}.perspective.yfov"),
                        "the vertical field of view must be between 0 and pi radians",
                    )));
                }
                let kind = CameraKind::Perspective {
                    fov: yfov.to_degrees(),
                    fov_axis: FovAxis::Y,
                    aperture_radius: 0.0,
                    focus_distance: None,
                };
                (kind, p.aspect_ratio())
            }
            gltf::camera::Projection::Orthographic(o) => {
                let (x, y) = (o.xmag().abs(), o.ymag().abs());
                if !(y > 0.0 && y.is_finite()) {
                    return Err(self.fail(bad("orthographic.ymag")));
                }
                (CameraKind::Orthographic { height: 2.0 * y }, (x > 0.0).then(|| x / y))
            }
        };
        if let Some(a) = aspect.filter(|a| !(a.is_finite() && *a > 0.0)) {
            return Err(self.fail(Fail::new(
                format!("{path}.perspective.aspectRatio"),
                format!("the aspect ratio {a} must be a positive number"),
            )));
        }
        let height = self.desc.render.height;
        let width = match aspect {
            Some(a) => ((height as f32 * a).round() as u32).clamp(1, 16384),
            None => self.desc.render.width,
        };
        // Camera space to world: glTF's -z forward becomes the +z of `from_frame`.
        let flip = Transform::scale(Vec3::new(-1.0, 1.0, -1.0)).expect("a reflection is invertible");
        let location = Some(self.location(&path));
        Ok(CameraChoice {
            camera: CameraDesc::from_frame(kind, &flip.then(*t), -1.0, location),
            width,
            height,
        })
    }

    /// A KHR_lights_punctual light on a node placed by `t` (lights shine down the node's -z).
    pub(super) fn light(&mut self, light: &gltf::khr_lights_punctual::Light, t: &Transform, path: &str) {
        use gltf::khr_lights_punctual::Kind;
        let [r, g, b] = light.color();
        let power = penumbra_core::Rgb::new(r, g, b) * light.intensity();
        if light.range().is_some() {
            self.warn(
                "range",
                path,
                "a light's range is ignored: light falls off with the inverse square of distance",
            );
        }
        let position = t.point(Vec3::ZERO);
        let direction = t.vector(-Vec3::Z).normalize_or_zero();
        if direction == Vec3::ZERO {
            self.warn(
                "light direction",
                path,
                "a light whose node squashes its direction is not used",
            );
            return;
        }
        self.desc.lights.push(match light.kind() {
            Kind::Directional => LightDesc::Directional {
                direction,
                irradiance: power,
            },
            Kind::Point => LightDesc::Point {
                position,
                intensity: power,
            },
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => LightDesc::Spot {
                position,
                target: position + direction,
                intensity: power,
                cone_angle: outer_cone_angle.to_degrees(),
                falloff_start: inner_cone_angle.min(outer_cone_angle).to_degrees(),
            },
        });
    }
}
