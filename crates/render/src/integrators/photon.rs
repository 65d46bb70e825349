//! Jensen's two-pass photon mapping (Jensen 1996, "Global Illumination Using Photon
//! Maps"; Jensen 2001, "Realistic Image Synthesis Using Photon Mapping", chapter 9). First
//! pass: photons are traced from the lights into two maps, the global map (every photon at
//! a surface with a smooth part) and the caustic map (photons that reached such a surface
//! through delta bounces only, L S+ D). Second pass: the camera path goes through delta
//! bounces to a surface with a smooth part, and the radiance there is split into
//!
//! - emission, and direct lighting by light and BSDF sampling (weighted by the power
//!   heuristic): no photons;
//! - caustics: a density estimate of the caustic map;
//! - the rest of the indirect light: final gathering, BSDF-sampled rays whose first
//!   surface with a smooth part (after any delta bounces) gives a density estimate of the
//!   global map.
//!
//! Each density estimate sums the k - 1 nearest photons over the disc that reaches the
//! k-th, Σ f Φ / (π r² N_e), which is unbiased where the photon density is constant (the
//! k nearest over their own disc would be k/(k - 1) too bright); within a largest radius,
//! beyond which fewer are summed over that radius's disc. The estimate is consistent only
//! as the maps grow: it blurs detail smaller than the discs, unlike `sppm`.

use super::photons::{trace_photons, walk, Photon, PhotonMap, VisiblePoint};
use super::{Integrator, IntegratorOptions, RayCounts, Splat};
use crate::bsdfs::TransportMode;
use crate::interface::Progress;
use crate::Scene;
use penumbra_core::{PixelSampler, Ray, Rgb};
use std::sync::RwLock;

pub struct PhotonMapper {
    pub options: IntegratorOptions,
    /// Built by `prepare`, afresh for every render (a frame may change the lights).
    maps: RwLock<Option<Maps>>,
}

struct Map {
    map: PhotonMap,
    /// Photons emitted while the map was filled.
    emitted: u64,
    /// The largest lookup radius, squared.
    r2_max: f32,
}

struct Maps {
    global: Map,
    caustic: Map,
}

/// Photons emitted per batch while the maps fill.
const BATCH: u64 = 1 << 16;

/// The global map's size when the settings leave it to us.
pub const GLOBAL_PHOTONS: u64 = 200_000;

/// A map stops filling when, at the rate it has filled so far, it would take more than
/// this many emissions per photon wanted (a scene with no caustic paths never fills its
/// caustic map).
const EMISSION_CAP: u64 = 64;

impl PhotonMapper {
    pub fn new(options: IntegratorOptions) -> Self {
        PhotonMapper {
            options,
            maps: RwLock::new(None),
        }
    }

    /// The first pass: both maps, emitting batch after batch until each holds what was
    /// asked (or the cap is reached).
    fn build(&self, scene: &Scene, counts: &mut RayCounts) -> Maps {
        let o = &self.options.photon;
        let want = [
            if o.photons == 0 { GLOBAL_PHOTONS } else { o.photons },
            o.caustic_photons,
        ];
        let max_depth = self.options.max_depth as usize;
        // A photon of the global map is found by a gathering ray (at least two camera
        // segments before it), one of the caustic map at the camera path's end (one).
        let keep_global = |ph: &Photon| ph.segments as usize + 2 <= max_depth;
        let keep_caustic = |ph: &Photon| ph.caustic && (ph.segments as usize) < max_depth;
        let mut kept: [Vec<Photon>; 2] = [Vec::new(), Vec::new()];
        let mut emitted = [0u64; 2];
        let mut total = 0u64;
        let seed = self.options.seed ^ 0x9a07_0a11;
        // Whether map m still fills: short of its size, and not projected past the cap.
        let filling = |kept: &[Vec<Photon>; 2], m: usize, total: u64| {
            let (have, want) = (kept[m].len() as u64, want[m]);
            have < want && total as f64 * want as f64 / have.max(1) as f64 <= (EMISSION_CAP * want) as f64
        };
        while (0..2).any(|m| filling(&kept, m, total)) {
            let keep = |ph: &Photon| keep_global(ph) || keep_caustic(ph);
            let (photons, _) = trace_photons(
                scene,
                &self.options,
                (seed, total..total + BATCH),
                (max_depth.saturating_sub(1), usize::MAX),
                &keep,
                counts,
            );
            total += BATCH;
            for (m, keep) in [&keep_global as &dyn Fn(&Photon) -> bool, &keep_caustic]
                .iter()
                .enumerate()
            {
                if filling(&kept, m, total - BATCH) {
                    kept[m].extend(photons.iter().filter(|ph| keep(ph)));
                    emitted[m] = total;
                }
            }
        }
        let [global, caustic] = kept;
        let radius = if o.radius > 0.0 {
            o.radius
        } else {
            0.05 * 2.0 * scene.sphere.1
        };
        Maps {
            global: Map {
                map: PhotonMap::build(global),
                emitted: emitted[0],
                r2_max: radius * radius,
            },
            caustic: Map {
                map: PhotonMap::build(caustic),
                emitted: emitted[1],
                r2_max: (radius * 0.25).powi(2),
            },
        }
    }

    /// The radiance the photons of `map` bring to `vp` (without its weight): the k - 1
    /// nearest photons that make paths short enough, over the disc reaching the k-th.
    fn estimate(&self, map: &Map, vp: &VisiblePoint) -> Rgb {
        if map.map.is_empty() || map.emitted == 0 {
            return Rgb::BLACK;
        }
        let max_depth = self.options.max_depth as usize;
        let k = self.options.photon.lookup.max(1) as usize;
        let mut found = Vec::with_capacity(k + 1);
        let r_max = map.r2_max.sqrt();
        let keep = |ph: &Photon| ph.segments as usize + vp.segments <= max_depth && vp.same_surface(ph, r_max);
        let r2 = map.map.nearest(vp.p, k + 1, map.r2_max, keep, &mut found);
        if found.len() == k + 1 {
            found.pop();
        }
        let sum = found
            .iter()
            .fold(Rgb::BLACK, |s, &i| s + vp.photon_value(map.map.photon(i)));
        sum * (1.0 / (std::f32::consts::PI * r2 * map.emitted as f32))
    }
}

impl Integrator for PhotonMapper {
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        _: &mut Vec<Splat>,
    ) -> Rgb {
        let w = walk(scene, *ray, Rgb::WHITE, 0, &self.options, true, sampler, counts);
        let maps = self.maps.read().unwrap_or_else(|e| e.into_inner());
        let (Some(vp), Some(maps)) = (w.point, maps.as_ref()) else {
            return w.radiance;
        };
        let mut radiance = w.radiance + vp.beta * self.estimate(&maps.caustic, &vp);
        let gather = self.options.photon.gather.max(1);
        for _ in 0..gather {
            let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
            let Some(bs) = vp.bsdf.sample(vp.wo, u_lobe, u, TransportMode::Radiance) else {
                continue;
            };
            // Delta directions belong to the camera walk's other branch.
            if bs.delta {
                continue;
            }
            let wi = vp.frame.to_world(bs.wi);
            if (wi.dot(vp.ng) > 0.0) != (bs.wi.z * vp.wo.z > 0.0) {
                continue;
            }
            counts.secondary += 1;
            let beta = vp.beta * bs.weight * (1.0 / gather as f32);
            let ray = Ray::spawn(vp.p, vp.ng, wi);
            let g = walk(scene, ray, beta, vp.segments, &self.options, false, sampler, counts);
            if let Some(at) = g.point {
                radiance += at.beta * self.estimate(&maps.global, &at);
            }
        }
        radiance
    }

    fn prepare(&self, scene: &Scene, _: &dyn Progress) -> RayCounts {
        let mut counts = RayCounts::default();
        let maps = self.build(scene, &mut counts);
        *self.maps.write().unwrap_or_else(|e| e.into_inner()) = Some(maps);
        counts
    }

    fn report(&self) -> Vec<String> {
        let maps = self.maps.read().unwrap_or_else(|e| e.into_inner());
        let Some(m) = maps.as_ref() else {
            return Vec::new();
        };
        let mut lines = vec![format!(
            "photon: global map {} photons of {} emitted (lookup radius {:.3e}), caustic map {} of {}",
            m.global.map.len(),
            m.global.emitted,
            m.global.r2_max.sqrt(),
            m.caustic.map.len(),
            m.caustic.emitted
        )];
        let o = &self.options.photon;
        let want = if o.photons == 0 { GLOBAL_PHOTONS } else { o.photons };
        if (m.global.map.len() as u64) < want {
            lines.push(format!(
                "warning: photon: the global map holds {} photons of the {want} asked after {} emissions: little light reaches surfaces that can hold photons",
                m.global.map.len(),
                m.global.emitted
            ));
        }
        lines
    }
}
