//! pbrt-v4's participating media: `MakeNamedMedium "name" "string type" "homogeneous"`
//! (`sigma_a`, `sigma_s`, `scale`, `g`; each coefficient 1 by default, as pbrt-v4's), the
//! graphics state's `MediumInterface "inside" "outside"` (an empty name: vacuum) that every
//! shape made after it bounds, and the camera's medium (the interface's outside medium when
//! `Camera` comes); `uniformgrid` density grids. Other medium types (`rgbgrid`, `cloud`,
//! `nanovdb`) are not read yet: a warning, and a reference to one is vacuum.

use super::objects::{color, unused};
use super::params::{ColorKind, Params};
use super::Reader;
use crate::desc::MediumDesc;
use crate::{Location, SceneError};
use glam::{UVec3, Vec3};
use penumbra_core::Rgb;
use penumbra_core::Transform;
use penumbra_render::media::{DensityGrid, GridMedium, Homogeneous, Medium, MediumInterface};
use penumbra_render::phase::{HenyeyGreenstein, Phase};
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// `MakeNamedMedium name params`.
pub(super) fn make_named(r: &mut Reader, name: String, p: &Params, here: Location) -> Result<()> {
    let kind = p
        .string("type")?
        .ok_or_else(|| SceneError::at(here.clone(), "MakeNamedMedium needs a \"string type\""))?;
    if kind == "uniformgrid" {
        return uniform_grid(r, name, p, here);
    }
    if kind != "homogeneous" {
        r.warn(
            &format!("medium {kind}"),
            format!("{here}: medium `{kind}` is not supported yet (homogeneous is): `{name}` is vacuum"),
        );
        r.media.insert(name, None);
        return Ok(());
    }
    let medium = coefficients(r, &name, p, &here)?;
    unused(r, p, "medium homogeneous", &here);
    add(r, name, Medium::Homogeneous(medium), here);
    Ok(())
}

/// σa and σs (`sigma_a`, `sigma_s`, each 1 by default, times `scale`) and the phase
/// function (`g`) of a `MakeNamedMedium`; presets and emission are warned and ignored.
fn coefficients(r: &mut Reader, name: &str, p: &Params, here: &Location) -> Result<Homogeneous> {
    if p.string("preset")?.is_some() {
        r.warn(
            "medium preset",
            format!("{here}: named medium presets are not supported: sigma_a and sigma_s are read instead"),
        );
    }
    let scale = p.float("scale", 1.0)?;
    let coefficient =
        |key: &str| -> Result<Rgb> { Ok(color(p, key, ColorKind::Albedo)?.unwrap_or(Rgb::WHITE) * scale) };
    let (sigma_a, sigma_s) = (coefficient("sigma_a")?, coefficient("sigma_s")?);
    let g = p.float("g", 0.0)?;
    let valid = scale >= 0.0 && scale.is_finite() && g > -1.0 && g < 1.0 && (sigma_a + sigma_s).is_finite();
    if !valid {
        return Err(SceneError::at(
            here.clone(),
            format!("medium `{name}`: scale must be finite and >= 0, g in (-1, 1), the coefficients finite"),
        ));
    }
    for ignored in ["Le", "Lescale", "temperature"] {
        if p.list.iter().any(|x| x.name == ignored) {
            r.warn(
                "medium emission",
                format!("{here}: emitting media are not supported: `{ignored}` is ignored"),
            );
            p.float(ignored, 0.0).ok();
        }
    }
    let phase = if g == 0.0 {
        Phase::Isotropic
    } else {
        Phase::HenyeyGreenstein(HenyeyGreenstein::new(g))
    };
    Ok(Homogeneous {
        sigma_a,
        sigma_s,
        phase,
    })
}

/// Adds `medium` to the scene under `name`.
fn add(r: &mut Reader, name: String, medium: Medium, here: Location) {
    let index = r.desc.media.len() as u32;
    r.desc.media.push(MediumDesc {
        name: name.clone(),
        medium,
        location: Some(here),
    });
    r.media.insert(name, Some(index));
}

/// pbrt-v4's `uniformgrid`: `density` (`nx` x `ny` x `nz` numbers, x fastest) over the box
/// `p0`-`p1` placed by the transform in force, times σa + σs (`sigma_a`, `sigma_s`,
/// `scale`), with the albedo σs/(σa + σs) and Henyey-Greenstein `g`. (pbrt fades the
/// density to zero over the outer half voxel; we hold the edge values there, as Mitsuba's
/// grids do.)
fn uniform_grid(r: &mut Reader, name: String, p: &Params, here: Location) -> Result<()> {
    let fail = |message: String| SceneError::at(here.clone(), format!("medium `{name}`: {message}"));
    let mut res = [0u32; 3];
    for (n, key) in res.iter_mut().zip(["nx", "ny", "nz"]) {
        let v = p.int(key, 1)?;
        if !(1..=4096).contains(&v) {
            return Err(fail(format!("`{key}` must be from 1 to 4096, found {v}")));
        }
        *n = v as u32;
    }
    let density = p
        .floats("density")?
        .ok_or_else(|| fail("a uniformgrid needs \"float density\"".into()))?;
    let grid = DensityGrid::new(UVec3::from(res), density).map_err(fail)?;
    let corner = |key: &str, default: Vec3| -> Result<Vec3> {
        Ok(match p.points(key, 3)?.as_deref() {
            Some([c]) => Vec3::new(c[0], c[1], c[2]),
            Some(_) => return Err(fail(format!("`{key}` takes one point"))),
            None => default,
        })
    };
    let (p0, p1) = (corner("p0", Vec3::ZERO)?, corner("p1", Vec3::ONE)?);
    if !(p1.cmpgt(p0).all() && (p1 - p0).is_finite()) {
        return Err(fail(format!("the box p0 {p0} to p1 {p1} is empty")));
    }
    let c = coefficients(r, &name, p, &here)?;
    let to_world = Transform::scale(p1 - p0)
        .ok_or_else(|| fail("the box is degenerate".into()))?
        .then(Transform::translate(p0))
        .then(r.state.ctm);
    unused(r, p, "medium uniformgrid", &here);
    let medium = Medium::Grid(GridMedium::new(
        Arc::new(grid),
        c.sigma_t(),
        c.albedo(),
        c.phase,
        to_world,
    ));
    add(r, name, medium, here);
    Ok(())
}

/// The medium named `name` ("" is vacuum), which `MakeNamedMedium` made before.
pub(super) fn named(r: &Reader, name: &str, here: &Location) -> Result<Option<u32>> {
    if name.is_empty() {
        return Ok(None);
    }
    r.media.get(name).copied().ok_or_else(|| {
        SceneError::at(
            here.clone(),
            format!("no medium is named `{name}` (MakeNamedMedium comes first)"),
        )
    })
}

/// The media a shape made now bounds: `None` where inside and outside are the same (no
/// boundary: rays keep their medium, as in pbrt-v4).
pub(super) fn of_shape(inside: Option<u32>, outside: Option<u32>) -> Option<MediumInterface> {
    (inside != outside).then_some(MediumInterface { inside, outside })
}
