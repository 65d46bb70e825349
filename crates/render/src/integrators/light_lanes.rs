//! The light samples of a wavefront depth's shading points: for the kinds whose sampling
//! has a lane kernel (environment, point, spot, directional; `lights/lanes.rs`; untextured
//! triangles sampled by area, [`crate::lights::TriangleByArea`]), eight points at a time in
//! SIMD lanes ([`sample_li_lanes`]), other area lights one by one. Each
//! sample is what the light's scalar `sample_li` gives: that is the one-lane instance of
//! the same kernel.

use crate::lights::lanes::sample_li_lanes;
use crate::lights::{AreaSampling, Light, LightGather, LightSample};
use crate::Scene;
use glam::{Vec2, Vec3};

/// A shading point's light sample to take: the light picked, the point it is seen from,
/// the sample's two numbers.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightRequest {
    pub light: u32,
    pub p: Vec3,
    pub u: Vec2,
}

/// The samples of `requests`, in their order, into `out` (`one_by_one`: the batch's
/// scratch list of the requests no lane kernel takes).
pub(super) fn sample_lights(
    scene: &Scene,
    requests: &[LightRequest],
    sampling: AreaSampling,
    out: &mut Vec<Option<LightSample>>,
    one_by_one: &mut Vec<usize>,
) {
    out.clear();
    out.resize(requests.len(), None);
    let lights = scene.lights.lights();
    let kind = |r: &LightRequest| &lights[r.light as usize];
    // Each kind with a lane kernel, and whether its samples are delta ones.
    macro_rules! in_lanes_of {
        ($($variant:ident: $delta:expr),*) => {$(
            in_lanes(requests, out, $delta, |_, r| match kind(r) {
                Light::$variant(l) => Some(l.lanes()),
                _ => None,
            });
        )*};
    }
    in_lanes_of!(Environment: false, Point: true, Spot: true, Directional: true);
    // Untextured triangles sampled by area in lanes, other area lights one by one.
    one_by_one.clear();
    in_lanes(requests, out, false, |j, r| match kind(r) {
        Light::Area(a) => {
            let kernel = a.triangle_by_area(r.p, sampling);
            if kernel.is_none() {
                one_by_one.push(j);
            }
            kernel
        }
        _ => None,
    });
    for &j in one_by_one.iter() {
        let r = &requests[j];
        out[j] = kind(r).sample_li(r.p, r.u, sampling);
    }
}

/// The requests whose light `one` (given each request's index) gives a one-lane kernel
/// of kind `G` for, eight at a time (a last group's spare lanes repeat its last request;
/// their results are dropped).
fn in_lanes<G: LightGather>(
    requests: &[LightRequest],
    out: &mut [Option<LightSample>],
    delta: bool,
    mut one: impl FnMut(usize, &LightRequest) -> Option<G>,
) {
    let mut group = [0usize; 8];
    // Filled whole by a group's first kernel, so that no lane is ever unset.
    let mut kernels: Option<[G; 8]> = None;
    let mut n = 0;
    let mut flush = |group: &[usize; 8], kernels: &[G; 8], n: usize| {
        let at = |k: usize| k.min(n - 1);
        let lights = std::array::from_fn(|k| kernels[at(k)]);
        let p = std::array::from_fn(|k| requests[group[at(k)]].p);
        let u = std::array::from_fn(|k| requests[group[at(k)]].u);
        let samples = sample_li_lanes(&lights, &p, &u, delta);
        for (k, s) in samples.into_iter().take(n).enumerate() {
            out[group[k]] = s;
        }
    };
    for (j, r) in requests.iter().enumerate() {
        let Some(g) = one(j, r) else { continue };
        let ks = kernels.get_or_insert([g; 8]);
        (group[n], ks[n]) = (j, g);
        n += 1;
        if n == 8 {
            flush(&group, ks, n);
            n = 0;
        }
    }
    if let Some(ks) = kernels.filter(|_| n > 0) {
        flush(&group, &ks, n);
    }
}
