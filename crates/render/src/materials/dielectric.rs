//! Glass, water and other dielectric interfaces, smooth or rough, rendered by
//! [`crate::bsdfs::Dielectric`]: `eta` (interior over exterior index, default 1.5),
//! `reflectance` and `transmittance` tints (default 1) and `roughness` (default none).

use super::Roughness;
use crate::bsdfs::{BsdfKind, Dielectric};
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct DielectricMaterial {
    /// Interior over exterior index of refraction.
    pub eta: f32,
    pub reflectance: Texture,
    pub transmittance: Texture,
    pub roughness: Option<Roughness>,
}

impl Default for DielectricMaterial {
    fn default() -> Self {
        DielectricMaterial {
            eta: 1.5,
            reflectance: Texture::Constant(Rgb::WHITE),
            transmittance: Texture::Constant(Rgb::WHITE),
            roughness: None,
        }
    }
}

impl DielectricMaterial {
    /// The BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> BsdfKind<'_> {
        BsdfKind::Dielectric(Dielectric {
            eta: self.eta,
            reflectance: self.reflectance.eval(uv),
            transmittance: self.transmittance.eval(uv),
            alpha: self.roughness.as_ref().and_then(|r| r.at(uv)),
        })
    }
}
