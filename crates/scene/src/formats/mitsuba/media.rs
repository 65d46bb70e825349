//! Mitsuba 3's participating media: `<medium type="homogeneous">` (`albedo`, `sigma_t`,
//! `scale`, a nested `<phase type="isotropic|hg">`), defined at the top level with an `id`
//! or nested where it is used: in a shape as `interior`/`exterior` (or a `<ref name=...>`
//! to one), in the sensor (the medium the camera is in). `albedo` and `sigma_t` are
//! colours, numbers or `<volume type="constvolume">`. Heterogeneous media are not read
//! yet: a warning, and the shape bounds nothing.

use super::props::Props;
use super::{warn_unused, At, Reader, Result};
use crate::desc::MediumDesc;
use penumbra_core::Rgb;
use penumbra_render::media::{Homogeneous, Medium, MediumInterface};
use penumbra_render::phase::{HenyeyGreenstein, Phase};

/// The medium `at` describes, added to the scene (under its `id`, when it has one); its
/// index, or `None` for a kind not read (warned).
pub fn medium(r: &mut Reader, at: At) -> Result<Option<u32>> {
    let p = r.props(at);
    let kind = r.require(at, "type")?;
    if kind != "homogeneous" {
        let text = format!(
            "{}: medium `{kind}` is not supported yet (homogeneous is): the scene renders without it",
            at.place()
        );
        r.warn_once(&format!("medium {kind}"), text);
        return Ok(None);
    }
    let albedo = coefficient(r, &p, "albedo", 0.75)?;
    let sigma_t = coefficient(r, &p, "sigma_t", 1.0)?;
    let scale = p.float_or(r, "scale", 1.0)?;
    if albedo.max_component() > 1.0 || !(scale >= 0.0 && scale.is_finite()) || !sigma_t.is_finite() {
        return Err(at.error(format!(
            "medium: albedo must lie in [0, 1], sigma_t be finite and scale finite and >= 0 \
             (albedo {albedo:?}, sigma_t {sigma_t:?}, scale {scale})"
        )));
    }
    let phase = match p.nested("phase").first() {
        Some(&ph) => phase(r, ph)?,
        None => Phase::Isotropic,
    };
    p.get("sample_emitters");
    warn_unused(r, &p, "medium homogeneous");
    let index = r.desc.media.len() as u32;
    let id = r.attr(at, "id")?;
    r.desc.media.push(MediumDesc {
        name: id.clone().unwrap_or_else(|| format!("medium at {}", at.place())),
        medium: Medium::Homogeneous(Homogeneous::from_albedo(albedo, sigma_t * scale, phase)),
        location: Some(at.location()),
    });
    if let Some(id) = id {
        r.media.insert(id, index);
    }
    Ok(Some(index))
}

/// A medium's colour parameter: a colour, a number or a `<volume type="constvolume">`.
fn coefficient(r: &mut Reader, p: &Props, name: &str, default: f32) -> Result<Rgb> {
    match p.get(name) {
        Some(v) if v.tag() == "volume" => {
            let vp = r.props(v);
            match r.require(v, "type")?.as_str() {
                "constvolume" => {
                    let c = vp.color_or(r, "value", 1.0)?;
                    warn_unused(r, &vp, "volume constvolume");
                    Ok(c)
                }
                other => Err(v.error(format!(
                    "volume `{other}` is not supported yet for `{name}` (constvolume is)"
                ))),
            }
        }
        _ => p.color_or(r, name, default),
    }
}

fn phase(r: &mut Reader, at: At) -> Result<Phase> {
    let p = r.props(at);
    let phase = match r.require(at, "type")?.as_str() {
        "isotropic" => Phase::Isotropic,
        "hg" => {
            let g = p.float_or(r, "g", 0.8)?;
            if !(g > -1.0 && g < 1.0) {
                return Err(at.error(format!("phase hg: `g` must lie in (-1, 1), found {g}")));
            }
            Phase::HenyeyGreenstein(HenyeyGreenstein::new(g))
        }
        other => return Err(at.error(format!("phase `{other}` is not supported (isotropic or hg)"))),
    };
    warn_unused(r, &p, "phase");
    Ok(phase)
}

/// The medium a shape or sensor names `name` (`<medium name=...>` nested, or `<ref
/// name=... id=...>`).
fn named(r: &mut Reader, p: &Props, name: &str) -> Result<Option<u32>> {
    let Some(v) = p.get(name) else {
        return Ok(None);
    };
    match v.tag() {
        "medium" => medium(r, v),
        "ref" => reference(r, v).map(Some),
        other => Err(v.error(format!(
            "`{name}` must be a <medium> or a <ref> to one, found <{other}>"
        ))),
    }
}

fn reference(r: &mut Reader, v: At) -> Result<u32> {
    let id = r.require(v, "id")?;
    r.media
        .get(&id)
        .copied()
        .ok_or_else(|| r.attr_error(v, "id", format!("no medium with id `{id}` is defined before this")))
}

/// The media inside and outside a shape, if it names any.
pub fn shape_media(r: &mut Reader, p: &Props) -> Result<Option<MediumInterface>> {
    let inside = named(r, p, "interior")?;
    let outside = named(r, p, "exterior")?;
    Ok((inside.is_some() || outside.is_some()).then_some(MediumInterface { inside, outside }))
}

/// The medium the sensor is in: a nested `<medium>` or a `<ref>` to one, with any name.
pub fn sensor_medium(r: &mut Reader, p: &Props) -> Result<Option<u32>> {
    if let Some(&m) = p.nested("medium").first() {
        return medium(r, m);
    }
    for v in p.nested("ref") {
        let id = r.require(v, "id")?;
        if let Some(&m) = r.media.get(&id) {
            return Ok(Some(m));
        }
    }
    for name in ["medium", "exterior"] {
        if let Some(m) = named(r, p, name)? {
            return Ok(Some(m));
        }
    }
    Ok(None)
}
