//! The Lambertian material: `reflectance` (texture, default 0.5), rendered by
//! [`crate::bsdfs::Diffuse`].

use crate::bsdfs::{BsdfKind, Diffuse};
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct DiffuseMaterial {
    pub reflectance: Texture,
}

impl Default for DiffuseMaterial {
    fn default() -> Self {
        DiffuseMaterial {
            reflectance: Texture::Constant(Rgb::splat(0.5)),
        }
    }
}

impl DiffuseMaterial {
    /// The BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> BsdfKind<'_> {
        BsdfKind::Diffuse(Diffuse {
            reflectance: self.reflectance.eval(uv),
        })
    }
}
