//! The interfaces between the render driver and the integrators, in one place: what an
//! integrator is ([`Integrator`], [`PassIntegrator`]), what it reports ([`RayCounts`],
//! [`Progress`]) and how many camera rays it wants at a time ([`Integrator::batch_size`]).
//! The driver and every integrator import these; neither imports the other.

use crate::film::Splat;
use crate::filter::Filters;
use crate::{Film, Scene};
use penumbra_core::{PixelSampler, Ray, Rgb};

/// Receives progress reports from the worker threads.
pub trait Progress: Sync {
    /// `samples` more samples are done, for which `rays` rays were traced.
    fn advance(&self, samples: u64, rays: u64);
}

/// A progress sink that ignores reports.
impl Progress for () {
    fn advance(&self, _: u64, _: u64) {}
}

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub secondary: u64,
    pub shadow: u64,
    /// Hits with more distinct perfectly specular directions than
    /// [`crate::bsdfs::MAX_SPECULAR_RAYS`]: the weakest were dropped (reported as a note).
    pub specular_overflows: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.secondary + self.shadow
    }

    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.secondary += o.secondary;
        self.shadow += o.shadow;
        self.specular_overflows += o.specular_overflows;
    }
}

/// What an integrator supports beyond estimating pixels, declared by the integrator
/// itself: the command line asks for these instead of matching on integrator names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capabilities {
    /// What the integrator keeps outside the film that a resumed render would need
    /// (Markov chains, photon statistics, particles); `None`: the film's state alone
    /// continues the render (`--resume`, `--checkpoint` states).
    pub state: Option<&'static str>,
    /// Why it draws random numbers of its own instead of the pixel sampler's (`--sampler`
    /// does not apply); `None` when it uses the sampler.
    pub own_numbers: Option<&'static str>,
    /// Estimates each pixel by camera samples of its own, so that the first hit's albedo,
    /// normal and depth (`--aovs`) describe the samples the image averages.
    pub pixel_samples: bool,
    /// Adds what light paths bring to other pixels (splats) besides its own.
    pub splats: bool,
    /// Carries what it learnt from one frame of an animation to the next (`--frames`
    /// then keeps the one integrator for every frame).
    pub carries_frames: bool,
    /// Can keep an image per sampling strategy (`--debug-strategies`).
    pub strategy_images: bool,
    /// Renders participating media (the others render a scene as if its media were
    /// vacuum).
    pub media: bool,
    /// Renders spectrally when the scene asks (the others render its colours in RGB).
    pub spectral: bool,
}

impl Default for Capabilities {
    /// A pixel-sampling integrator without splats or state of its own.
    fn default() -> Self {
        Capabilities {
            state: None,
            own_numbers: None,
            pixel_samples: true,
            splats: false,
            carries_frames: false,
            strategy_images: false,
            media: false,
            spectral: false,
        }
    }
}

/// A radiance estimator for camera rays.
pub trait Integrator: Send + Sync {
    /// What it supports (see [`Capabilities`]).
    fn capabilities(&self) -> Capabilities {
        Capabilities::default()
    }

    /// Radiance arriving at the camera along `ray`, counting the rays traced in `counts`;
    /// what the sample adds to other pixels (light paths that reach the camera) goes to
    /// `splats` (see [`crate::film`]).
    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
    ) -> Rgb;

    /// [`Integrator::li`] for each of `rays` with its sampler, into `out`: the same values,
    /// computed together where the integrator gains by it.
    fn li_batch(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &mut [PixelSampler],
        out: &mut [Rgb],
        counts: &mut RayCounts,
        splats: &mut Vec<Splat>,
    ) {
        for ((ray, sampler), out) in rays.iter().zip(samplers).zip(out) {
            *out = self.li(scene, ray, sampler, counts, splats);
        }
    }

    /// For integrators that render whole passes themselves instead of a pixel's samples
    /// one by one (Metropolis light transport): that renderer.
    fn passes(&self) -> Option<&dyn PassIntegrator> {
        None
    }

    /// Work before the first sample (Metropolis's bootstrap, the photon maps); the rays
    /// traced. Renders call it once, before any sample.
    fn prepare(&self, _scene: &Scene, _progress: &dyn Progress) -> RayCounts {
        RayCounts::default()
    }

    /// Lines that describe the render so far (acceptance rates, photons), for the user.
    fn report(&self) -> Vec<String> {
        Vec::new()
    }

    /// How many camera rays [`Integrator::li_batch`] should get at a time (the driver's
    /// batch within a tile; the image does not depend on it).
    fn batch_size(&self) -> usize {
        256
    }
}

/// An integrator that renders the film a pass at a time (each pass worth one sample per
/// pixel), splatting wherever its paths land.
pub trait PassIntegrator: Sync {
    /// Adds pass `index` to `film` (splats weighted by `filter`), reporting progress;
    /// the rays traced.
    fn pass(&self, scene: &Scene, filter: &Filters, index: u32, film: &mut Film, progress: &dyn Progress) -> RayCounts;
}
