//! Mitsuba's BSDFs and textures mapped onto Penumbra's materials and textures.

use super::props::Props;
use super::{warn_unused, At, Reader, Result};
use penumbra_core::Rgb;
use penumbra_render::bsdfs::MetalFresnel;
use penumbra_render::bsdfs::Role;
use penumbra_render::materials::{metal_ior, metal_spectra, Roughness};
use penumbra_render::materials::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use penumbra_render::texture::Wrap;
use penumbra_render::{Material, Texture};

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

/// GGX roughness from `alpha` or `alpha_u`/`alpha_v` (default 0.1). Mitsuba's other
/// distribution, Beckmann, is also its default: either is warned and rendered as GGX.
fn roughness(r: &mut Reader, p: &Props, what: &str) -> Result<Roughness> {
    match p.string(r, "distribution")? {
        Some((d, _)) if d == "ggx" => {}
        Some((d, v)) => r.warn_once(
            "distribution",
            format!("{}: {what}: the `{d}` distribution is rendered as GGX", v.place()),
        ),
        None => {
            let at = p.at;
            r.warn_once(
                "distribution",
                format!(
                    "{}: {what}: Mitsuba's default `beckmann` distribution is rendered as GGX (give `ggx` to match)",
                    at.place()
                ),
            )
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
    let kind = r.require(at, "type")?;
    let what = format!("bsdf {kind}");
    // Parameters given as spectra by wavelength, kept for spectral rendering.
    for (name, role) in [
        ("reflectance", Role::Reflectance),
        ("diffuse_reflectance", Role::Reflectance),
        ("specular_reflectance", Role::Specular),
        ("specular_transmittance", Role::Transmittance),
        ("eta", Role::Eta),
        ("k", Role::K),
    ] {
        if let Some(s) = p.spectrum(r, name)? {
            r.spectra.by_role.push((role, s));
        }
    }
    let material = match kind.as_str() {
        "diffuse" => Material::Diffuse(DiffuseMaterial {
            reflectance: p.texture(r, "reflectance", 0.5, false)?,
        }),
        // Only a boundary between media.
        "null" => Material::null(),
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
                        Some(m) => {
                            if let Some(s) = metal_spectra(&name) {
                                r.spectra.by_role.extend(s.by_role);
                            }
                            m
                        }
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
            Material::Conductor(ConductorMaterial {
                fresnel: MetalFresnel::Complex { eta, k },
                specular: p.texture(r, "specular_reflectance", 1.0, false)?,
                roughness: (kind == "roughconductor")
                    .then(|| roughness(r, &p, &what))
                    .transpose()?,
            })
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            if kind == "thindielectric" {
                r.warn_once(
                    "thindielectric",
                    format!("{}: `thindielectric` is rendered as a smooth `dielectric`", at.place()),
                );
            }
            Material::Dielectric(DielectricMaterial {
                eta: ior(r, &p, "int_ior", 1.5046)? / ior(r, &p, "ext_ior", 1.000277)?,
                reflectance: p.texture(r, "specular_reflectance", 1.0, false)?,
                transmittance: p.texture(r, "specular_transmittance", 1.0, false)?,
                roughness: (kind == "roughdielectric")
                    .then(|| roughness(r, &p, &what))
                    .transpose()?,
            })
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
            return Ok(Material::Diffuse(DiffuseMaterial {
                reflectance: Texture::Constant(Rgb::splat(0.5)),
            }));
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
    let kind = r.require(at, "type")?;
    let tex = match kind.as_str() {
        "bitmap" => {
            let (name, v) = p
                .string(r, "filename")?
                .ok_or_else(|| at.error("a bitmap needs a `filename`"))?;
            let raw = p.bool_or(r, "raw", data)?;
            let path = r.resolve(v, &name);
            let wrap = match p.string(r, "wrap_mode")? {
                None => Wrap::Repeat,
                Some((mode, at)) => match mode.as_str() {
                    "repeat" => Wrap::Repeat,
                    "mirror" => Wrap::Mirror,
                    "clamp" => Wrap::Clamp,
                    _ => {
                        let message = format!("unknown wrap_mode `{mode}`: expected repeat, mirror or clamp");
                        return Err(r.attr_error(at, "value", message));
                    }
                },
            };
            match p.string(r, "filter_type")? {
                Some((f, at)) if f == "nearest" => r.warn_once(
                    "filter_type nearest",
                    format!(
                        "{}: filter_type `nearest` is not supported: textures are filtered bilinearly",
                        at.place()
                    ),
                ),
                Some((f, at)) if f != "bilinear" => {
                    let message = format!("unknown filter_type `{f}`: expected bilinear or nearest");
                    return Err(r.attr_error(at, "value", message));
                }
                _ => {}
            }
            let texture = crate::image_input::image_texture(&path, !raw, uv_scale(r, &p)?)
                .map_err(|e| r.attr_error(v, "value", e))?;
            crate::image_input::with_wrap(texture, [wrap; 2])
        }
        "checkerboard" => Texture::Checker(penumbra_render::texture::Checker {
            even: p.color_or(r, "color0", 0.4)?,
            odd: p.color_or(r, "color1", 0.2)?,
            size: 0.5 / uv_scale(r, &p)?,
        }),
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
