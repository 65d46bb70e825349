//! pbrt-v4's objects mapped onto Penumbra's: the camera and render settings, textures and
//! lights (materials: `materials.rs`; shapes: `shapes.rs`). What we lack is one warning
//! per kind.

use super::params::{ColorKind, Params};
use super::{Reader, Result};
use crate::desc::{CameraDesc, CameraKind, Emission, EnvironmentDesc, EnvironmentSource, LightDesc};
use crate::{Location, SceneError, SourceFile};
use glam::Vec3;
use penumbra_core::{Rgb, SamplerKind, Transform};
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::MAX_DEPTH_LIMIT;
use penumbra_render::materials::metal_ior;
use penumbra_render::texture::Wrap;
use penumbra_render::{Filter, Texture};

/// Parameters nobody read: one warning per directive type and name.
pub(super) fn unused(r: &mut Reader, p: &Params, what: &str, here: &Location) {
    for name in p.unused() {
        r.warn(
            &format!("{what}.{name}"),
            format!("{here}: {what}: parameter `{name}` is not supported: ignored"),
        );
    }
}

/// Named spectra: pbrt's metals (`metal-Au-eta`, `metal-Au-k`, ... for the metals of our
/// table) and glasses (by their index at 550 nm).
fn named_spectrum(name: &str) -> Option<Rgb> {
    if let Some(rest) = name.strip_prefix("metal-") {
        let (metal, part) = rest.rsplit_once('-')?;
        let (eta, k) = metal_ior(metal)?;
        return match part {
            "eta" => Some(eta),
            "k" => Some(k),
            _ => None,
        };
    }
    let glass = [
        ("glass-BK7", 1.5168),
        ("glass-BAF10", 1.67),
        ("glass-F11", 1.62),
        ("glass-F5", 1.6034),
        ("fused-silica", 1.4585),
    ];
    glass.iter().find(|g| g.0 == name).map(|g| Rgb::splat(g.1))
}

pub(super) fn color(p: &Params, name: &str, kind: ColorKind) -> Result<Option<Rgb>> {
    p.color(name, kind, &|s| named_spectrum(s).or_else(|| spectrum_file(&p.file, s)))
}

/// A spectrum from a file (`.spd`: wavelength and value pairs, `#` comments), relative to
/// the folder of the file that names it.
fn spectrum_file(file: &SourceFile, name: &str) -> Option<Rgb> {
    let path = file.path.parent().unwrap_or(std::path::Path::new(".")).join(name);
    let text = std::fs::read_to_string(path).ok()?;
    let numbers: Vec<f64> = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(str::split_whitespace)
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .ok()?;
    if numbers.len() < 4 || !numbers.len().is_multiple_of(2) {
        return None;
    }
    let samples: Vec<(f64, f64)> = numbers.chunks(2).map(|c| (c[0], c[1])).collect();
    samples
        .windows(2)
        .all(|w| w[0].0 < w[1].0)
        .then(|| crate::formats::mitsuba::spectrum::spectrum_to_rgb(&samples))
}

/// A colour or a named texture; `default` when absent.
pub(super) fn texture_param(r: &Reader, p: &Params, name: &str, default: f32) -> Result<Texture> {
    if let Some(t) = p.texture_name(name) {
        return r.textures.get(&t).cloned().ok_or_else(|| {
            let param = p.list.iter().rev().find(|x| x.name == name).expect("just found");
            p.error(param, format!("no texture is named `{t}`"))
        });
    }
    Ok(Texture::Constant(
        color(p, name, ColorKind::Albedo)?.unwrap_or(Rgb::splat(default)),
    ))
}

pub fn camera(r: &mut Reader, kind: &str, p: &Params, here: Location) -> Result<()> {
    if kind != "perspective" {
        r.warn("camera", format!("{here}: camera `{kind}` is read as `perspective`"));
    }
    let world_from_camera = r.state.ctm.inverse();
    r.named_coords.insert("camera".into(), world_from_camera);
    let fov = p.float("fov", 90.0)?;
    let lens = p.float("lensradius", 0.0)?;
    let focus = p.float("focaldistance", 1e6)?;
    let (open, close) = (p.float("shutteropen", 0.0)?, p.float("shutterclose", 1.0)?);
    if close < open || !(close - open).is_finite() {
        return Err(SceneError::at(
            here,
            format!("`shutterclose` ({close}) is before `shutteropen` ({open})"),
        ));
    }
    r.exposure_time = close - open;
    let projection = CameraKind::Perspective {
        fov,
        fov_axis: FovAxis::Smaller,
        aperture_radius: lens,
        focus_distance: (lens > 0.0).then_some(focus),
    };
    // pbrt's image x runs along camera +x.
    r.desc.camera = CameraDesc::from_frame(projection, &world_from_camera, 1.0, Some(here.clone()));
    unused(r, p, &format!("camera {kind}"), &here);
    Ok(())
}

/// `Film`, `Sampler`, `PixelFilter`, `Integrator`.
pub fn setting(r: &mut Reader, directive: &str, kind: &str, p: &Params, here: Location) -> Result<()> {
    let what = format!("{directive} {kind}");
    match directive {
        "Film" => {
            let size = |name: &str, default: i64| -> Result<u32> {
                match p.int(name, default)? {
                    n @ 1..=65536 => Ok(n as u32),
                    n => Err(SceneError::at(
                        here.clone(),
                        format!("`{name}` must be from 1 to 65536, found {n}"),
                    )),
                }
            };
            r.desc.render.width = size("xresolution", 1280)?;
            r.desc.render.height = size("yresolution", 720)?;
            p.string("filename")?;
            r.iso = match p.float("iso", 100.0)? {
                iso if iso > 0.0 && iso.is_finite() => iso,
                iso => return Err(SceneError::at(here, format!("`iso` must be positive, found {iso}"))),
            };
        }
        "Sampler" => {
            r.desc.render.sampler = match kind {
                "independent" => SamplerKind::Independent,
                "stratified" => SamplerKind::Stratified,
                "halton" => SamplerKind::Halton,
                "sobol" | "zsobol" | "paddedsobol" | "pmj02bn" => SamplerKind::Sobol,
                other => {
                    r.warn("sampler", format!("{here}: sampler `{other}` is read as `sobol`"));
                    SamplerKind::Sobol
                }
            };
            let n = p.int("pixelsamples", 16)?;
            if !(1..=1 << 24).contains(&n) {
                return Err(SceneError::at(
                    here,
                    format!("pixelsamples must be from 1 to 16777216, found {n}"),
                ));
            }
            r.desc.render.spp = n as u32;
            p.int("seed", 0)?;
        }
        "PixelFilter" => {
            let radius =
                |default: f32| -> Result<f32> { Ok(p.float("xradius", default)?.max(p.float("yradius", default)?)) };
            r.desc.render.filter = match kind {
                "gaussian" => Filter::Gaussian {
                    radius: radius(1.5)?,
                    sigma: p.float("sigma", 0.5)?,
                },
                "box" => Filter::Box { radius: radius(0.5)? },
                "triangle" => Filter::Tent { radius: radius(2.0)? },
                other => {
                    r.warn("filter", format!("{here}: filter `{other}` is read as `gaussian`"));
                    Filter::Gaussian {
                        radius: 1.5,
                        sigma: 0.5,
                    }
                }
            };
        }
        _ => {
            use penumbra_render::integrators::IntegratorKind;
            r.desc.render.integrator = match kind {
                "path" => IntegratorKind::Path,
                "volpath" => IntegratorKind::Volpath,
                "bdpt" => {
                    for flag in ["visualizestrategies", "visualizeweights"] {
                        if p.bool(flag, false)? {
                            r.warn(
                                "integrator",
                                format!("{here}: `{flag}` is `penumbra render --debug-strategies`"),
                            );
                        }
                    }
                    IntegratorKind::Bdpt
                }
                "mlt" => {
                    // pbrt's MLT is the multiplexed one (per-length chains choosing the strategy).
                    let m = &mut r.desc.render.mlt;
                    m.large_step_probability = p.float("largestepprobability", 0.3)?.clamp(0.0, 1.0);
                    m.sigma = p.float("sigma", 0.01)?.clamp(0.0, 1.0);
                    m.chains = p.int("chains", 1000)?.clamp(1, 10_000_000) as u32;
                    m.bootstrap = p.int("bootstrapsamples", 100_000)?.clamp(1, 100_000_000) as u32;
                    let mutations = p.int("mutationsperpixel", 0)?;
                    if mutations > 0 {
                        r.desc.render.spp = mutations.min(u32::MAX as i64) as u32;
                    }
                    IntegratorKind::Mlt
                }
                "sppm" => {
                    let o = &mut r.desc.render.photon;
                    let photons = p.int("photonsperiteration", -1)?;
                    o.photons = if photons > 0 { photons as u64 } else { 0 };
                    // pbrt's default radius (1 scene unit) suits few scenes: ours is
                    // from the pixel footprint unless the file gives one.
                    let radius = p.float("radius", 0.0)?;
                    o.radius = if radius > 0.0 && radius.is_finite() {
                        radius
                    } else {
                        0.0
                    };
                    let iterations = p.int("iterations", 0)?.max(p.int("numiterations", 0)?);
                    if iterations > 0 {
                        r.desc.render.spp = iterations.min(u32::MAX as i64) as u32;
                    }
                    IntegratorKind::Sppm
                }
                _ => {
                    r.warn(
                        "integrator",
                        format!("{here}: integrator `{kind}` is rendered with `path`"),
                    );
                    IntegratorKind::Path
                }
            };
            // pbrt counts scattering events; Mitsuba's depth (ours) counts segments.
            let depth = p.int("maxdepth", 5)?;
            r.desc.render.max_depth = (depth.max(0) as u64 + 1).min(MAX_DEPTH_LIMIT as u64) as u32;
            p.bool("regularize", false)?;
        }
    }
    unused(r, p, &what, &here);
    Ok(())
}

pub fn texture(r: &mut Reader, class: &str, p: &Params, file: &SourceFile, here: Location) -> Result<Texture> {
    let t = match class {
        "imagemap" => {
            let name = p
                .string("filename")?
                .ok_or_else(|| SceneError::at(here.clone(), "an imagemap needs a \"string filename\""))?;
            let path = r.resolve(file, &name);
            let srgb = p.string("encoding")?.is_none_or(|e| e == "sRGB");
            let wrap = match p.string("wrap")?.as_deref() {
                None | Some("repeat") => Wrap::Repeat,
                Some("clamp") => Wrap::Clamp,
                Some("black") => Wrap::Black,
                Some(other) => {
                    let message = format!("unknown wrap \"{other}\": expected repeat, clamp or black");
                    return Err(SceneError::at(here.clone(), message));
                }
            };
            let texture = crate::image_input::image_texture(&path, srgb, p.float("uscale", 1.0)?)
                .map_err(|e| SceneError::at(here.clone(), e))?;
            crate::image_input::with_wrap(texture, [wrap; 2])
        }
        "scale" => {
            // `tex` times `scale`: a number (a texture as the scale is not supported).
            if p.texture_name("scale").is_some() {
                r.warn(
                    "scale by texture",
                    format!("{here}: a `scale` texture scaled by another texture is read unscaled"),
                );
            }
            let factor = if p.texture_name("scale").is_some() {
                1.0
            } else {
                p.float("scale", 1.0)?
            };
            scaled(texture_param(r, p, "tex", 1.0)?, factor)
        }
        "checkerboard" => Texture::Checker(penumbra_render::texture::Checker {
            even: color(p, "tex1", ColorKind::Albedo)?.unwrap_or(Rgb::WHITE),
            odd: color(p, "tex2", ColorKind::Albedo)?.unwrap_or(Rgb::BLACK),
            size: 1.0 / p.float("uscale", 1.0)?.max(1e-6),
        }),
        "constant" => Texture::Constant(color(p, "value", ColorKind::Albedo)?.unwrap_or(Rgb::WHITE)),
        other => {
            r.warn(
                &format!("texture {other}"),
                format!("{here}: texture `{other}` is not supported: read as 0.5"),
            );
            Texture::Constant(Rgb::splat(0.5))
        }
    };
    unused(r, p, &format!("texture {class}"), &here);
    Ok(t)
}

/// `t` times `factor`.
fn scaled(t: Texture, factor: f32) -> Texture {
    match t {
        Texture::Constant(c) => Texture::Constant(c * factor),
        Texture::Checker(penumbra_render::texture::Checker { even, odd, size }) => {
            Texture::Checker(penumbra_render::texture::Checker {
                even: even * factor,
                odd: odd * factor,
                size,
            })
        }
        Texture::Image(penumbra_render::texture::ImageTexture { image, scale }) => {
            Texture::Image(penumbra_render::texture::ImageTexture {
                image: std::sync::Arc::new(penumbra_render::texture::TextureImage {
                    pixels: image.pixels.iter().map(|&p| p * factor).collect(),
                    ..(*image).clone()
                }),
                scale,
            })
        }
    }
}

/// A light's spectrum times `scale` (pbrt scales lights given as spectra to unit
/// luminance first; `rgb` ones stay as given) and the imaging ratio.
fn emitted(r: &Reader, p: &Params, name: &str) -> Result<Rgb> {
    let c = color(p, name, ColorKind::Illuminant)?.unwrap_or(Rgb::WHITE);
    Ok(c * p.float("scale", 1.0)? * r.imaging_ratio())
}

pub fn light(r: &mut Reader, kind: &str, p: &Params, file: &SourceFile, here: Location) -> Result<()> {
    let ctm = r.state.ctm;
    let point = |name: &str, default: Vec3| -> Result<Vec3> {
        Ok(match p.points(name, 3)? {
            Some(v) if v.len() == 1 => Vec3::new(v[0][0], v[0][1], v[0][2]),
            _ => default,
        })
    };
    match kind {
        "point" => {
            let position = ctm.point(point("from", Vec3::ZERO)?);
            r.desc.lights.push(LightDesc::Point {
                position,
                intensity: emitted(r, p, "I")?,
            });
        }
        "spot" => {
            let (from, to) = (ctm.point(point("from", Vec3::ZERO)?), ctm.point(point("to", Vec3::Z)?));
            let cone = p.float("coneangle", 30.0)?;
            let delta = p.float("conedelta", 5.0)?;
            r.desc.lights.push(LightDesc::Spot {
                position: from,
                target: to,
                intensity: emitted(r, p, "I")?,
                cone_angle: cone,
                falloff_start: (cone - delta).clamp(0.0, cone),
            });
        }
        "distant" => {
            let direction = ctm.vector(point("to", Vec3::Z)? - point("from", Vec3::ZERO)?);
            if direction.length_squared() == 0.0 {
                return Err(SceneError::at(here, "a distant light needs `from` and `to` apart"));
            }
            r.desc.lights.push(LightDesc::Directional {
                direction,
                irradiance: emitted(r, p, "L")?,
            });
        }
        "infinite" => {
            if r.desc.environment.is_some() {
                return Err(SceneError::at(here, "a second infinite light: the scene may have one"));
            }
            // An image in pbrt's equal-area octahedral mapping, times `scale`, placed by the
            // current transform; or a constant `L`.
            let (source, scale, transform) = match p.string("filename")? {
                Some(name) => {
                    let path = r.resolve(file, &name);
                    if !path.exists() {
                        return Err(SceneError::at(
                            here,
                            format!("cannot read the environment map {}", path.display()),
                        ));
                    }
                    (
                        EnvironmentSource::Octahedral(path),
                        Rgb::splat(p.float("scale", 1.0)? * r.imaging_ratio()),
                        r.state.ctm,
                    )
                }
                None => (EnvironmentSource::Constant, emitted(r, p, "L")?, Transform::IDENTITY),
            };
            r.desc.environment = Some(EnvironmentDesc {
                source,
                scale,
                transform,
                spin: 0.0,
                location: Some(here.clone()),
            });
        }
        other => {
            r.warn(
                &format!("light {other}"),
                format!("{here}: light `{other}` is not supported: skipped"),
            );
            return Ok(());
        }
    }
    p.float("power", 0.0)?.ne(&0.0).then(|| {
        r.warn(
            "power",
            format!("{here}: a light's `power` is not supported: its own value is used"),
        )
    });
    unused(r, p, &format!("light {kind}"), &here);
    Ok(())
}

pub fn area_light(r: &mut Reader, kind: &str, p: &Params, here: Location) -> Result<Option<Emission>> {
    if kind != "diffuse" {
        r.warn(
            "area light",
            format!("{here}: area light `{kind}` is read as `diffuse`"),
        );
    }
    let e = Emission {
        radiance: emitted(r, p, "L")?,
        two_sided: p.bool("twosided", false)?,
        texture: None,
        spectrum: None,
    };
    unused(r, p, &format!("area light {kind}"), &here);
    Ok(Some(e))
}
