//! Penumbra scenes: the format-neutral [`SceneDesc`], the readers that produce it, the
//! builder that turns it into a renderable [`penumbra_render::Scene`], and image output.
//!
//! Readers never build renderer internals: they produce a description, validated, with
//! source locations so that every error names the file, line and column of its cause.

mod build;
pub mod desc;
mod emitters;
mod error;
pub mod formats;
pub mod image_input;
pub mod image_io;
pub mod octahedral;
mod params;

pub use build::build_scene;
pub use desc::SceneDesc;
pub use error::{Location, SceneError, SourceFile};
pub use formats::{read_scene, read_scene_with};
