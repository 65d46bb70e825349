//! A homogeneous medium: the same absorption σa, scattering σs and phase function
//! everywhere (Mitsuba's `homogeneous`, pbrt-v4's `homogeneous`). Scenes give σa and σs,
//! or an albedo σs/σt and σt (Mitsuba's form), each scaled by `scale`; the phase function
//! is isotropic by default.

use super::{MediumModel, MediumPoint, Segment};
use crate::phase::Phase;
use glam::Vec3;
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homogeneous {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    pub phase: Phase,
}

impl Default for Homogeneous {
    /// Mitsuba's default: albedo 0.75, σt 1, isotropic.
    fn default() -> Self {
        Homogeneous::from_albedo(Rgb::splat(0.75), Rgb::WHITE, Phase::Isotropic)
    }
}

impl Homogeneous {
    /// The medium of single-scattering `albedo` σs/σt and extinction `sigma_t`.
    pub fn from_albedo(albedo: Rgb, sigma_t: Rgb, phase: Phase) -> Self {
        let sigma_s = albedo * sigma_t;
        Homogeneous {
            sigma_a: (sigma_t - sigma_s).max(Rgb::BLACK),
            sigma_s,
            phase,
        }
    }

    /// σt = σa + σs.
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// σs/σt in each channel (0 where σt is).
    pub fn albedo(&self) -> Rgb {
        self.at(Vec3::ZERO).albedo()
    }
}

impl MediumModel for Homogeneous {
    fn at(&self, _: Vec3) -> MediumPoint {
        MediumPoint {
            sigma_a: self.sigma_a,
            sigma_s: self.sigma_s,
            phase: self.phase,
        }
    }

    fn segments(&self, _: Vec3, _: Vec3, t_max: f32, out: &mut Vec<Segment>) {
        out.clear();
        out.push(Segment {
            t0: 0.0,
            t1: t_max,
            sigma_maj: self.sigma_t(),
        });
    }

    fn is_homogeneous(&self) -> bool {
        true
    }
}
