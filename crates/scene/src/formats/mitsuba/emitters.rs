//! Mitsuba's emitters outside shapes: point, spot, directional, the constant and
//! image environments, and area emitters with an id that shapes refer to.

use super::{warn_unused, At, Reader, Result};
use crate::desc::{Emission, EnvironmentDesc, EnvironmentSource, LightDesc};
use glam::Vec3;
use penumbra_core::{Rgb, Transform};

/// A top-level `<emitter>`.
pub fn emitter(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = r.require(at, "type")?;
    let to_world = p.transform(r, "to_world")?;
    match kind.as_str() {
        "point" => {
            let position = p.vec3(r, "position")?.unwrap_or_else(|| to_world.point(Vec3::ZERO));
            let intensity = p.color_or(r, "intensity", 1.0)?;
            r.desc.lights.push(LightDesc::Point { position, intensity });
        }
        "spot" => {
            let cutoff = p.float_or(r, "cutoff_angle", 20.0)?;
            let beam = p.float_or(r, "beam_width", cutoff * 0.75)?.min(cutoff);
            let position = to_world.point(Vec3::ZERO);
            let intensity = p.color_or(r, "intensity", 1.0)?;
            r.desc.lights.push(LightDesc::Spot {
                position,
                target: position + to_world.vector(Vec3::Z),
                intensity,
                cone_angle: cutoff,
                falloff_start: beam,
            });
        }
        "directional" => {
            let direction = p.vec3(r, "direction")?.unwrap_or_else(|| to_world.vector(Vec3::Z));
            if direction.length_squared() == 0.0 {
                return Err(at.error("a directional emitter needs a non-zero direction"));
            }
            let irradiance = p.color_or(r, "irradiance", 1.0)?;
            r.desc.lights.push(LightDesc::Directional { direction, irradiance });
        }
        "constant" | "envmap" => {
            if r.desc.environment.is_some() {
                return Err(at.error("a second environment emitter: the scene may have one"));
            }
            let (source, scale) = if kind == "constant" {
                (EnvironmentSource::Constant, p.color_or(r, "radiance", 1.0)?)
            } else {
                let (name, v) = p
                    .string(r, "filename")?
                    .ok_or_else(|| at.error("an envmap needs a `filename`"))?;
                let path = r.resolve(v, &name);
                if !path.is_file() {
                    return Err(r.attr_error(
                        v,
                        "value",
                        format!("cannot read the environment map {}", path.display()),
                    ));
                }
                (EnvironmentSource::Image(path), Rgb::splat(p.float_or(r, "scale", 1.0)?))
            };
            r.desc.environment = Some(EnvironmentDesc {
                source,
                scale,
                transform: Transform::from_matrix(glam::Mat4::from_mat3(glam::Mat3::from_mat4(to_world.m)))
                    .unwrap_or(Transform::IDENTITY),
                spin: 0.0,
                location: Some(at.location()),
            });
        }
        "area" => {
            let Some(id) = r.attr(at, "id")? else {
                return Err(at.error(
                    "an `area` emitter belongs inside the <shape> it makes emit, or has an id shapes refer to",
                ));
            };
            let radiance = p.color_or(r, "radiance", 1.0)?;
            let spectrum = p.spectrum(r, "radiance")?.map(|s| (s, 1.0));
            r.area_emitters.insert(
                id,
                Emission {
                    radiance,
                    two_sided: false,
                    texture: None,
                    spectrum,
                },
            );
        }
        other => {
            r.warn_once(
                &format!("emitter {other}"),
                format!("{}: emitter `{other}` is not supported: skipped", at.place()),
            );
            return Ok(());
        }
    }
    warn_unused(r, &p, &format!("emitter {kind}"));
    Ok(())
}
