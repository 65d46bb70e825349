//! `[[material]]` tables: a unique `name`, a `type` (only `phong` so far) and its keys.

use super::choice;
use crate::desc::MaterialDesc;
use crate::params::{Result, Table, Value};
use penumbra_core::Rgb;
use penumbra_render::materials::Phong;
use penumbra_render::{Material, Texture};

pub fn read_all(tables: &[Table]) -> Result<Vec<MaterialDesc>> {
    let mut out: Vec<MaterialDesc> = Vec::new();
    for t in tables {
        let name_value = t.require("name")?;
        let name = name_value.str()?.to_string();
        if out.iter().any(|m| m.name == name) {
            return Err(name_value
                .error(format!("material `{name}` is defined twice"))
                .label("second definition"));
        }
        if let Some(kind) = t.get("type") {
            choice(&kind, "material type", &["phong"], |s| (s == "phong").then_some(()))?;
        }
        let material = Material::Phong(read_phong(t)?);
        t.finish()?;
        out.push(MaterialDesc { name, material });
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
            Some(v) => texture(&v)?,
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

/// A colour, or a texture table `{ type = "checker", even, odd, size }`.
fn texture(v: &Value) -> Result<Texture> {
    if !v.is_table() {
        return Ok(Texture::Constant(v.rgb()?));
    }
    let t = v.table()?;
    choice(&t.require("type")?, "texture type", &["checker"], |s| {
        (s == "checker").then_some(())
    })?;
    let tex = Texture::Checker {
        even: t.rgb_or("even", Rgb::WHITE)?,
        odd: t.rgb_or("odd", Rgb::BLACK)?,
        size: t.positive_or("size", 0.125)?,
    };
    t.finish()?;
    Ok(tex)
}
