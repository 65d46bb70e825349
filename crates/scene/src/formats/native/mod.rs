//! The native scene format: TOML, documented key by key in `docs/scene-format.md`.
//!
//! Top-level tables: `[render]` (image and sampling settings), `[camera]`, `[world]`
//! (background and ambient light), and arrays `[[material]]`, `[[mesh]]` (shared meshes for
//! instancing), `[[shape]]` and `[[light]]`. Paths are relative to the scene file.

mod material;
mod medium;
mod shape;

use crate::desc::{CameraDesc, CameraKind, EnvironmentDesc, EnvironmentSource, LightDesc, RenderDesc, SceneDesc};
use crate::params::{parse_toml, Result, Table, Value};
use crate::SourceFile;
use glam::Vec3;
use penumbra_core::{Rgb, SamplerKind};
use penumbra_geometry::AccelKind;
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::{DirectOptions, IntegratorKind, LightSampling, MisHeuristic, MAX_DEPTH_LIMIT};
use penumbra_render::lights::LightSelection;
use penumbra_render::Filter;
use std::sync::Arc;

/// Reads a native scene from its source text.
pub fn read(file: &Arc<SourceFile>) -> Result<SceneDesc> {
    let root = parse_toml(file)?;
    let top = Table::new(file, root.get_ref(), root.span());
    let mut desc = SceneDesc::empty();
    desc.media = medium::read_all(&top.tables("medium")?)?;
    if let Some(t) = top.table("render")? {
        desc.render = read_render(&t)?;
        t.finish()?;
    }
    if let Some(t) = top.table("camera")? {
        desc.camera = read_camera(&t)?;
        desc.camera_medium = medium::reference(&t, "medium", &desc.media)?;
        t.finish()?;
    }
    if let Some(t) = top.table("world")? {
        desc.background = t.rgb_or("background", Rgb::BLACK)?;
        desc.ambient = t.rgb_or("ambient", Rgb::BLACK)?;
        t.finish()?;
    }
    if let Some(t) = top.table("environment")? {
        let env = read_environment(&t)?;
        if !desc.background.is_black() {
            return Err(t.error(
                "a scene with an `[environment]` takes its background from it: remove `background` from `[world]`",
            ));
        }
        desc.environment = Some(env);
        t.finish()?;
    }
    let materials = material::read_all(&top.tables("material")?)?;
    let meshes = shape::read_meshes(file, &top.tables("mesh")?, &mut desc.warnings)?;
    for t in top.tables("shape")? {
        desc.shapes.push(shape::read(
            file,
            &t,
            &materials,
            &desc.media,
            &meshes,
            &mut desc.warnings,
        )?);
        t.finish()?;
    }
    desc.materials = materials;
    desc.meshes = meshes.into_iter().map(|(_, m)| m).collect();
    for t in top.tables("light")? {
        desc.lights.push(read_light(&t)?);
        t.finish()?;
    }
    top.finish()?;
    Ok(desc)
}

/// The `name` of table `t`, which none of `taken` (the names of its kind defined before,
/// a `what`) may already be.
pub(crate) fn unique_name<'a>(t: &Table, what: &str, mut taken: impl Iterator<Item = &'a String>) -> Result<String> {
    let value = t.require("name")?;
    let name = value.str()?.to_string();
    if taken.any(|n| *n == name) {
        return Err(value
            .error(format!("{what} `{name}` is defined twice"))
            .label("second definition"));
    }
    Ok(name)
}

/// A value that must be one of `names`, with the list in the error.
pub(crate) fn choice<T>(v: &Value, what: &str, names: &[&str], parse: impl Fn(&str) -> Option<T>) -> Result<T> {
    let s = v.str()?;
    parse(s).ok_or_else(|| {
        v.error(format!("unknown {what} `{s}`"))
            .label(format!("unknown {what}"))
            .help(format!("expected one of: {}", names.join(", ")))
    })
}

/// The value of `key`, one of `names`, or `default` when the key is absent.
fn choice_or<T>(
    t: &Table,
    key: &str,
    what: &str,
    names: &[&str],
    parse: impl Fn(&str) -> Option<T>,
    default: T,
) -> Result<T> {
    t.get(key).map_or(Ok(default), |v| choice(&v, what, names, parse))
}

/// The largest image side, here and on the command line.
pub const MAX_RESOLUTION: i64 = 65536;
/// The largest number of pixels, here and on the command line (2^28, about 16k x 16k).
pub const MAX_PIXELS: u64 = 1 << 28;

fn read_render(t: &Table) -> Result<RenderDesc> {
    let d = RenderDesc::default();
    let int = |key: &str, range: std::ops::RangeInclusive<i64>, default: u64| -> Result<u64> {
        t.get(key).map_or(Ok(default), |v| v.integer(range).map(|n| n as u64))
    };
    let integrator = choice_or(
        t,
        "integrator",
        "integrator",
        &IntegratorKind::NAMES,
        IntegratorKind::from_name,
        d.integrator,
    )?;
    let sampler = choice_or(
        t,
        "sampler",
        "sampler",
        &SamplerKind::NAMES,
        SamplerKind::from_name,
        d.sampler,
    )?;
    let accel = choice_or(
        t,
        "accel",
        "accelerator",
        &AccelKind::NAMES,
        AccelKind::from_name,
        d.accel,
    )?;
    let min_weight = t.f32_or("min_weight", d.min_weight)?;
    if min_weight < 0.0 {
        return Err(t.require("min_weight")?.error("`min_weight` must not be negative"));
    }
    let (width, height) = (
        int("width", 1..=MAX_RESOLUTION, d.width as u64)?,
        int("height", 1..=MAX_RESOLUTION, d.height as u64)?,
    );
    if width * height > MAX_PIXELS {
        let at = t
            .get("height")
            .or_else(|| t.get("width"))
            .map_or_else(|| t.location(), |v| v.location());
        return Err(
            crate::SceneError::at(at, format!("{width}x{height} is more than {MAX_PIXELS} pixels")).label("too large"),
        );
    }
    let direct = read_direct(t, &d.direct)?;
    Ok(RenderDesc {
        width: width as u32,
        height: height as u32,
        spp: int("spp", 1..=u32::MAX as i64, d.spp as u64)? as u32,
        seed: int("seed", 0..=i64::MAX, d.seed)?,
        integrator,
        max_depth: int("max_depth", 0..=MAX_DEPTH_LIMIT as i64, d.max_depth as u64)? as u32,
        rr_depth: int("rr_depth", 1..=MAX_DEPTH_LIMIT as i64, d.rr_depth as u64)? as u32,
        min_weight,
        sampler,
        filter: match t.table("filter")? {
            Some(f) => {
                let filter = read_filter(&f)?;
                f.finish()?;
                filter
            }
            None => d.filter,
        },
        accel,
        direct,
        mlt: d.mlt,
        photon: d.photon,
        env: d.env,
        spectral: match t.get("spectral") {
            Some(v) => v.bool()?,
            None => d.spectral,
        },
    })
}

/// `light_sampling`, `light_samples`, `mis_heuristic` and `light_selection`: the settings
/// of the `direct` integrator.
fn read_direct(t: &Table, d: &DirectOptions) -> Result<DirectOptions> {
    let sampling = choice_or(
        t,
        "light_sampling",
        "light sampling",
        &LightSampling::NAMES,
        LightSampling::from_name,
        d.sampling,
    )?;
    let heuristic = choice_or(
        t,
        "mis_heuristic",
        "MIS heuristic",
        &MisHeuristic::NAMES,
        MisHeuristic::from_name,
        d.heuristic,
    )?;
    let selection = choice_or(
        t,
        "light_selection",
        "light selection",
        &LightSelection::NAMES,
        LightSelection::from_name,
        d.selection,
    )?;
    let light_samples = match t.get("light_samples") {
        Some(v) => v.integer(1..=1 << 16)? as u32,
        None => d.light_samples,
    };
    let direct = DirectOptions {
        sampling,
        light_samples,
        heuristic,
        selection,
    };
    if let Err(e) = direct.check() {
        let at = t
            .get("light_samples")
            .or_else(|| t.get("light_sampling"))
            .map_or_else(|| t.location(), |v| v.location());
        return Err(crate::SceneError::at(at, e));
    }
    Ok(direct)
}

fn read_filter(t: &Table) -> Result<Filter> {
    let names = ["box", "tent", "gaussian"];
    let kind = choice(&t.require("type")?, "filter", &names, |s| {
        names.iter().find(|&&n| n == s).copied()
    })?;
    Ok(match kind {
        "box" => Filter::Box {
            radius: t.positive_or("radius", 0.5)?,
        },
        "tent" => Filter::Tent {
            radius: t.positive_or("radius", 1.0)?,
        },
        _ => Filter::Gaussian {
            radius: t.positive_or("radius", 1.5)?,
            sigma: t.positive_or("sigma", 0.5)?,
        },
    })
}

fn nonzero(t: &Table, key: &str, default: Vec3) -> Result<Vec3> {
    let v = t.vec3_or(key, default)?;
    if v.length_squared() == 0.0 {
        let at = t.get(key).map_or_else(|| t.location(), |v| v.location());
        return Err(
            crate::SceneError::at(at, format!("`{key}` must not be a zero-length vector")).label("zero length"),
        );
    }
    Ok(v)
}

fn read_camera(t: &Table) -> Result<CameraDesc> {
    let names = ["perspective", "orthographic"];
    let kind = match t.get("type") {
        Some(v) => choice(&v, "camera type", &names, |s| names.iter().find(|&&n| n == s).copied())?,
        None => "perspective",
    };
    let position = t.vec3_or("position", Vec3::new(0.0, 0.0, 5.0))?;
    let target = t.vec3_or("target", Vec3::ZERO)?;
    let up = nonzero(t, "up", Vec3::Y)?;
    let kind = match kind {
        "orthographic" => CameraKind::Orthographic {
            height: t.positive_or("height", 2.0)?,
        },
        _ => {
            let fov = t.f32_or("fov", 45.0)?;
            if !(fov > 0.0 && fov < 180.0) {
                let v = t.require("fov")?;
                return Err(v
                    .error(format!("`fov` must be between 0 and 180 degrees, found {fov}"))
                    .label("out of range"));
            }
            let fov_axis = match t.get("fov_axis") {
                Some(v) => choice(&v, "fov_axis", &["x", "y", "smaller", "larger"], |s| match s {
                    "x" => Some(FovAxis::X),
                    "y" => Some(FovAxis::Y),
                    "smaller" => Some(FovAxis::Smaller),
                    "larger" => Some(FovAxis::Larger),
                    _ => None,
                })?,
                None => FovAxis::Y,
            };
            let aperture_radius = t.get("aperture_radius").map_or(Ok(0.0), |v| {
                let r = v.f32()?;
                if r < 0.0 {
                    return Err(v.error("`aperture_radius` must not be negative").label("negative"));
                }
                Ok(r)
            })?;
            let focus_distance = match t.get("focus_distance") {
                Some(v) => Some(v.positive()?),
                None => None,
            };
            CameraKind::Perspective {
                fov,
                fov_axis,
                aperture_radius,
                focus_distance,
            }
        }
    };
    let forward = target - position;
    if forward.length_squared() == 0.0
        || forward.cross(up).length_squared() <= 1e-12 * forward.length_squared() * up.length_squared()
    {
        return Err(t
            .error("the camera's view direction (target - position) is zero or parallel to `up`")
            .label("in this camera"));
    }
    Ok(CameraDesc {
        kind,
        position,
        target,
        up,
        mirrored: false,
        location: Some(t.location()),
    })
}

/// `[environment]`: `radiance` (a constant colour) or `file` (an equirectangular .exr, .hdr
/// or .pfm map) with `scale`, a `transform` that may only rotate, and `spin` (degrees per
/// animation frame about +y).
fn read_environment(t: &Table) -> Result<EnvironmentDesc> {
    let (source, scale) = match (t.get("file"), t.get("radiance")) {
        (Some(f), None) => {
            let scale = match t.get("scale") {
                Some(v) if v.is_number() => Rgb::splat(v.f32()?),
                Some(v) => v.rgb()?,
                None => Rgb::WHITE,
            };
            let location = t.location();
            let base = location.file.path.parent().unwrap_or(std::path::Path::new("."));
            (EnvironmentSource::Image(base.join(f.str()?)), scale)
        }
        (None, Some(r)) => (EnvironmentSource::Constant, r.rgb()?),
        (Some(f), Some(_)) => return Err(f.error("give either `file` or `radiance`, not both")),
        (None, None) => return Err(t.error("`[environment]` needs `file` (an image) or `radiance` (a colour)")),
    };
    if scale.r < 0.0 || scale.g < 0.0 || scale.b < 0.0 {
        let key = if t.get("scale").is_some() { "scale" } else { "radiance" };
        return Err(t.require(key)?.error("must not be negative"));
    }
    let transform = match t.get("transform") {
        Some(v) => {
            let tr = shape::transform(&v)?;
            let m = glam::Mat3::from_mat4(tr.m);
            let orthonormal = (m.transpose() * m).abs_diff_eq(glam::Mat3::IDENTITY, 1e-4) && m.determinant() > 0.0;
            if !orthonormal {
                return Err(v.error("an environment can only be rotated").label("not a rotation"));
            }
            tr
        }
        None => penumbra_core::Transform::IDENTITY,
    };
    let spin = t.f32_or("spin", 0.0)?;
    if !spin.is_finite() {
        return Err(t.require("spin")?.error("must be a finite number of degrees per frame"));
    }
    Ok(EnvironmentDesc {
        source,
        scale,
        transform,
        spin,
        location: Some(t.location()),
    })
}

fn read_light(t: &Table) -> Result<LightDesc> {
    let names = ["point", "spot", "directional"];
    let kind = choice(&t.require("type")?, "light type", &names, |s| {
        names.iter().find(|&&n| n == s).copied()
    })?;
    Ok(match kind {
        "point" => LightDesc::Point {
            position: t.require("position")?.vec3()?,
            intensity: t.rgb_or("intensity", Rgb::WHITE)?,
        },
        "spot" => {
            let position = t.require("position")?.vec3()?;
            let target = match t.get("target") {
                None => position - Vec3::Y,
                Some(v) if v.vec3()? == position => {
                    return Err(v.error("a spot light's `target` must differ from its `position`"));
                }
                Some(v) => v.vec3()?,
            };
            let cone_angle = t.positive_or("cone_angle", 30.0)?;
            if cone_angle > 180.0 {
                return Err(t
                    .require("cone_angle")?
                    .error("`cone_angle` must be at most 180 degrees"));
            }
            LightDesc::Spot {
                position,
                target,
                intensity: t.rgb_or("intensity", Rgb::WHITE)?,
                cone_angle,
                falloff_start: match t.get("falloff_start") {
                    None => cone_angle.min(25.0),
                    Some(v) => match v.f32()? {
                        f if (0.0..=cone_angle).contains(&f) => f,
                        f => {
                            return Err(v
                                .error(format!(
                                    "`falloff_start` must be from 0 to `cone_angle` ({cone_angle}), found {f}"
                                ))
                                .label("out of range"))
                        }
                    },
                },
            }
        }
        _ => LightDesc::Directional {
            direction: nonzero(t, "direction", Vec3::NEG_Y)?,
            irradiance: t.rgb_or("irradiance", Rgb::WHITE)?,
        },
    })
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_media;
