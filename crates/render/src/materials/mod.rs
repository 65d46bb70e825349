//! Materials: how a surface reflects and transmits light.
//!
//! Adding a material: a new file, one variant in [`Material`] and one arm in each match.

mod phong;

pub use phong::{Phong, SpecularRay};

/// Every material the renderer knows.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    Phong(Phong),
}
