//! Mitsuba 3's participating media: `<medium type="homogeneous|heterogeneous">` (`albedo`,
//! `sigma_t`, `scale`, a nested `<phase type="isotropic|hg">`), defined at the top level
//! with an `id` or nested where it is used: in a shape as `interior`/`exterior` (or a
//! `<ref name=...>` to one), in the sensor (the medium the camera is in). `albedo` and
//! `sigma_t` are colours, numbers or `<volume type="constvolume">`; a heterogeneous
//! medium's `sigma_t` is also a `<volume type="gridvolume">`: a one-channel `.vol` file
//! over the unit cube placed by its `to_world` (or over the file's own box with
//! `use_grid_bbox`), looked up trilinearly. Grids of albedo are not read (an error).

use super::props::Props;
use super::{warn_unused, At, Reader, Result};
use crate::desc::MediumDesc;
use crate::formats::vol;
use penumbra_core::{Rgb, Transform};
use penumbra_render::media::{DensityGrid, GridMedium, Homogeneous, Medium, MediumInterface};
use penumbra_render::phase::{HenyeyGreenstein, Phase};
use std::sync::Arc;

/// The medium `at` describes, added to the scene (under its `id`, when it has one); its
/// index, or `None` for a kind not read (warned).
pub fn medium(r: &mut Reader, at: At) -> Result<Option<u32>> {
    let p = r.props(at);
    let kind = r.require(at, "type")?;
    if kind != "homogeneous" && kind != "heterogeneous" {
        return Err(r.attr_error(
            at,
            "type",
            format!("medium `{kind}` is not supported (homogeneous and heterogeneous are)"),
        ));
    }
    let albedo = match coefficient(r, &p, "albedo", 0.75)? {
        Volume::Constant(c) => c,
        Volume::Grid(..) => {
            return Err(p
                .get("albedo")
                .map_or(at, |v| v)
                .error("a grid of albedo is not supported (a constant albedo is)"))
        }
    };
    let sigma_t = coefficient(r, &p, "sigma_t", 1.0)?;
    let scale = p.float_or(r, "scale", 1.0)?;
    let finite = match &sigma_t {
        Volume::Constant(c) => c.is_finite(),
        Volume::Grid(..) => true,
    };
    if albedo.max_component() > 1.0 || !(scale >= 0.0 && scale.is_finite()) || !finite {
        return Err(at.error(format!(
            "medium: albedo must lie in [0, 1], sigma_t be finite and scale finite and >= 0 \
             (albedo {albedo:?}, sigma_t {sigma_t:?}, scale {scale})"
        )));
    }
    let phase = match p.nested("phase").first() {
        Some(&ph) => phase(r, ph)?,
        None => Phase::Isotropic,
    };
    for ignored in ["sample_emitters", "has_spectral_extinction"] {
        p.get(ignored);
    }
    warn_unused(r, &p, &format!("medium {kind}"));
    let medium = match sigma_t {
        Volume::Constant(c) => Medium::Homogeneous(Homogeneous::from_albedo(albedo, c * scale, phase)),
        Volume::Grid(grid, to_world) => Medium::Grid(GridMedium::new(grid, Rgb::splat(scale), albedo, phase, to_world)),
    };
    let index = r.desc.media.len() as u32;
    let id = r.attr(at, "id")?;
    r.desc.media.push(MediumDesc {
        name: id.clone().unwrap_or_else(|| format!("medium at {}", at.place())),
        medium,
        location: Some(at.location()),
    });
    if let Some(id) = id {
        r.media.insert(id, index);
    }
    Ok(Some(index))
}

/// A medium parameter's value: constant, or a grid over the unit cube placed in the world.
#[derive(Debug)]
enum Volume {
    Constant(Rgb),
    Grid(Arc<DensityGrid>, Transform),
}

/// A medium's parameter: a colour, a number, a `<volume type="constvolume">` or a
/// `<volume type="gridvolume">`.
fn coefficient(r: &mut Reader, p: &Props, name: &str, default: f32) -> Result<Volume> {
    let Some(v) = p.get(name).filter(|v| v.tag() == "volume") else {
        return p.color_or(r, name, default).map(Volume::Constant);
    };
    let vp = r.props(v);
    let volume = match r.require(v, "type")?.as_str() {
        "constvolume" => Volume::Constant(vp.color_or(r, "value", 1.0)?),
        "gridvolume" => grid_volume(r, v, &vp)?,
        other => {
            return Err(r.attr_error(
                v,
                "type",
                format!("volume `{other}` is not supported (constvolume and gridvolume are)"),
            ))
        }
    };
    warn_unused(r, &vp, "volume");
    Ok(volume)
}

/// A `gridvolume`: its `.vol` file (one channel) and where its unit cube lies.
fn grid_volume(r: &mut Reader, v: At, vp: &Props) -> Result<Volume> {
    let (file, file_at) = vp
        .string(r, "filename")?
        .ok_or_else(|| v.error("a gridvolume needs a `filename`"))?;
    let path = r.resolve(v, &file);
    let fail = |e: String| file_at.error(e);
    let vol = vol::read(&path).map_err(fail)?;
    if vol.channels != 1 {
        return Err(fail(format!(
            "{}: {} channels; a density grid has one",
            path.display(),
            vol.channels
        )));
    }
    let grid = DensityGrid::new(vol.res, vol.values).map_err(|e| fail(format!("{}: {e}", path.display())))?;
    if let Some((filter, at)) = vp.string(r, "filter_type")? {
        if filter != "trilinear" {
            return Err(at.error(format!("filter_type `{filter}` is not supported (trilinear is)")));
        }
    }
    let mut to_world = vp.transform(r, "to_world")?;
    if vp.bool_or(r, "use_grid_bbox", false)? {
        let [lo, hi] = vol.bbox;
        let scale = Transform::scale(hi - lo).ok_or_else(|| fail(format!("{}: its box is empty", path.display())))?;
        to_world = scale.then(Transform::translate(lo)).then(to_world);
    }
    for ignored in ["raw", "accel", "wrap_mode"] {
        vp.get(ignored);
    }
    Ok(Volume::Grid(Arc::new(grid), to_world))
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
