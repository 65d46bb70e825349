//! Mitsuba's render settings mapped onto Penumbra's: integrator, and sensor with its film,
//! filter and sampler. BSDFs and textures are in [`super::bsdfs`], emitters in
//! [`super::emitters`], shapes in [`super::shapes`].

use super::props::Props;
use super::{warn_unused, At, Reader, Result};
use crate::desc::{CameraDesc, CameraKind, RenderDesc};
use glam::Vec3;
use penumbra_core::SamplerKind;
use penumbra_render::cameras::FovAxis;
use penumbra_render::integrators::{IntegratorKind, LightSampling, MAX_DEPTH_LIMIT};
use penumbra_render::lights::LightSelection;
use penumbra_render::Filter;

/// Mitsuba's defaults: `hdrfilm` 768 x 576 with a Gaussian filter (standard deviation
/// 0.5, radius 2), `independent` sampler with 4 samples, `path` with no depth limit.
pub fn default_render() -> RenderDesc {
    RenderDesc {
        width: 768,
        height: 576,
        spp: 4,
        integrator: IntegratorKind::Path,
        max_depth: MAX_DEPTH_LIMIT,
        sampler: SamplerKind::Independent,
        filter: Filter::Gaussian {
            radius: 2.0,
            sigma: 0.5,
        },
        ..RenderDesc::default()
    }
}

/// A scene without a sensor is seen from the origin along +z, Mitsuba's default.
pub fn default_camera() -> CameraDesc {
    CameraDesc {
        kind: CameraKind::Perspective {
            fov: 39.597755,
            fov_axis: FovAxis::X,
            aperture_radius: 0.0,
            focus_distance: None,
        },
        position: Vec3::ZERO,
        target: Vec3::Z,
        up: Vec3::Y,
        mirrored: false,
        location: None,
    }
}

/// The type attribute of a plugin element.
fn kind(r: &Reader, at: At) -> Result<String> {
    r.require(at, "type")
}

/// A depth that Mitsuba writes as -1 for "no limit".
fn depth(r: &Reader, p: &Props, name: &str, default: u32) -> Result<u32> {
    match p.int(r, name)? {
        None => Ok(default),
        Some(-1) => Ok(MAX_DEPTH_LIMIT),
        Some(d) if (0..=MAX_DEPTH_LIMIT as i64).contains(&d) => Ok(d as u32),
        Some(d) => Err(p
            .get(name)
            .map(|v| {
                r.attr_error(
                    v,
                    "value",
                    format!("`{name}` must be -1 or from 0 to {MAX_DEPTH_LIMIT}, found {d}"),
                )
            })
            .expect("the parameter was just read")),
    }
}

pub fn integrator(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    let integrator = match kind.as_str() {
        "path" => IntegratorKind::Path,
        "direct" => IntegratorKind::Direct,
        // Mitsuba 0.6's bidirectional path tracer (Mitsuba 3 has none).
        "bdpt" => IntegratorKind::Bdpt,
        // Mitsuba 0.6's photon mappers.
        "sppm" => IntegratorKind::Sppm,
        "photonmapper" => IntegratorKind::Photon,
        // Mitsuba 3's volumetric path tracers (`volpathmis`: with spectral MIS, which
        // ours always does).
        "volpath" | "volpathmis" => IntegratorKind::Volpath,
        other => {
            let text = format!(
                "{}: integrator `{other}` is not supported: rendered with `path`",
                at.place()
            );
            r.warn_once(&format!("integrator {other}"), text);
            IntegratorKind::Path
        }
    };
    r.desc.render.integrator = integrator;
    let max_depth = depth(r, &p, "max_depth", MAX_DEPTH_LIMIT)?;
    let rr_depth = depth(r, &p, "rr_depth", penumbra_render::integrators::RR_DEPTH)?.max(1);
    if integrator == IntegratorKind::Direct {
        // Mitsuba's `direct`: `emitter_samples` shadow rays to emitters picked uniformly
        // and `bsdf_samples` BSDF samples, combined by the power heuristic when both are
        // taken.
        let count = |name: &str| -> Result<u32> {
            match p.int(r, name)? {
                None => Ok(1),
                Some(n) if (0..=1024).contains(&n) => Ok(n as u32),
                Some(n) => Err(r.attr_error(
                    p.get(name).expect("just read"),
                    "value",
                    format!("`{name}` must be from 0 to 1024, found {n}"),
                )),
            }
        };
        let (emitter, bsdf) = (count("emitter_samples")?, count("bsdf_samples")?);
        let d = &mut r.desc.render.direct;
        d.selection = LightSelection::Uniform;
        d.light_samples = emitter.max(1);
        d.sampling = match (emitter, bsdf) {
            (0, 0) => return Err(at.error("`emitter_samples` and `bsdf_samples` are both 0: nothing is sampled")),
            (0, _) => LightSampling::Bsdf,
            (_, 0) => LightSampling::SolidAngle,
            _ => LightSampling::Mis,
        };
        if bsdf > 1 && emitter > 0 {
            r.warn_once(
                "bsdf_samples",
                format!("{}: `bsdf_samples` above 1 is read as 1", at.place()),
            );
        }
    }
    if matches!(integrator, IntegratorKind::Sppm | IntegratorKind::Photon) {
        let count = |name: &str, default: u64| -> Result<u64> {
            Ok(p.int(r, name)?.map_or(default, |n| n.clamp(0, 1_000_000_000) as u64))
        };
        let o = penumbra_render::integrators::PhotonOptions {
            photons: count("photonCount", 0)?.max(count("globalPhotons", 0)?),
            caustic_photons: count("causticPhotons", 100_000)?,
            radius: p
                .float(r, "initialRadius")?
                .filter(|x| *x > 0.0 && x.is_finite())
                .unwrap_or(0.0),
            alpha: p.float(r, "alpha")?.map_or(2.0 / 3.0, |a| a.clamp(0.01, 1.0)),
            lookup: count("lookupSize", 100)?.clamp(1, 100_000) as u32,
            ..r.desc.render.photon
        };
        r.desc.render.photon = o;
    }
    let render = &mut r.desc.render;
    render.max_depth = max_depth;
    render.rr_depth = rr_depth;
    warn_unused(r, &p, &format!("integrator {kind}"));
    Ok(())
}

pub fn sensor(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    let thin_lens = match kind.as_str() {
        "perspective" => false,
        "thinlens" => true,
        other => {
            return Err(r.attr_error(
                at,
                "type",
                format!("sensor `{other}` is not supported (perspective or thinlens)"),
            ))
        }
    };
    let to_world = p.transform(r, "to_world")?;
    r.desc.camera_medium = super::media::sensor_medium(r, &p)?;
    let fov_axis = match p.string(r, "fov_axis")? {
        None => FovAxis::X,
        Some((s, v)) => match s.as_str() {
            "x" => FovAxis::X,
            "y" => FovAxis::Y,
            "smaller" => FovAxis::Smaller,
            "larger" => FovAxis::Larger,
            "diagonal" => {
                r.warn_once("fov_axis", format!("{}: fov_axis `diagonal` is read as `x`", v.place()));
                FovAxis::X
            }
            other => {
                return Err(r.attr_error(
                    v,
                    "value",
                    format!("unknown fov_axis `{other}` (x, y, smaller, larger)"),
                ))
            }
        },
    };
    let fov = match (p.float(r, "fov")?, p.string(r, "focal_length")?) {
        (Some(f), _) => f,
        (None, Some((s, v))) => {
            let mm: f32 = s
                .trim_end_matches("mm")
                .trim()
                .parse()
                .map_err(|_| r.attr_error(v, "value", "expected e.g. 50mm"))?;
            // The 36 mm width of a full-frame film, along x.
            2.0 * (18.0 / mm).atan().to_degrees()
        }
        (None, None) => 39.597755,
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(p.get("fov").map_or(at.error("fov must be in (0, 180)"), |v| {
            r.attr_error(v, "value", "fov must be in (0, 180) degrees")
        }));
    }
    let (aperture_radius, focus_distance) = if thin_lens {
        (p.float_or(r, "aperture_radius", 0.0)?, p.float(r, "focus_distance")?)
    } else {
        p.float(r, "focus_distance")?; // A pinhole has nothing to focus.
        (0.0, None)
    };
    p.float(r, "near_clip")?;
    p.float(r, "far_clip")?;
    // Mitsuba's camera looks along +z with +y up and x to the left (up x dir).
    let lens = CameraKind::Perspective {
        fov,
        fov_axis,
        aperture_radius,
        focus_distance,
    };
    r.desc.camera = CameraDesc::from_frame(lens, &to_world, -1.0, Some(at.location()));
    for film in p.nested("film") {
        self::film(r, film)?;
    }
    for sampler in p.nested("sampler") {
        self::sampler(r, sampler)?;
    }
    warn_unused(r, &p, &format!("sensor {kind}"));
    Ok(())
}

fn film(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    if kind != "hdrfilm" {
        r.warn_once("film", format!("{}: film `{kind}` is read as `hdrfilm`", at.place()));
    }
    let size = |name: &str, default: u32| -> Result<u32> {
        match p.int(r, name)? {
            None => Ok(default),
            Some(n) if (1..=1 << 16).contains(&n) => Ok(n as u32),
            Some(n) => Err(r.attr_error(
                p.get(name).expect("just read"),
                "value",
                format!("`{name}` must be from 1 to 65536, found {n}"),
            )),
        }
    };
    let (width, height) = (size("width", 768)?, size("height", 576)?);
    (r.desc.render.width, r.desc.render.height) = (width, height);
    for s in ["pixel_format", "component_format", "file_format"] {
        p.string(r, s)?; // Output formats follow the output file's extension.
    }
    for f in p.nested("rfilter") {
        let fp = r.props(f);
        let filter = match r.require(f, "type")?.as_str() {
            "gaussian" => {
                let sigma = fp.float_or(r, "stddev", 0.5)?;
                Filter::Gaussian {
                    radius: 4.0 * sigma,
                    sigma,
                }
            }
            "box" => Filter::Box { radius: 0.5 },
            "tent" => Filter::Tent {
                radius: fp.float_or(r, "radius", 1.0)?,
            },
            other => {
                r.warn_once(
                    "rfilter",
                    format!("{}: rfilter `{other}` is read as `gaussian`", f.place()),
                );
                Filter::Gaussian {
                    radius: 2.0,
                    sigma: 0.5,
                }
            }
        };
        r.desc.render.filter = filter;
        warn_unused(r, &fp, "rfilter");
    }
    warn_unused(r, &p, &format!("film {kind}"));
    Ok(())
}

fn sampler(r: &mut Reader, at: At) -> Result<()> {
    let p = r.props(at);
    let kind = kind(r, at)?;
    r.desc.render.sampler = match kind.as_str() {
        "independent" => SamplerKind::Independent,
        "stratified" | "multijitter" => SamplerKind::Stratified,
        "ldsampler" | "orthogonal" => SamplerKind::Sobol,
        other => {
            r.warn_once(
                "sampler",
                format!("{}: sampler `{other}` is read as `independent`", at.place()),
            );
            SamplerKind::Independent
        }
    };
    if let Some(n) = p.int(r, "sample_count")? {
        if !(1..=1 << 24).contains(&n) {
            let v = p.get("sample_count").expect("just read");
            return Err(r.attr_error(
                v,
                "value",
                format!("sample_count must be from 1 to 16777216, found {n}"),
            ));
        }
        r.desc.render.spp = n as u32;
    }
    p.int(r, "seed")?;
    p.bool_or(r, "jitter", true)?;
    warn_unused(r, &p, &format!("sampler {kind}"));
    Ok(())
}
