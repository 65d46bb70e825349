//! Penumbra rendering: materials, lights, cameras, film, integrators and the driver that
//! renders a [`Scene`] tile by tile in parallel.

pub mod bsdfs;
pub mod cameras;
pub mod driver;
pub mod film;
pub mod filter;
pub mod integrators;
pub mod interface;
pub mod lights;
pub mod materials;
pub mod media;
pub mod mis;
pub mod optics;
pub mod phase;
mod scene;
pub mod spectral;
#[cfg(test)]
mod test_payload;
pub mod texture;

pub use cameras::Camera;
pub use driver::{render, RenderOptions, RenderResult, RenderStats};
pub use film::Film;
pub use filter::Filter;
pub use integrators::{Integrator, IntegratorKind, RayCounts};
pub use interface::Progress;
pub use lights::Light;
pub use materials::Material;
pub use scene::{Interaction, Scene};
pub use texture::Texture;
