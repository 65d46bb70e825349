//! Integrators: estimate the radiance arriving along a camera ray.
//!
//! Integrators are the one open family (a trait object); each is a file here, one variant
//! in [`IntegratorKind`] and one arm in [`IntegratorKind::create`].

mod bdpt;
mod bsdf_lanes;
mod diffuse_lanes;
mod direct;
mod env;
mod light_lanes;
mod mlt;
mod nee;
mod path;
pub(crate) mod path_diffuse;
mod photon;
mod photons;
mod sppm;
mod volpath;
mod whitted;

pub use crate::mis::MisHeuristic;
pub use bdpt::{strategy_layer, Bdpt};
pub use direct::{Direct, DirectOptions, LightSampling};
pub use env::{EnvDirect, EnvOptions, EnvSampling};
pub use mlt::{Mlt, MltOptions};
pub use path::{PathTracer, BATCH, RR_DEPTH};
pub use photon::PhotonMapper;
pub use photons::{Photon, PhotonMap, PhotonOptions};
pub use sppm::Sppm;
pub use volpath::VolPath;
pub use whitted::Whitted;

use crate::bsdfs::TransportMode;
pub use crate::film::Splat;
pub use crate::interface::{Integrator, PassIntegrator, RayCounts};
use crate::lights::LightSample;

use glam::Vec3;
use nee::Shading;
use penumbra_core::{Ray, Rgb};

/// The largest `max_depth` a scene may ask for: recursion deeper than this could exhaust a
/// worker thread's stack.
pub const MAX_DEPTH_LIMIT: u32 = 256;

/// Settings shared by the integrators.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegratorOptions {
    /// Maximum number of bounces after the camera ray.
    pub max_depth: u32,
    /// Rays whose accumulated weight falls below this are not traced.
    pub min_weight: f32,
    /// The path depth (segments) from which `path` plays Russian roulette (Mitsuba's
    /// `rr_depth`); at `max_depth` or above, never.
    pub rr_depth: u32,
    /// Settings of the `direct` integrator.
    pub direct: DirectOptions,
    /// `bdpt` also splats every strategy's contribution, weighted and not, to layers of
    /// their own ([`strategy_layer`]).
    pub debug_strategies: bool,
    /// Settings of `mlt`.
    pub mlt: MltOptions,
    /// Settings of `sppm` and `photon`.
    pub photon: PhotonOptions,
    /// Settings of `env`.
    pub env: EnvOptions,
    /// The render's seed (for integrators with random streams of their own: `mlt`).
    pub seed: u64,
}

impl Default for IntegratorOptions {
    fn default() -> Self {
        IntegratorOptions {
            max_depth: 5,
            min_weight: 1e-3,
            rr_depth: RR_DEPTH,
            direct: DirectOptions::default(),
            debug_strategies: false,
            mlt: MltOptions::default(),
            photon: PhotonOptions::default(),
            env: EnvOptions::default(),
            seed: 0,
        }
    }
}

/// The registry of integrators: one line per kind (variant, name, and how it is made from
/// the options `o`; the first is the default) generates [`IntegratorKind`], its [`IntegratorKind::NAMES`],
/// [`IntegratorKind::from_name`] and [`IntegratorKind::create`]. Adding an integrator: its
/// file, implementing [`Integrator`], and one line here.
macro_rules! integrator_kinds {
    ($o:ident; $default:ident = $default_name:literal => $default_make:expr, $($variant:ident = $name:literal => $make:expr),* $(,)?) => {
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub enum IntegratorKind {
            #[default]
            $default,
            $($variant),*
        }

        impl IntegratorKind {
            /// Every kind's name, in the order of the variants.
            pub const NAMES: [&'static str; 1 + [$($name),*].len()] = [$default_name, $($name),*];

            pub fn from_name(name: &str) -> Option<Self> {
                match name {
                    $default_name => Some(IntegratorKind::$default),
                    $($name => Some(IntegratorKind::$variant),)*
                    _ => None,
                }
            }

            pub fn create(self, $o: IntegratorOptions) -> Box<dyn Integrator> {
                match self {
                    IntegratorKind::$default => Box::new($default_make),
                    $(IntegratorKind::$variant => Box::new($make)),*
                }
            }
        }
    };
}

integrator_kinds! { o;
    Whitted = "whitted" => Whitted { options: o },
    Direct = "direct" => Direct { options: o },
    Path = "path" => PathTracer::new(o),
    Bdpt = "bdpt" => Bdpt { options: o },
    Mlt = "mlt" => Mlt::new(o),
    Sppm = "sppm" => Sppm::new(o),
    Photon = "photon" => PhotonMapper::new(o),
    Env = "env" => EnvDirect::new(o.env, o.seed),
    Volpath = "volpath" => VolPath::new(o),
}

/// The extent of a shadow ray whose direction reaches the light's point: all of it but the
/// last [`penumbra_core::ray::SHADOW_EPSILON`], so the light's own surface is not a blocker.
pub(super) const SHADOW_T_MAX: f32 = 1.0 - penumbra_core::ray::SHADOW_EPSILON;

/// The shadow ray from `origin` (a surface point already pushed off its surface) towards the
/// light of `ls`, and its `t_max`, which stops it just short of the light.
pub(crate) fn shadow_ray(origin: Vec3, ls: &LightSample) -> (Ray, f32) {
    if ls.dist.is_finite() {
        let target = origin + ls.wi * ls.dist;
        (Ray::new(origin, target - origin), SHADOW_T_MAX)
    } else {
        (Ray::new(origin, ls.wi), f32::INFINITY)
    }
}

/// The radiance the perfectly specular rays at `sh` bring back towards the viewer (mirror
/// reflection, Fresnel-weighted reflection and refraction), each traced by `trace(ray,
/// accumulated weight, counts)`; nothing beyond `max_depth` bounces or below `min_weight`.
fn specular_bounces(
    options: &IntegratorOptions,
    sh: &Shading,
    depth: u32,
    beta: Rgb,
    counts: &mut RayCounts,
    mut trace: impl FnMut(&Ray, Rgb, &mut RayCounts) -> Rgb,
) -> Rgb {
    let mut radiance = Rgb::BLACK;
    if depth >= options.max_depth {
        return radiance;
    }
    let s = &sh.it.surface;
    let rays = sh.bsdf.specular_rays(sh.wo, TransportMode::Radiance);
    counts.specular_overflows += (rays.dropped() > 0.0) as u64;
    for r in rays.as_slice() {
        let weight = beta * r.weight;
        if weight.max_component() < options.min_weight {
            continue;
        }
        counts.secondary += 1;
        let wi = sh.frame.to_world(r.wi);
        radiance += r.weight * trace(&Ray::spawn(s.p, s.ng, wi), weight, counts);
    }
    radiance
}
