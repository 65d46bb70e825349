//! `[[medium]]` tables: participating media that shapes (`interior`, `exterior`) and the
//! camera (`[camera] medium`) name.
//!
//! - `name`: unique.
//! - `type`: `homogeneous` (the default) or `grid`.
//! - `sigma_a` and `sigma_s`: absorption and scattering per unit length (colours or
//!   numbers; default 0 and 1), or instead `albedo` (σs/σt, each channel in [0, 1]) and
//!   `sigma_t` (extinction) as Mitsuba gives them; either pair scaled by `scale` (default 1).
//!   In a grid they are the coefficients where the density is 1.
//! - `phase`: `isotropic` (the default) or `hg` (Henyey-Greenstein) with `g`, the mean
//!   cosine, in (-1, 1) (default 0).
//! - A grid's densities: `file`, a Mitsuba `.vol` file of one channel (relative to the
//!   scene file), or `resolution = [nx, ny, nz]` and `density`, nx·ny·nz numbers, x
//!   fastest. They cover the unit cube, placed by `transform` (as a shape's), and are
//!   looked up trilinearly between cell centres.

use super::{choice, unique_name};
use crate::desc::MediumDesc;
use crate::formats::vol;
use crate::params::{Result, Table};
use glam::UVec3;
use penumbra_core::{Rgb, Transform};
use penumbra_render::media::{DensityGrid, GridMedium, Homogeneous, Medium};
use penumbra_render::phase::{HenyeyGreenstein, Phase};
use std::path::Path;
use std::sync::Arc;

/// The kinds the native format reads.
const TYPES: [&str; 2] = ["homogeneous", "grid"];

pub fn read_all(tables: &[Table]) -> Result<Vec<MediumDesc>> {
    let mut out: Vec<MediumDesc> = Vec::new();
    for t in tables {
        let name = unique_name(t, "medium", out.iter().map(|m| &m.name))?;
        let kind = match t.get("type") {
            Some(v) => choice(&v, "medium type", &TYPES, |s| TYPES.iter().position(|n| *n == s))?,
            None => 0,
        };
        let coefficients = read_homogeneous(t)?;
        let medium = match kind {
            0 => Medium::Homogeneous(coefficients),
            _ => Medium::Grid(read_grid(t, coefficients)?),
        };
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

/// A grid medium: its densities, placement and the coefficients where the density is 1.
fn read_grid(t: &Table, c: Homogeneous) -> Result<GridMedium> {
    let grid = match (t.get("file"), t.get("resolution")) {
        (Some(f), None) => {
            let base = t
                .location()
                .file
                .path
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default();
            let path = base.join(f.str()?);
            let vol = vol::read(&path).map_err(|e| f.error(e).label("bad grid file"))?;
            if vol.channels != 1 {
                return Err(f
                    .error(format!(
                        "{}: {} channels; a density grid has one",
                        path.display(),
                        vol.channels
                    ))
                    .label("not one channel"));
            }
            DensityGrid::new(vol.res, vol.values).map_err(|e| f.error(e).label("bad density"))?
        }
        (None, Some(r)) => {
            let n = r.numbers(3)?;
            let limit = 1.0..=vol::MAX_RES as f32;
            if !n.iter().all(|x| limit.contains(x) && x.fract() == 0.0) {
                return Err(r
                    .error(format!(
                        "a resolution is three whole numbers from 1 to {}",
                        vol::MAX_RES
                    ))
                    .label("bad resolution"));
            }
            let res = UVec3::new(n[0] as u32, n[1] as u32, n[2] as u32);
            let count = res.x as u64 * res.y as u64 * res.z as u64;
            let d = t.require("density")?;
            let items = d.array()?;
            if items.len() as u64 != count {
                return Err(d
                    .error(format!(
                        "a {}x{}x{} grid needs {count} densities, found {}",
                        res.x,
                        res.y,
                        res.z,
                        items.len()
                    ))
                    .label("wrong count"));
            }
            let values = items.iter().map(|v| v.f32()).collect::<Result<Vec<_>>>()?;
            DensityGrid::new(res, values).map_err(|e| d.error(e).label("bad density"))?
        }
        _ => return Err(t.error("a grid medium takes its densities from `file`, or from `resolution` and `density`")),
    };
    let to_world = match t.get("transform") {
        Some(v) => super::shape::transform(&v)?,
        None => Transform::IDENTITY,
    };
    Ok(GridMedium::new(
        Arc::new(grid),
        c.sigma_t(),
        c.albedo(),
        c.phase,
        to_world,
    ))
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
