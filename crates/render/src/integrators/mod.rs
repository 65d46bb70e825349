//! Integrators: estimate the radiance arriving along a camera ray.
//!
//! Integrators are the one open family (a trait object); each is a file here, one variant
//! in [`IntegratorKind`] and one arm in [`IntegratorKind::create`].

mod whitted;

pub use whitted::Whitted;

use crate::Scene;
use penumbra_core::{PixelSampler, Ray, Rgb};

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub secondary: u64,
    pub shadow: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.secondary + self.shadow
    }

    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.secondary += o.secondary;
        self.shadow += o.shadow;
    }
}

/// A radiance estimator for camera rays.
pub trait Integrator: Send + Sync {
    /// Radiance arriving at the camera along `ray`, counting the rays traced in `counts`.
    fn li(&self, scene: &Scene, ray: &Ray, sampler: &mut PixelSampler, counts: &mut RayCounts) -> Rgb;
}

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
}

impl Default for IntegratorOptions {
    fn default() -> Self {
        IntegratorOptions {
            max_depth: 5,
            min_weight: 1e-3,
        }
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    #[default]
    Whitted,
}

impl IntegratorKind {
    pub const NAMES: [&'static str; 1] = ["whitted"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "whitted" => Some(IntegratorKind::Whitted),
            _ => None,
        }
    }

    pub fn create(self, options: IntegratorOptions) -> Box<dyn Integrator> {
        match self {
            IntegratorKind::Whitted => Box::new(Whitted { options }),
        }
    }
}
