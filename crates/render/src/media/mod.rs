//! Participating media: what fills the space between surfaces (fog, smoke, the inside of
//! a cloud or of a glass of milk), as absorption σa, scattering σs and a phase function
//! per point, and the majorant σ_maj >= σt = σa + σs that free-flight sampling tracks
//! against (delta tracking; the null-scattering formulation of Miller, Georgiev and
//! Jarosz, "A null-scattering path integral formulation of light transport", SIGGRAPH
//! 2019, as pbrt-v4's `volpath` uses it).
//!
//! Media are attached to surfaces ([`MediumInterface`]: the medium inside and the one
//! outside a shape) and to the camera; a ray keeps the medium it is in until it crosses a
//! surface that names another.
//!
//! Adding a medium: a new file whose type answers [`MediumModel`], and one line in the
//! `medium_kinds!` registry below.

mod grid;
mod homogeneous;
mod tracker;

pub use grid::{DensityGrid, GridMedium};
pub use homogeneous::Homogeneous;
pub use tracker::{attenuation, attenuation_in, Step, Tracker};

use crate::phase::Phase;
use glam::Vec3;
use penumbra_core::Rgb;

/// The coefficients of a medium at one point (per unit length, per RGB channel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumPoint {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    pub phase: Phase,
}

impl MediumPoint {
    /// The extinction σt = σa + σs.
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// The single-scattering albedo σs/σt per channel (0 where σt is), at most 1.
    pub fn albedo(&self) -> Rgb {
        let t = self.sigma_t();
        let ratio = |s: f32, t: f32| if t > 0.0 { (s / t).min(1.0) } else { 0.0 };
        Rgb::new(
            ratio(self.sigma_s.r, t.r),
            ratio(self.sigma_s.g, t.g),
            ratio(self.sigma_s.b, t.b),
        )
    }
}

/// A stretch `[t0, t1)` of a ray (unit direction) over which the majorant is constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub t0: f32,
    pub t1: f32,
    pub sigma_maj: Rgb,
}

/// What every medium answers; each kind's file implements it.
pub trait MediumModel {
    /// The coefficients at `p`.
    fn at(&self, p: Vec3) -> MediumPoint;
    /// The majorant segments along the ray from `origin` in the unit direction `dir` over
    /// `[0, t_max)`, in order, into `out` (cleared first). A homogeneous medium has one.
    fn segments(&self, origin: Vec3, dir: Vec3, t_max: f32, out: &mut Vec<Segment>);
    /// Whether σt is the same everywhere (the majorant is then exact: no null collisions).
    fn is_homogeneous(&self) -> bool;
}

macro_rules! medium_kinds {
    ($($variant:ident($ty:ty) = $name:literal),* $(,)?) => {
        /// Every medium the renderer knows (a closed set: the per-collision calls are
        /// statically dispatched).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Medium {
            $($variant($ty)),*
        }

        impl Medium {
            /// The name of each kind, as scenes and messages spell it.
            pub const NAMES: [&'static str; [$($name),*].len()] = [$($name),*];

            fn model(&self) -> &dyn MediumModel {
                match self {
                    $(Medium::$variant(m) => m),*
                }
            }
        }
    };
}

medium_kinds! {
    Homogeneous(Homogeneous) = "homogeneous",
    Grid(GridMedium) = "grid",
}

impl Medium {
    /// See [`MediumModel::at`].
    pub fn at(&self, p: Vec3) -> MediumPoint {
        self.model().at(p)
    }

    /// See [`MediumModel::segments`].
    pub fn segments(&self, origin: Vec3, dir: Vec3, t_max: f32, out: &mut Vec<Segment>) {
        self.model().segments(origin, dir, t_max, out)
    }

    /// See [`MediumModel::is_homogeneous`].
    pub fn is_homogeneous(&self) -> bool {
        self.model().is_homogeneous()
    }

    /// What the medium is and the memory its tables take, for the render's report (e.g.
    /// "grid 40x40x40, 250 KiB + 16 KiB of majorants").
    pub fn summary(&self) -> String {
        match self {
            Medium::Homogeneous(_) => "homogeneous".into(),
            Medium::Grid(g) => {
                let r = g.density.res;
                format!(
                    "grid {}x{}x{}, {} KiB + {} KiB of majorants",
                    r.x,
                    r.y,
                    r.z,
                    (4 * g.density.values.len()).div_ceil(1024),
                    g.majorant_bytes().div_ceil(1024)
                )
            }
        }
    }
}

/// The media on the two sides of a surface: `inside` behind its geometric normal,
/// `outside` in front of it (`None`: vacuum). Mitsuba's `interior`/`exterior`, pbrt-v4's
/// `MediumInterface "inside" "outside"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumInterface {
    pub inside: Option<u32>,
    pub outside: Option<u32>,
}

impl MediumInterface {
    /// The medium a ray leaving the surface (geometric normal `ng`) along `dir` enters.
    pub fn towards(&self, ng: Vec3, dir: Vec3) -> Option<u32> {
        if ng.dot(dir) > 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

/// The RGB channel `i` (0 red, 1 green, 2 blue) of `c`.
#[inline]
pub fn channel(c: Rgb, i: usize) -> f32 {
    c.to_array()[i]
}
