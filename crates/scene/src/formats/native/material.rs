//! `[[material]]` tables: a unique `name`, a `type` and its keys (docs/scene-format.md).
//!
//! - `phong` (the default): `diffuse`, `specular`, `exponent`, `mirror`, `transmission`,
//!   `ior`, `ior_outside`.
//! - `diffuse`: `reflectance` (colour or texture, default 0.5).
//! - `conductor`: `metal` (Au, Ag, Cu, Al; default Au) or `eta` and `k` colours;
//!   `specular` tint; `roughness` (GGX α) or `alpha_u` and `alpha_v`; smooth without.
//! - `dielectric`: `ior` (default 1.5; or a glass's name, `"BK7"`: dispersive in spectral
//!   mode), `ior_outside` (default 1), `reflectance`,
//!   `transmittance`, `roughness` / `alpha_u` + `alpha_v`.
//! - `plastic`: `diffuse` (default 0.5), `specular` (default 1), `ior` (1.5),
//!   `ior_outside` (1), `roughness` (isotropic).
//! - `blend`: `a` and `b`, names of materials defined above, and `weight` of `b` (0.5).
//! - `coated` (pbrt-v4's coated materials, the layered BSDF): a diffuse base of
//!   `reflectance` (0.5), or a metal base when `metal` or `eta` and `k` are given, with
//!   `metal_roughness` (α; smooth without); the coating's `ior` (1.5) and `roughness`
//!   (isotropic α); the layer's `thickness` (0.01), medium `albedo` (0) and `g` (0),
//!   `max_depth` (10) and `samples` (1). Always two-sided.
//!
//! - `null`: no keys; only a boundary between media (`[[medium]]`), which light crosses
//!   unchanged (Mitsuba's `null` BSDF, pbrt-v4's `interface` material).
//!
//! `diffuse`, `conductor` and `plastic` take `two_sided` (default true): false makes the
//! back of the surface black, as Mitsuba's BSDFs without `twosided`; a blend's parts keep
//! their own. Every type takes
//! `normal_map`, an image file of tangent-space normals.

use super::{choice, unique_name};
use crate::desc::MaterialDesc;
use crate::params::{Result, Table, Value};
use penumbra_core::Rgb;
use penumbra_render::bsdfs::MetalFresnel;
use penumbra_render::materials::{metal_ior, metal_spectra, Coated, CoatedBase, Phong, Roughness, METALS};
use penumbra_render::materials::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use penumbra_render::spectral::{glass, MaterialSpectra, GLASSES};
use penumbra_render::{Material, Texture};

const TYPES: [&str; 8] = [
    "phong",
    "diffuse",
    "conductor",
    "dielectric",
    "plastic",
    "blend",
    "coated",
    "null",
];

pub fn read_all(tables: &[Table]) -> Result<Vec<MaterialDesc>> {
    let mut out: Vec<MaterialDesc> = Vec::new();
    for t in tables {
        let name = unique_name(t, "material", out.iter().map(|m| &m.name))?;
        let kind = match t.get("type") {
            Some(v) => choice(&v, "material type", &TYPES, |s| {
                TYPES.contains(&s).then(|| s.to_string())
            })?,
            None => "phong".to_string(),
        };
        let mut spectra = None;
        let material = match kind.as_str() {
            "phong" => Material::Phong(read_phong(t)?),
            "dielectric" => read_dielectric(t, &mut spectra)?,
            "coated" => read_coated(t)?,
            "null" => Material::null(),
            other => {
                let m = match other {
                    "diffuse" => Material::Diffuse(DiffuseMaterial {
                        reflectance: texture_or(t, "reflectance", 0.5)?,
                    }),
                    "conductor" => read_conductor(t, &mut spectra)?,
                    "plastic" => {
                        let eta = t.positive_or("ior", 1.5)? / t.positive_or("ior_outside", 1.0)?;
                        let roughness = roughness(t, false)?;
                        Material::plastic(
                            texture_or(t, "diffuse", 0.5)?,
                            texture_or(t, "specular", 1.0)?,
                            eta,
                            roughness,
                        )
                    }
                    _ => read_blend(t, &out)?,
                };
                // A blend's parts keep their own sides (wrapping it would turn a glass part
                // inside out).
                if other != "blend" && t.get("two_sided").map_or(Ok(true), |v| v.bool())? {
                    Material::TwoSided(Box::new(m))
                } else {
                    m
                }
            }
        };
        let material = match t.get("normal_map") {
            Some(v) => Material::NormalMapped {
                map: image_texture_file(&v, v.str()?, 1.0, false)?,
                inner: Box::new(material),
            },
            None => material,
        };
        t.finish()?;
        out.push(MaterialDesc {
            name,
            material,
            spectra,
        });
    }
    Ok(out)
}

fn read_phong(t: &Table) -> Result<Phong> {
    let d = Phong::default();
    let ior = t.positive_or("ior", d.ior)?;
    let ior_outside = t.positive_or("ior_outside", d.ior_outside)?;
    let exponent = t.f32_or("exponent", d.exponent)?;
    if exponent < 0.0 {
        return Err(t.require("exponent")?.error("`exponent` must not be negative"));
    }
    Ok(Phong {
        diffuse: match t.get("diffuse") {
            Some(v) => texture(&v, false)?,
            None => d.diffuse,
        },
        specular: t.rgb_or("specular", d.specular)?,
        exponent,
        mirror: t.rgb_or("mirror", d.mirror)?,
        transmission: t.rgb_or("transmission", d.transmission)?,
        ior,
        ior_outside,
    })
}

/// A conductor; a named `metal` brings its measured spectra for spectral rendering.
fn read_conductor(t: &Table, spectra: &mut Option<MaterialSpectra>) -> Result<Material> {
    let (eta, k) = metal_index(t)?;
    if t.get("eta").is_none() {
        if let Some(v) = t.get("metal") {
            *spectra = metal_spectra(v.str()?);
        }
    }
    Ok(Material::Conductor(ConductorMaterial {
        fresnel: MetalFresnel::Complex { eta, k },
        specular: texture_or(t, "specular", 1.0)?,
        roughness: roughness(t, true)?,
    }))
}

fn read_coated(t: &Table) -> Result<Material> {
    let d = Coated::default();
    let base = if ["metal", "eta", "k"].iter().any(|k| t.get(k).is_some()) {
        let (eta, k) = metal_index(t)?;
        let alpha = t.f32_or("metal_roughness", 0.0)?;
        if !(0.0..=1.0).contains(&alpha) {
            let v = t.require("metal_roughness")?;
            return Err(v.error(format!("`metal_roughness` must lie in [0, 1], found {alpha}")));
        }
        CoatedBase::Conductor {
            fresnel: MetalFresnel::Complex { eta, k },
            specular: Texture::Constant(Rgb::WHITE),
            roughness: (alpha > 0.0).then(|| Roughness::isotropic(alpha)),
        }
    } else {
        CoatedBase::Diffuse {
            reflectance: texture_or(t, "reflectance", 0.5)?,
        }
    };
    let count = |key: &str, default: u32| -> Result<u32> {
        t.get(key).map_or(Ok(default), |v| Ok(v.integer(0..=10_000)? as u32))
    };
    let g = t.f32_or("g", d.g)?;
    if g.abs() >= 1.0 {
        return Err(t.require("g")?.error(format!("`g` must lie in (-1, 1), found {g}")));
    }
    Ok(Material::Coated(Coated {
        base,
        eta: t.positive_or("ior", d.eta)?,
        roughness: roughness(t, false)?,
        thickness: t.positive_or("thickness", d.thickness)?,
        albedo: texture_or(t, "albedo", 0.0)?,
        g,
        max_depth: count("max_depth", d.max_depth)?,
        samples: count("samples", d.samples)?.max(1),
    }))
}

/// A metal's complex index: `metal` (a name) or `eta` and `k` (gold by default).
fn metal_index(t: &Table) -> Result<(Rgb, Rgb)> {
    Ok(match (t.get("eta"), t.get("k")) {
        (Some(eta), Some(k)) => {
            if let Some(metal) = t.get("metal") {
                return Err(metal.error("give either `metal` or `eta` and `k`, not both"));
            }
            (eta.rgb()?, k.rgb()?)
        }
        (Some(v), None) | (None, Some(v)) => return Err(v.error("`eta` and `k` go together")),
        (None, None) => {
            let names: Vec<&str> = METALS.iter().map(|m| m.0).collect();
            match t.get("metal") {
                Some(v) => choice(&v, "metal", &names, metal_ior)?,
                None => metal_ior("Au").expect("gold is a named metal"),
            }
        }
    })
}

/// A dielectric; `ior` a number or a glass's name (dispersive: its index by wavelength
/// goes to `spectra`, its index at 550 nm to RGB rendering).
fn read_dielectric(t: &Table, spectra: &mut Option<MaterialSpectra>) -> Result<Material> {
    let outside = t.positive_or("ior_outside", 1.0)?;
    let inside = match t.get("ior") {
        Some(v) if !v.is_number() => {
            let name = v.str()?;
            let g = glass(name).ok_or_else(|| {
                v.error(format!("unknown glass `{name}`"))
                    .label("not a glass")
                    .help(format!("a number, or one of: {}", GLASSES.map(|g| g.0).join(", ")))
            })?;
            let n = g.eval(550.0);
            spectra.get_or_insert_with(Default::default).ior = Some((g, outside));
            n
        }
        _ => t.positive_or("ior", 1.5)?,
    };
    Ok(Material::Dielectric(DielectricMaterial {
        eta: inside / outside,
        reflectance: texture_or(t, "reflectance", 1.0)?,
        transmittance: texture_or(t, "transmittance", 1.0)?,
        roughness: roughness(t, true)?,
    }))
}

fn read_blend(t: &Table, defined: &[MaterialDesc]) -> Result<Material> {
    let part = |key: &str| -> Result<Box<Material>> {
        let v = t.require(key)?;
        let name = v.str()?;
        defined
            .iter()
            .find(|m| m.name == name)
            .map(|m| Box::new(m.material.clone()))
            .ok_or_else(|| {
                v.error(format!("no material `{name}` is defined above this blend"))
                    .label("unknown material")
            })
    };
    let weight = match t.get("weight") {
        Some(v) if !v.is_number() => texture(&v, true)?,
        _ => texture_or(t, "weight", 0.5)?,
    };
    check_range(t, "weight", &weight)?;
    Ok(Material::Blend {
        a: part("a")?,
        b: part("b")?,
        weight,
    })
}

/// `roughness` (α, isotropic) or `alpha_u` and `alpha_v` (when `anisotropic` is allowed);
/// `None` when absent (smooth).
fn roughness(t: &Table, anisotropic: bool) -> Result<Option<Roughness>> {
    let alpha = |key: &str| -> Result<Option<Texture>> {
        let Some(v) = t.get(key) else { return Ok(None) };
        let tex = if v.is_number() {
            Texture::Constant(Rgb::splat(v.f32()?))
        } else {
            texture(&v, true)?
        };
        check_range(t, key, &tex)?;
        Ok(Some(tex))
    };
    let iso = alpha("roughness")?;
    let (u, v) = if anisotropic {
        (alpha("alpha_u")?, alpha("alpha_v")?)
    } else {
        (None, None)
    };
    match (iso, u, v) {
        (Some(a), None, None) => Ok(Some(Roughness {
            alpha_u: a.clone(),
            alpha_v: a,
        })),
        (None, Some(alpha_u), Some(alpha_v)) => Ok(Some(Roughness { alpha_u, alpha_v })),
        (None, None, None) => Ok(None),
        (Some(_), _, _) => Err(t
            .require("roughness")?
            .error("give either `roughness` or `alpha_u` and `alpha_v`, not both")),
        _ => Err(t.error("`alpha_u` and `alpha_v` go together")),
    }
}

/// Rejects a roughness or weight outside [0, 1], naming the line.
fn check_range(t: &Table, key: &str, tex: &Texture) -> Result<()> {
    let (lo, hi) = (tex.min_value(), tex.max_value());
    let out = [lo.r, lo.g, lo.b, hi.r, hi.g, hi.b]
        .into_iter()
        .find(|x| !(0.0..=1.0).contains(x));
    match out {
        Some(x) => Err(t
            .require(key)?
            .error(format!("`{key}` must lie in [0, 1], found {x}"))
            .label("out of range")),
        None => Ok(()),
    }
}

fn texture_or(t: &Table, key: &str, default: f32) -> Result<Texture> {
    match t.get(key) {
        Some(v) if v.is_number() => Ok(Texture::Constant(Rgb::splat(v.f32()?))),
        Some(v) => texture(&v, false),
        None => Ok(Texture::Constant(Rgb::splat(default))),
    }
}

/// A colour, or a texture table: `{ type = "checker", even, odd, size }` or
/// `{ type = "image", file, scale, srgb }`. `data` textures (roughness, weights, normals)
/// read 8-bit images as they are; colour textures decode them from sRGB, unless `srgb`
/// says otherwise.
fn texture(v: &Value, data: bool) -> Result<Texture> {
    if !v.is_table() {
        return Ok(Texture::Constant(v.rgb()?));
    }
    let t = v.table()?;
    let kind = choice(&t.require("type")?, "texture type", &["checker", "image"], |s| {
        ["checker", "image"].contains(&s).then(|| s.to_string())
    })?;
    let tex = if kind == "checker" {
        Texture::Checker(penumbra_render::texture::Checker {
            even: t.rgb_or("even", Rgb::WHITE)?,
            odd: t.rgb_or("odd", Rgb::BLACK)?,
            size: t.positive_or("size", 0.125)?,
        })
    } else {
        let file = t.require("file")?;
        let srgb = t.get("srgb").map_or(Ok(!data), |v| v.bool())?;
        image_texture_file(&file, file.str()?, t.positive_or("scale", 1.0)?, srgb)?
    };
    t.finish()?;
    Ok(tex)
}

/// The image texture in file `name` (relative to the scene's folder), repeated every
/// 1/`scale` texture units; an error at `at` naming the file when it cannot be read.
fn image_texture_file(at: &Value, name: &str, scale: f32, srgb: bool) -> Result<Texture> {
    let location = at.location();
    let path = location
        .file
        .path
        .parent()
        .unwrap_or(std::path::Path::new("."))
        .join(name);
    crate::image_input::image_texture(&path, srgb, scale).map_err(|e| at.error(e).label("this texture"))
}
