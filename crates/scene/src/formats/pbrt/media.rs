//! pbrt-v4's participating media: `MakeNamedMedium "name" "string type" "homogeneous"`
//! (`sigma_a`, `sigma_s`, `scale`, `g`; each coefficient 1 by default, as pbrt-v4's), the
//! graphics state's `MediumInterface "inside" "outside"` (an empty name: vacuum) that every
//! shape made after it bounds, and the camera's medium (the interface's outside medium when
//! `Camera` comes). Other medium types (`uniformgrid`, `rgbgrid`, `cloud`, `nanovdb`) are
//! not read yet: a warning, and a reference to one is vacuum.

use super::objects::{color, unused};
use super::params::{ColorKind, Params};
use super::Reader;
use crate::desc::MediumDesc;
use crate::{Location, SceneError};
use penumbra_core::Rgb;
use penumbra_render::media::{Homogeneous, Medium, MediumInterface};
use penumbra_render::phase::{HenyeyGreenstein, Phase};

type Result<T> = std::result::Result<T, SceneError>;

/// `MakeNamedMedium name params`.
pub(super) fn make_named(r: &mut Reader, name: String, p: &Params, here: Location) -> Result<()> {
    let kind = p
        .string("type")?
        .ok_or_else(|| SceneError::at(here.clone(), "MakeNamedMedium needs a \"string type\""))?;
    if kind != "homogeneous" {
        r.warn(
            &format!("medium {kind}"),
            format!("{here}: medium `{kind}` is not supported yet (homogeneous is): `{name}` is vacuum"),
        );
        r.media.insert(name, None);
        return Ok(());
    }
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
            here,
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
    unused(r, p, &format!("medium {kind}"), &here);
    let index = r.desc.media.len() as u32;
    r.desc.media.push(MediumDesc {
        name: name.clone(),
        medium: Medium::Homogeneous(Homogeneous {
            sigma_a,
            sigma_s,
            phase,
        }),
        location: Some(here),
    });
    r.media.insert(name, Some(index));
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
