//! Mitsuba's plugins mapped onto Penumbra's: integrator, sensor (with its film, filter and
//! sampler), BSDFs, textures and emitters. Shapes are in [`super::shapes`].

use super::props::Props;
use super::{warn_unused, At, Reader, Result};
use crate::desc::{CameraDesc, CameraKind, Emission, EnvironmentDesc, EnvironmentSource, LightDesc, RenderDesc};
use crate::image_input::read_input_image;
use glam::Vec3;
use penumbra_core::{Rgb, SamplerKind, Transform};
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::{IntegratorKind, LightSampling, MAX_DEPTH_LIMIT};
use penumbra_render::lights::LightSelection;
use penumbra_render::materials::{metal_ior, Roughness};
use penumbra_render::texture::TextureImage;
use penumbra_render::{Filter, Material, Texture};
use std::sync::Arc;

pub(super) use super::shapes::shape;

/// Mitsuba's defaults: `hdrfilm` 768 x 576 with a Gaussian filter (standard deviation
/// 0.5, radius 2), `independent` sampler with 4 samples, `path` with no depth limit.
pub fn default_render() -> RenderDesc {
    RenderDesc {
        width: 768,
        height: 576,
        spp: 4,
        integrator: IntegratorKind::Path,
        max_depth: MAX_DEPTH_LIMIT,
        sampler: SamplerKind::Independent,
        filter: Filter::Gaussian {
            radius: 2.0,
            sigma: 0.5,
        },
        ..RenderDesc::default()
    }
}

/// A scene without a sensor is seen from the origin along +z, Mitsuba's default.
pub fn default_camera() -> CameraDesc {
    CameraDesc {
        kind: CameraKind::Perspective {
            fov: 39.597755,
            fov_axis: FovAxis::X,
            aperture_radius: 0.0,
            focus_distance: None,
        },
        position: Vec3::ZERO,
        target: Vec3::Z,
        up: Vec3::Y,
        location: None,
    }
}

/// The type attribute of a plugin element.
fn kind(r: &Reader, at: At) -> Result<String> {
    r.require(at, "type")
}

/// A depth that Mitsuba writes as -1 for "no limit".
fn depth(r: &Reader, p: &Props, name: &str, default: u32) -> Result<u32> {
    match p.int(r, name)? {
        None => Ok(default),
        Some(-1) => Ok(MAX_DEPTH_LIMIT),
        Some(d) if (0..=MAX_DEPTH_LIMIT as i64).contains(&d) => Ok(d as u32),
        Some(d) => Err(p
            .get(name)
            .map(|v| {
                r.attr_error(
                    v,
                    "value",
                    format!("`{name}` must be -1 or from 0 to {MAX_DEPTH_LIMIT}, found {d}"),
                )
            })
            .expect("the parameter was just read")),
    }
}

pub fn integrator(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    let integrator = match kind.as_str() {
        "path" => IntegratorKind::Path,
        "direct" => IntegratorKind::Direct,
        other => {
            let text = format!(
                "{}: integrator `{other}` is not supported: rendered with `path`",
                at.place()
            );
            r.warn_once(&format!("integrator {other}"), text);
            IntegratorKind::Path
        }
    };
    r.desc.render.integrator = integrator;
    let max_depth = depth(r, &p, "max_depth", MAX_DEPTH_LIMIT)?;
    let rr_depth = depth(r, &p, "rr_depth", penumbra_render::integrators::RR_DEPTH)?.max(1);
    if integrator == IntegratorKind::Direct {
        // Mitsuba's `direct`: `emitter_samples` shadow rays to emitters picked uniformly
        // and `bsdf_samples` BSDF samples, combined by the power heuristic when both are
        // taken.
        let count = |name: &str| -> Result<u32> {
            match p.int(r, name)? {
                None => Ok(1),
                Some(n) if (0..=1024).contains(&n) => Ok(n as u32),
                Some(n) => Err(r.attr_error(
                    p.get(name).expect("just read"),
                    "value",
                    format!("`{name}` must be from 0 to 1024, found {n}"),
                )),
            }
        };
        let (emitter, bsdf) = (count("emitter_samples")?, count("bsdf_samples")?);
        let d = &mut r.desc.render.direct;
        d.selection = LightSelection::Uniform;
        d.light_samples = emitter.max(1);
        d.sampling = match (emitter, bsdf) {
            (0, 0) => return Err(at.error("`emitter_samples` and `bsdf_samples` are both 0: nothing is sampled")),
            (0, _) => LightSampling::Bsdf,
            (_, 0) => LightSampling::SolidAngle,
            _ => LightSampling::Mis,
        };
        if bsdf > 1 && emitter > 0 {
            r.warn_once(
                "bsdf_samples",
                format!("{}: `bsdf_samples` above 1 is read as 1", at.place()),
            );
        }
    }
    let render = &mut r.desc.render;
    render.max_depth = max_depth;
    render.rr_depth = rr_depth;
    warn_unused(r, &p, &format!("integrator {kind}"));
    Ok(())
}

pub fn sensor(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    let thin_lens = match kind.as_str() {
        "perspective" => false,
        "thinlens" => true,
        other => {
            return Err(r.attr_error(
                at,
                "type",
                format!("sensor `{other}` is not supported (perspective or thinlens)"),
            ))
        }
    };
    let to_world = p.transform(r, "to_world")?;
    let fov_axis = match p.string(r, "fov_axis")? {
        None => FovAxis::X,
        Some((s, v)) => match s.as_str() {
            "x" => FovAxis::X,
            "y" => FovAxis::Y,
            "smaller" => FovAxis::Smaller,
            "larger" => FovAxis::Larger,
            "diagonal" => {
                r.warn_once("fov_axis", format!("{}: fov_axis `diagonal` is read as `x`", v.place()));
                FovAxis::X
            }
            other => {
                return Err(r.attr_error(
                    v,
                    "value",
                    format!("unknown fov_axis `{other}` (x, y, smaller, larger)"),
                ))
            }
        },
    };
    let fov = match (p.float(r, "fov")?, p.string(r, "focal_length")?) {
        (Some(f), _) => f,
        (None, Some((s, v))) => {
            let mm: f32 = s
                .trim_end_matches("mm")
                .trim()
                .parse()
                .map_err(|_| r.attr_error(v, "value", "expected e.g. 50mm"))?;
            // The 36 mm width of a full-frame film, along x.
            2.0 * (18.0 / mm).atan().to_degrees()
        }
        (None, None) => 39.597755,
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(p.get("fov").map_or(at.error("fov must be in (0, 180)"), |v| {
            r.attr_error(v, "value", "fov must be in (0, 180) degrees")
        }));
    }
    let (aperture_radius, focus_distance) = if thin_lens {
        (p.float_or(r, "aperture_radius", 0.0)?, p.float(r, "focus_distance")?)
    } else {
        p.float(r, "focus_distance")?; // A pinhole has nothing to focus.
        (0.0, None)
    };
    p.float(r, "near_clip")?;
    p.float(r, "far_clip")?;
    // Mitsuba's camera looks along +z with +y up, x to the left.
    let position = to_world.point(Vec3::ZERO);
    let dir = to_world.vector(Vec3::Z);
    let up = to_world.vector(Vec3::Y);
    if to_world.vector(Vec3::X).dot(up.cross(dir)) < 0.0 {
        r.warn_once(
            "mirrored sensor",
            format!("{}: a mirrored sensor transform is rendered unmirrored", at.place()),
        );
    }
    r.desc.camera = CameraDesc {
        kind: CameraKind::Perspective {
            fov,
            fov_axis,
            aperture_radius,
            focus_distance,
        },
        position,
        target: position + dir,
        up,
        location: Some(at.location()),
    };
    for film in p.nested("film") {
        self::film(r, film)?;
    }
    for sampler in p.nested("sampler") {
        self::sampler(r, sampler)?;
    }
    warn_unused(r, &p, &format!("sensor {kind}"));
    Ok(())
}

fn film(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    if kind != "hdrfilm" {
        r.warn_once("film", format!("{}: film `{kind}` is read as `hdrfilm`", at.place()));
    }
    let size = |name: &str, default: u32| -> Result<u32> {
        match p.int(r, name)? {
            None => Ok(default),
            Some(n) if (1..=1 << 16).contains(&n) => Ok(n as u32),
            Some(n) => Err(r.attr_error(
                p.get(name).expect("just read"),
                "value",
                format!("`{name}` must be from 1 to 65536, found {n}"),
            )),
        }
    };
    let (width, height) = (size("width", 768)?, size("height", 576)?);
    (r.desc.render.width, r.desc.render.height) = (width, height);
    for s in ["pixel_format", "component_format", "file_format"] {
        p.string(r, s)?; // Output formats follow the output file's extension.
    }
    for f in p.nested("rfilter") {
        let fp = r.props(f);
        let filter = match kind_of(r, f)?.as_str() {
            "gaussian" => {
                let sigma = fp.float_or(r, "stddev", 0.5)?;
                Filter::Gaussian {
                    radius: 4.0 * sigma,
                    sigma,
                }
            }
            "box" => Filter::Box { radius: 0.5 },
            "tent" => Filter::Tent {
                radius: fp.float_or(r, "radius", 1.0)?,
            },
            other => {
                r.warn_once(
                    "rfilter",
                    format!("{}: rfilter `{other}` is read as `gaussian`", f.place()),
                );
                Filter::Gaussian {
                    radius: 2.0,
                    sigma: 0.5,
                }
            }
        };
        r.desc.render.filter = filter;
        warn_unused(r, &fp, "rfilter");
    }
    warn_unused(r, &p, &format!("film {kind}"));
    Ok(())
}

fn kind_of(r: &Reader, at: At) -> Result<String> {
    kind(r, at)
}

fn sampler(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    r.desc.render.sampler = match kind.as_str() {
        "independent" => SamplerKind::Independent,
        "stratified" | "multijitter" => SamplerKind::Stratified,
        "ldsampler" | "orthogonal" => SamplerKind::Sobol,
        other => {
            r.warn_once(
                "sampler",
                format!("{}: sampler `{other}` is read as `independent`", at.place()),
            );
            SamplerKind::Independent
        }
    };
    if let Some(n) = p.int(r, "sample_count")? {
        if !(1..=1 << 24).contains(&n) {
            let v = p.get("sample_count").expect("just read");
            return Err(r.attr_error(
                v,
                "value",
                format!("sample_count must be from 1 to 16777216, found {n}"),
            ));
        }
        r.desc.render.spp = n as u32;
    }
    p.int(r, "seed")?;
    p.bool_or(r, "jitter", true)?;
    warn_unused(r, &p, &format!("sampler {kind}"));
    Ok(())
}

/// Named interior indices of refraction (Mitsuba's table, the common ones).
fn ior(r: &Reader, p: &Props, name: &str, default: f32) -> Result<f32> {
    let Some(v) = p.get(name) else { return Ok(default) };
    if v.tag() == "float" {
        return super::props::number(r, v, "value");
    }
    let s = r.require(v, "value")?;
    let known = [
        ("vacuum", 1.0),
        ("air", 1.000277),
        ("water", 1.3330),
        ("water ice", 1.31),
        ("fused quartz", 1.458),
        ("pyrex", 1.470),
        ("acrylic glass", 1.49),
        ("polypropylene", 1.49),
        ("bk7", 1.5046),
        ("sodium chloride", 1.544),
        ("amber", 1.55),
        ("pet", 1.5750),
        ("diamond", 2.419),
    ];
    known
        .iter()
        .find(|(n, _)| *n == s)
        .map(|k| k.1)
        .ok_or_else(|| r.attr_error(v, "value", format!("unknown index of refraction `{s}`")))
}

/// GGX roughness from `alpha` or `alpha_u`/`alpha_v` (default 0.1).
fn roughness(r: &mut Reader, p: &Props, what: &str) -> Result<Roughness> {
    if let Some((d, v)) = p.string(r, "distribution")? {
        if d != "ggx" {
            r.warn_once(
                "distribution",
                format!("{}: {what}: the `{d}` distribution is rendered as GGX", v.place()),
            );
        }
    }
    p.bool_or(r, "sample_visible", true)?;
    Ok(match (p.get("alpha_u").is_some(), p.get("alpha_v").is_some()) {
        (true, true) => Roughness {
            alpha_u: p.texture(r, "alpha_u", 0.1, true)?,
            alpha_v: p.texture(r, "alpha_v", 0.1, true)?,
        },
        _ => {
            let a = p.texture(r, "alpha", 0.1, true)?;
            Roughness {
                alpha_u: a.clone(),
                alpha_v: a,
            }
        }
    })
}

/// The material a `<bsdf>` describes (nested or at the top level).
pub fn bsdf(r: &mut Reader, at: At) -> Result<Material> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    let what = format!("bsdf {kind}");
    let material = match kind.as_str() {
        "diffuse" => Material::Diffuse {
            reflectance: p.texture(r, "reflectance", 0.5, false)?,
        },
        "twosided" => {
            let inner = nested_bsdfs(r, &p, 1)?.remove(0);
            Material::TwoSided(Box::new(inner))
        }
        "conductor" | "roughconductor" => {
            let (eta, k) = match (p.color(r, "eta")?, p.color(r, "k")?) {
                (Some(eta), Some(k)) => (eta, k),
                _ => match p.string(r, "material")? {
                    None => (Rgb::BLACK, Rgb::WHITE),
                    Some((name, _)) if name == "none" => (Rgb::BLACK, Rgb::WHITE),
                    Some((name, v)) => match metal_ior(&name) {
                        Some(m) => m,
                        None => {
                            r.warn_once(
                                &format!("metal {name}"),
                                format!("{}: metal `{name}` is not in our table (Au, Ag, Cu, Al): rendered as a perfect mirror", v.place()),
                            );
                            (Rgb::BLACK, Rgb::WHITE)
                        }
                    },
                },
            };
            Material::Conductor {
                eta,
                k,
                specular: p.texture(r, "specular_reflectance", 1.0, false)?,
                roughness: (kind == "roughconductor")
                    .then(|| roughness(r, &p, &what))
                    .transpose()?,
            }
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            if kind == "thindielectric" {
                r.warn_once(
                    "thindielectric",
                    format!("{}: `thindielectric` is rendered as a smooth `dielectric`", at.place()),
                );
            }
            Material::Dielectric {
                eta: ior(r, &p, "int_ior", 1.5046)? / ior(r, &p, "ext_ior", 1.000277)?,
                reflectance: p.texture(r, "specular_reflectance", 1.0, false)?,
                transmittance: p.texture(r, "specular_transmittance", 1.0, false)?,
                roughness: (kind == "roughdielectric")
                    .then(|| roughness(r, &p, &what))
                    .transpose()?,
            }
        }
        "plastic" | "roughplastic" => {
            p.bool_or(r, "nonlinear", false)?;
            let eta = ior(r, &p, "int_ior", 1.49)? / ior(r, &p, "ext_ior", 1.000277)?;
            Material::plastic(
                p.texture(r, "diffuse_reflectance", 0.5, false)?,
                p.texture(r, "specular_reflectance", 1.0, false)?,
                eta,
                (kind == "roughplastic").then(|| roughness(r, &p, &what)).transpose()?,
            )
        }
        "blendbsdf" => {
            let weight = p.texture(r, "weight", 0.5, true)?;
            let mut parts = nested_bsdfs(r, &p, 2)?;
            let b = parts.pop().expect("two parts");
            let a = parts.pop().expect("two parts");
            Material::Blend {
                a: Box::new(a),
                b: Box::new(b),
                weight,
            }
        }
        "normalmap" => {
            let map = p.texture(r, "normalmap", 0.5, true)?;
            let inner = nested_bsdfs(r, &p, 1)?.remove(0);
            Material::NormalMapped {
                map,
                inner: Box::new(inner),
            }
        }
        other => {
            r.warn_once(
                &format!("bsdf {other}"),
                format!(
                    "{}: bsdf `{other}` is not supported: rendered as a grey `diffuse`",
                    at.place()
                ),
            );
            return Ok(Material::Diffuse {
                reflectance: Texture::Constant(Rgb::splat(0.5)),
            });
        }
    };
    warn_unused(r, &p, &what);
    Ok(material)
}

/// The `count` BSDFs nested in (or referred to by) a wrapper.
fn nested_bsdfs(r: &mut Reader, p: &Props, count: usize) -> Result<Vec<Material>> {
    let mut out = Vec::new();
    let children: Vec<At> =
        p.at.node
            .children()
            .filter(|c| c.is_element() && matches!(c.tag_name().name(), "bsdf" | "ref"))
            .map(|c| p.at.with(c))
            .collect();
    for c in children {
        if c.tag() == "bsdf" {
            out.push(bsdf(r, c)?);
        } else {
            out.push(material_ref(r, c)?);
        }
    }
    if out.len() != count {
        return Err(p
            .at
            .error(format!("this bsdf wraps {count} bsdf(s), found {}", out.len())));
    }
    Ok(out)
}

/// The material a `<ref id>` names.
pub fn material_ref(r: &Reader, at: At) -> Result<Material> {
    let id = r.require(at, "id")?;
    let index = *r.bsdfs.get(&id).ok_or_else(|| {
        r.attr_error(
            at,
            "id",
            format!("no bsdf has the id `{id}` (bsdfs are defined before use)"),
        )
    })?;
    Ok(r.desc.materials[index].material.clone())
}

/// A `<texture>`: `bitmap` or `checkerboard`.
pub fn texture(r: &mut Reader, at: At, data: bool) -> Result<Texture> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    let tex = match kind.as_str() {
        "bitmap" => {
            let (name, v) = p
                .string(r, "filename")?
                .ok_or_else(|| at.error("a bitmap needs a `filename`"))?;
            let raw = p.bool_or(r, "raw", data)?;
            let path = r.resolve(v, &name);
            let image = read_input_image(&path, !raw)
                .map_err(|e| r.attr_error(v, "value", format!("cannot read the texture {}: {e}", path.display())))?;
            if image.width == 0 || image.height == 0 || image.pixels.iter().any(|p| !p.is_finite()) {
                return Err(r.attr_error(
                    v,
                    "value",
                    format!("the texture {} is empty or not finite", path.display()),
                ));
            }
            p.string(r, "filter_type")?;
            p.string(r, "wrap_mode")?;
            Texture::Image {
                image: Arc::new(TextureImage {
                    width: image.width as usize,
                    height: image.height as usize,
                    pixels: image.pixels,
                }),
                scale: uv_scale(r, &p)?,
            }
        }
        "checkerboard" => Texture::Checker {
            even: p.color_or(r, "color0", 0.4)?,
            odd: p.color_or(r, "color1", 0.2)?,
            size: 0.5 / uv_scale(r, &p)?,
        },
        other => {
            r.warn_once(
                &format!("texture {other}"),
                format!("{}: texture `{other}` is not supported: read as 0.5", at.place()),
            );
            return Ok(Texture::Constant(Rgb::splat(0.5)));
        }
    };
    warn_unused(r, &p, &format!("texture {kind}"));
    Ok(tex)
}

/// The uniform scale of a texture's `to_uv` (its first diagonal entry).
fn uv_scale(r: &Reader, p: &Props) -> Result<f32> {
    let t = p.transform(r, "to_uv")?;
    Ok(t.m.x_axis.x.abs().max(1e-6))
}

/// A top-level `<emitter>`.
pub fn emitter(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
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
            r.area_emitters.insert(
                id,
                Emission {
                    radiance,
                    two_sided: false,
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
