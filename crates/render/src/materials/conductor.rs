//! Metals, smooth or rough (GGX), rendered by [`crate::bsdfs::Conductor`]: `fresnel` (a
//! complex index `eta + i k`, default gold's; or Schlick's with `specular` as the
//! reflectance at normal incidence), a `specular` tint (default 1) and `roughness`
//! (default none: a mirror).

use super::{metal_ior, Roughness};
use crate::bsdfs::{BsdfKind, Conductor, MetalFresnel};
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct ConductorMaterial {
    pub fresnel: MetalFresnel,
    pub specular: Texture,
    pub roughness: Option<Roughness>,
}

impl Default for ConductorMaterial {
    fn default() -> Self {
        let (eta, k) = metal_ior("Au").expect("gold is a named metal");
        ConductorMaterial {
            fresnel: MetalFresnel::Complex { eta, k },
            specular: Texture::Constant(Rgb::WHITE),
            roughness: None,
        }
    }
}

impl ConductorMaterial {
    /// The BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> BsdfKind<'_> {
        BsdfKind::Conductor(Conductor {
            fresnel: self.fresnel,
            specular: self.specular.eval(uv),
            alpha: self.roughness.as_ref().and_then(|r| r.at(uv)),
        })
    }
}
