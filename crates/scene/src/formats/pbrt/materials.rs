//! pbrt-v4's materials mapped onto Penumbra's: `diffuse`, `conductor`, `dielectric`
//! (`thindielectric` read as it), `coateddiffuse` and `coatedconductor` (the layered BSDF,
//! every parameter), `mix`; anything else is a grey diffuse with one warning per kind.

use super::objects::{color, texture_param, unused};
use super::params::{ColorKind, Params};
use super::{Reader, Result};
use crate::{Location, SceneError};
use penumbra_core::Rgb;
use penumbra_render::bsdfs::MetalFresnel;
use penumbra_render::materials::{metal_ior, Coated, CoatedBase, Roughness};
use penumbra_render::materials::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use penumbra_render::{Material, Texture};

/// pbrt-v4's roughness: `roughness` or `uroughness`/`vroughness` (after `prefix`, e.g.
/// `interface.`), remapped to GGX alpha by sqrt when `remaproughness` (the default); `None`
/// when smooth.
fn roughness(p: &Params, prefix: &str) -> Result<Option<Roughness>> {
    let iso = p.float(&format!("{prefix}roughness"), 0.0)?;
    let u = p.float(&format!("{prefix}uroughness"), iso)?;
    let v = p.float(&format!("{prefix}vroughness"), iso)?;
    let remap = p.bool("remaproughness", true)?;
    let alpha = |x: f32| if remap { x.max(0.0).sqrt() } else { x.max(0.0) };
    let (au, av) = (alpha(u), alpha(v));
    Ok((au > 0.0 || av > 0.0).then(|| Roughness {
        alpha_u: Texture::Constant(Rgb::splat(au)),
        alpha_v: Texture::Constant(Rgb::splat(av)),
    }))
}

fn eta(p: &Params, name: &str, default: f32) -> Result<f32> {
    Ok(match color(p, name, ColorKind::Albedo)? {
        Some(c) => c.g,
        None => default,
    })
}

/// A metal's Fresnel term from `{prefix}eta` and `{prefix}k` (copper by default), or from
/// a reflectance `colour` (pbrt-v4 derives an index from it; we take it as the reflectance
/// at normal incidence of Schlick's Fresnel term).
fn metal(p: &Params, prefix: &str, colour: &str) -> Result<(MetalFresnel, Rgb)> {
    let copper = metal_ior("Cu").expect("copper is in the table");
    let eta = color(p, &format!("{prefix}eta"), ColorKind::Albedo)?.unwrap_or(copper.0);
    let k = color(p, &format!("{prefix}k"), ColorKind::Albedo)?.unwrap_or(copper.1);
    Ok(match color(p, colour, ColorKind::Albedo)? {
        Some(f0) => (MetalFresnel::Schlick, f0),
        None => (MetalFresnel::Complex { eta, k }, Rgb::WHITE),
    })
}

/// The coated materials' layer parameters with pbrt-v4's defaults: `thickness` (0.01),
/// the medium's `albedo` (0) and `g` (0), `maxdepth` (10) and `nsamples` (1).
fn layer(r: &Reader, p: &Params) -> Result<Coated> {
    let count = |name: &str, default: i64| -> Result<u32> {
        let v = p.int(name, default)?;
        u32::try_from(v).ok().filter(|&v| v <= 10_000).ok_or_else(|| {
            let param = p.list.iter().rev().find(|x| x.name == name).expect("a set value");
            p.error(param, format!("`{name}` must be between 0 and 10000, not {v}"))
        })
    };
    Ok(Coated {
        thickness: p.float("thickness", 0.01)?.max(0.0),
        albedo: texture_param(r, p, "albedo", 0.0)?,
        g: p.float("g", 0.0)?.clamp(-0.99, 0.99),
        max_depth: count("maxdepth", 10)?,
        samples: count("nsamples", 1)?.max(1),
        ..Coated::default()
    })
}

/// The material of `Material` or `MakeNamedMaterial`; its index.
pub(super) fn material(r: &mut Reader, kind: &str, p: &Params, here: Location) -> Result<usize> {
    let m = match kind {
        "diffuse" => Material::Diffuse(DiffuseMaterial {
            reflectance: texture_param(r, p, "reflectance", 0.5)?,
        }),
        "conductor" => {
            let (fresnel, specular) = metal(p, "", "reflectance")?;
            Material::Conductor(ConductorMaterial {
                fresnel,
                specular: Texture::Constant(specular),
                roughness: roughness(p, "")?,
            })
        }
        "coatedconductor" => {
            // pbrt-v4 names the metal's colour `reflectance`; some exporters write
            // `conductor.reflectance`.
            let colour = if p.list.iter().any(|x| x.name == "reflectance") {
                "reflectance"
            } else {
                "conductor.reflectance"
            };
            let (fresnel, specular) = metal(p, "conductor.", colour)?;
            Material::Coated(Coated {
                base: CoatedBase::Conductor {
                    fresnel,
                    specular: Texture::Constant(specular),
                    roughness: roughness(p, "conductor.")?,
                },
                eta: eta(p, "interface.eta", 1.5)?,
                roughness: roughness(p, "interface.")?,
                ..layer(r, p)?
            })
        }
        "dielectric" | "thindielectric" => {
            if kind == "thindielectric" {
                r.warn(
                    "thindielectric",
                    format!("{here}: `thindielectric` is rendered as a `dielectric`"),
                );
            }
            Material::Dielectric(DielectricMaterial {
                eta: eta(p, "eta", 1.5)?,
                reflectance: Texture::Constant(Rgb::WHITE),
                transmittance: Texture::Constant(Rgb::WHITE),
                roughness: roughness(p, "")?,
            })
        }
        "coateddiffuse" => Material::Coated(Coated {
            base: CoatedBase::Diffuse {
                reflectance: texture_param(r, p, "reflectance", 0.5)?,
            },
            eta: eta(p, "eta", 1.5)?,
            roughness: roughness(p, "")?,
            ..layer(r, p)?
        }),
        // Only a boundary between media.
        "interface" => Material::null(),
        "mix" => {
            let names = p.strings("materials")?.unwrap_or_default();
            if names.len() != 2 {
                return Err(SceneError::at(
                    here,
                    "a `mix` material needs \"string materials\" with two names",
                ));
            }
            let part = |n: &str| -> Result<Material> {
                let i = r
                    .named_materials
                    .get(n)
                    .ok_or_else(|| SceneError::at(here.clone(), format!("no material is named `{n}`")))?;
                Ok(r.desc.materials[*i].material.clone())
            };
            Material::Blend {
                a: Box::new(part(&names[0])?),
                b: Box::new(part(&names[1])?),
                weight: texture_param(r, p, "amount", 0.5)?,
            }
        }
        other => {
            r.warn(
                &format!("material {other}"),
                format!("{here}: material `{other}` is not supported: rendered as a grey diffuse"),
            );
            Material::Diffuse(DiffuseMaterial {
                reflectance: Texture::Constant(Rgb::splat(0.5)),
            })
        }
    };
    // pbrt's BSDFs reflect on both sides of a surface (Mitsuba's and ours on the front).
    let m = match m {
        Material::Dielectric(DielectricMaterial { .. }) | Material::Blend { .. } | Material::Coated(_) => m,
        m => Material::TwoSided(Box::new(m)),
    };
    p.string("type")?;
    p.texture_name("displacement").is_some().then(|| {
        r.warn(
            "displacement",
            format!("{here}: displacement is not supported: ignored"),
        )
    });
    unused(r, p, &format!("material {kind}"), &here);
    let index = r.desc.materials.len();
    r.desc.materials.push(crate::desc::MaterialDesc {
        name: format!("{kind} at {here}"),
        material: m,
        spectra: None,
    });
    Ok(index)
}
