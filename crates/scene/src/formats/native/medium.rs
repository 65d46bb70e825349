//! `[[medium]]` tables: participating media that shapes (`interior`, `exterior`) and the
//! camera (`[camera] medium`) name.
//!
//! - `name`: unique.
//! - `type`: `homogeneous` (the default and, for now, the only kind).
//! - `sigma_a` and `sigma_s`: absorption and scattering per unit length (colours or
//!   numbers; default 0 and 1), or instead `albedo` (σs/σt, each channel in [0, 1]) and
//!   `sigma_t` (extinction) as Mitsuba gives them; either pair scaled by `scale` (default 1).
//! - `phase`: `isotropic` (the default) or `hg` (Henyey-Greenstein) with `g`, the mean
//!   cosine, in (-1, 1) (default 0).

use super::{choice, unique_name};
use crate::desc::MediumDesc;
use crate::params::{Result, Table};
use penumbra_core::Rgb;
use penumbra_render::media::{Homogeneous, Medium};
use penumbra_render::phase::{HenyeyGreenstein, Phase};

/// The kinds the native format reads so far.
const TYPES: [&str; 1] = ["homogeneous"];

pub fn read_all(tables: &[Table]) -> Result<Vec<MediumDesc>> {
    let mut out: Vec<MediumDesc> = Vec::new();
    for t in tables {
        let name = unique_name(t, "medium", out.iter().map(|m| &m.name))?;
        if let Some(v) = t.get("type") {
            choice(&v, "medium type", &TYPES, |s| TYPES.contains(&s).then_some(()))?;
        }
        let medium = Medium::Homogeneous(read_homogeneous(t)?);
        t.finish()?;
        out.push(MediumDesc {
            name,
            medium,
            location: Some(t.location()),
        });
    }
    Ok(out)
}

fn read_homogeneous(t: &Table) -> Result<Homogeneous> {
    let scale = t.f32_or("scale", 1.0)?;
    if !(scale >= 0.0 && scale.is_finite()) {
        return Err(t
            .require("scale")?
            .error("`scale` must be a finite number >= 0")
            .label("bad scale"));
    }
    let phase = read_phase(t)?;
    let albedo_form = t.get("albedo").is_some() || t.get("sigma_t").is_some();
    let coefficients_form = t.get("sigma_a").is_some() || t.get("sigma_s").is_some();
    if albedo_form && coefficients_form {
        return Err(t.error("a medium takes `sigma_a` and `sigma_s`, or `albedo` and `sigma_t`, not both"));
    }
    let finite = |key: &str, c: Rgb| -> Result<Rgb> {
        if c.is_finite() {
            Ok(c * scale)
        } else {
            Err(t.require(key)?.error("coefficients must be finite").label("not finite"))
        }
    };
    if albedo_form {
        let albedo = t.rgb_or("albedo", Rgb::splat(0.75))?;
        if albedo.max_component() > 1.0 {
            return Err(t
                .require("albedo")?
                .error("an albedo is at most 1 in each channel")
                .label("above 1"));
        }
        let sigma_t = finite("sigma_t", t.rgb_or("sigma_t", Rgb::WHITE)?)?;
        return Ok(Homogeneous::from_albedo(albedo, sigma_t, phase));
    }
    Ok(Homogeneous {
        sigma_a: finite("sigma_a", t.rgb_or("sigma_a", Rgb::BLACK)?)?,
        sigma_s: finite("sigma_s", t.rgb_or("sigma_s", Rgb::WHITE)?)?,
        phase,
    })
}

fn read_phase(t: &Table) -> Result<Phase> {
    let kind = match t.get("phase") {
        Some(v) => choice(&v, "phase function", &Phase::NAMES, |s| {
            Phase::NAMES.iter().position(|n| *n == s)
        })?,
        None => 0,
    };
    let g = t.f32_or("g", 0.0)?;
    if !(g > -1.0 && g < 1.0) {
        return Err(t.require("g")?.error("`g` must lie in (-1, 1)").label("out of range"));
    }
    Ok(match kind {
        0 => Phase::Isotropic,
        _ => Phase::HenyeyGreenstein(HenyeyGreenstein::new(g)),
    })
}

/// The medium named by `key` in `t`, as an index into `media`; `None` without the key.
pub fn reference(t: &Table, key: &str, media: &[MediumDesc]) -> Result<Option<u32>> {
    let Some(v) = t.get(key) else {
        return Ok(None);
    };
    let name = v.str()?;
    match media.iter().position(|m| m.name == name) {
        Some(i) => Ok(Some(i as u32)),
        None => Err(v
            .error(format!("no medium named `{name}`"))
            .label("unknown medium")
            .help(format!(
                "define it in a [[medium]] table; defined: {}",
                super::shape::names(media.iter().map(|m| &m.name))
            ))),
    }
}
