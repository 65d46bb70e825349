//! MTL materials (the `mtllib` of an OBJ file) as Penumbra materials, by the illumination
//! model (`illum`) and the colours the MTL specification gives them:
//!
//! - `d` below 1 or `illum` 4, 6, 7, 9: glass, a smooth dielectric of index `Ni` (1.5 by
//!   default), its transmission tinted by `Tf` when given;
//! - `illum` 3, 5, 8: a mirror tinted by `Ks`;
//! - a non-black `Ks` (`illum` 2, or none): plastic, `Kd` (or `map_Kd`) under a coating of
//!   index 1.5 whose GGX roughness comes from the Phong exponent `Ns` as
//!   alpha = sqrt(2 / (Ns + 2)) (Walter et al. 2007, eq. 28's Beckmann match);
//! - otherwise (`illum` 0, 1, or no `Ks`): Lambertian `Kd` (or `map_Kd`, sRGB);
//!
//! all two-sided, as OBJ viewers show them; `Ke` makes the surface emit.

use crate::desc::Emission;
use penumbra_core::Rgb;
use penumbra_render::bsdfs::MetalFresnel;
use penumbra_render::materials::Roughness;
use penumbra_render::materials::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use penumbra_render::{Material, Texture};
use std::path::Path;

fn rgb(c: Option<[f32; 3]>) -> Option<Rgb> {
    c.map(|[r, g, b]| Rgb::new(r, g, b))
}

/// The material and emission of `m`; `dir` is the OBJ file's folder (textures are relative
/// to it). Warnings go to `warn`.
pub fn material(m: &tobj::Material, dir: &Path, warn: &mut dyn FnMut(String)) -> (Material, Option<Emission>) {
    let kd = rgb(m.diffuse).unwrap_or(Rgb::splat(0.8));
    let ks = rgb(m.specular).unwrap_or(Rgb::BLACK);
    let illum = m
        .illumination_model
        .unwrap_or(if ks.max_component() > 0.0 { 2 } else { 1 });
    let diffuse = match &m.diffuse_texture {
        Some(name) => crate::image_input::image_texture(&dir.join(name.trim()), true, 1.0).unwrap_or_else(|e| {
            warn(format!("material `{}`: {e}: Kd is used", m.name));
            Texture::Constant(kd)
        }),
        None => Texture::Constant(kd),
    };
    let dissolve = m.dissolve.unwrap_or(1.0);
    let material = if dissolve < 1.0 || matches!(illum, 4 | 6 | 7 | 9) {
        let tint = m.unknown_param.get("Tf").and_then(|t| parse3(t)).unwrap_or(Rgb::WHITE);
        Material::Dielectric(DielectricMaterial {
            eta: m.optical_density.filter(|&n| n > 0.0).unwrap_or(1.5),
            reflectance: Texture::Constant(Rgb::WHITE),
            transmittance: Texture::Constant(tint),
            roughness: None,
        })
    } else if matches!(illum, 3 | 5 | 8) {
        Material::TwoSided(Box::new(Material::Conductor(ConductorMaterial {
            fresnel: MetalFresnel::Complex {
                eta: Rgb::BLACK,
                k: Rgb::WHITE,
            },
            specular: Texture::Constant(if ks.max_component() > 0.0 { ks } else { Rgb::WHITE }),
            roughness: None,
        })))
    } else if ks.max_component() > 0.0 && illum >= 2 {
        let ns = m.shininess.unwrap_or(10.0).max(0.0);
        let alpha = (2.0 / (ns + 2.0)).sqrt();
        Material::TwoSided(Box::new(Material::plastic(
            diffuse,
            Texture::Constant(ks),
            1.5,
            Some(Roughness::isotropic(alpha)),
        )))
    } else {
        Material::TwoSided(Box::new(Material::Diffuse(DiffuseMaterial { reflectance: diffuse })))
    };
    let ke = m.unknown_param.get("Ke").and_then(|t| parse3(t)).or(rgb(m.emissive));
    let emission = ke.filter(|e| e.max_component() > 0.0).map(|radiance| Emission {
        radiance,
        two_sided: true,
        texture: None,
        spectrum: None,
    });
    (material, emission)
}

fn parse3(s: &str) -> Option<Rgb> {
    let v: Vec<f32> = s.split_whitespace().map(str::parse).collect::<Result<_, _>>().ok()?;
    match v[..] {
        [g] => Some(Rgb::splat(g)),
        [r, g, b] => Some(Rgb::new(r, g, b)),
        _ => None,
    }
}
