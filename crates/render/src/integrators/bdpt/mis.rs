//! The multiple-importance weight of a bidirectional strategy (Veach 1997 section 10.3.4;
//! pbrt-v4 section 13.4.4): the path made by connecting light prefix `s` with camera prefix
//! `t` could have been made by every other split of its vertices; the weight is the power
//! heuristic (β = 2) over all of them, computed from ratios of neighbouring strategies'
//! densities, each ratio p_{i+1}/p_i being one vertex's reverse over forward area density.
//! A strategy that would have to hit a delta vertex (a specular bounce, a point light, a
//! camera that cannot be reached) is impossible and left out.

use super::vertex::Vertex;
use crate::bsdfs::TransportMode;
use crate::Scene;

/// A density of zero means "not sampled by a density" (delta events): it is taken as one,
/// since the same delta factor then appears in both densities of a ratio.
fn remap0(p: f32) -> f32 {
    if p != 0.0 {
        p
    } else {
        1.0
    }
}

/// The weight of strategy (s, t) for the path `light[..s]` + `camera[..t]`, where
/// `sampled` replaces `light[0]` (s = 1) or `camera[0]` (t = 1) when the connection drew
/// that endpoint anew.
pub(super) fn weight(
    scene: &Scene,
    light: &[Vertex],
    camera: &[Vertex],
    sampled: Option<&Vertex>,
    s: usize,
    t: usize,
) -> f32 {
    if s + t == 2 {
        return 1.0;
    }
    // The subpaths' vertices, with the endpoint the connection drew in place.
    let light_at = |k: usize| match sampled {
        Some(v) if s == 1 && k == 0 => *v,
        _ => light[k],
    };
    let camera_at = |k: usize| match sampled {
        Some(v) if t == 1 && k == 0 => *v,
        _ => camera[k],
    };
    let qs = s.checked_sub(1).map(light_at);
    let pt = camera_at(t - 1);
    let qs_minus = s.checked_sub(2).map(light_at);
    let pt_minus = t.checked_sub(2).map(camera_at);

    // The densities of the four vertices about the connection, for this strategy.
    let pt_rev = match &qs {
        Some(qs) => qs.pdf(scene, qs_minus.as_ref(), &pt, TransportMode::Importance),
        None => pt_minus.as_ref().map_or(0.0, |pm| pt.pdf_light_origin(scene, pm)),
    };
    let pt_minus_rev = pt_minus.as_ref().map(|pm| match &qs {
        Some(qs) => pt.pdf(scene, Some(qs), pm, TransportMode::Importance),
        None => pt.pdf_light(scene, pm),
    });
    let qs_rev = qs
        .as_ref()
        .map(|qs| pt.pdf(scene, pt_minus.as_ref(), qs, TransportMode::Radiance));
    let qs_minus_rev = qs_minus.as_ref().map(|qm| {
        qs.as_ref()
            .expect("qs")
            .pdf(scene, Some(&pt), qm, TransportMode::Radiance)
    });

    let mut sum = 0.0;
    // Strategies with fewer camera vertices: camera vertex i becomes the light path's end.
    let mut ri = 1.0;
    for i in (1..t).rev() {
        // (i >= 1: never the camera vertex a connection drew.)
        let v = &camera[i];
        let rev = if i == t - 1 {
            pt_rev
        } else if i + 2 == t {
            pt_minus_rev.unwrap_or(v.pdf_rev)
        } else {
            v.pdf_rev
        };
        ri *= remap0(rev) / remap0(v.pdf_fwd);
        let delta = v.delta && i != t - 1;
        let delta_before = camera[i - 1].delta;
        if !delta && !delta_before {
            sum += ri * ri;
        }
    }
    // Strategies with fewer light vertices: light vertex i becomes the camera path's end.
    let mut ri = 1.0;
    for i in (0..s).rev() {
        let v = match sampled {
            Some(v) if s == 1 => v,
            _ => &light[i],
        };
        let rev = if i == s - 1 {
            qs_rev.unwrap_or(v.pdf_rev)
        } else if i + 2 == s {
            qs_minus_rev.unwrap_or(v.pdf_rev)
        } else {
            v.pdf_rev
        };
        ri *= remap0(rev) / remap0(v.pdf_fwd);
        let delta = v.delta && i != s - 1;
        let delta_before = if i > 0 {
            light[i - 1].delta
        } else {
            v.light(scene).is_some_and(|(_, l)| l.is_delta())
        };
        if !delta && !delta_before {
            sum += ri * ri;
        }
    }
    1.0 / (1.0 + sum)
}
