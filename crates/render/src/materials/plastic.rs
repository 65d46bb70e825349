//! Plastic: a diffuse base under a smooth or rough dielectric coating (Mitsuba 3's
//! `plastic` and `roughplastic`), rendered by [`crate::bsdfs::Plastic`]: `diffuse` (texture,
//! default 0.5), `specular` tint on the coating (default 1), `eta` (default 1.49, Mitsuba's
//! polypropylene) and `roughness` (isotropic; default none). [`PlasticMaterial::new`] works
//! out the coating's tables from `eta` and a constant roughness.

use super::Roughness;
use crate::bsdfs::microfacet::Ggx;
use crate::bsdfs::{BsdfKind, Coating, Plastic};
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct PlasticMaterial {
    pub diffuse: Texture,
    pub specular: Texture,
    pub eta: f32,
    /// The coating's internal reflectance and transmittance, from [`PlasticMaterial::new`].
    pub coating: Coating,
    pub roughness: Option<Roughness>,
}

impl Default for PlasticMaterial {
    fn default() -> Self {
        PlasticMaterial::new(
            Texture::Constant(Rgb::splat(0.5)),
            Texture::Constant(Rgb::WHITE),
            1.49,
            None,
        )
    }
}

impl PlasticMaterial {
    /// A plastic material, its coating's transmittance and internal reflectance worked
    /// out: the rough ones for a constant roughness, else the smooth ones (a textured
    /// roughness has no one table).
    pub fn new(diffuse: Texture, specular: Texture, eta: f32, roughness: Option<Roughness>) -> Self {
        let constant = roughness
            .as_ref()
            .filter(|r| matches!(r.alpha_u, Texture::Constant(_)) && matches!(r.alpha_v, Texture::Constant(_)));
        let coating = match constant.and_then(|r| r.at(Vec2::ZERO)) {
            Some(g) => Coating::rough(eta, Ggx { ax: g.ax, ay: g.ax }),
            None => Coating::smooth(eta),
        };
        PlasticMaterial {
            diffuse,
            specular,
            eta,
            coating,
            roughness,
        }
    }

    /// The BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> BsdfKind<'_> {
        let (diffuse, specular) = (self.diffuse.eval(uv), self.specular.eval(uv));
        let (d, s) = (diffuse.mean(), specular.mean());
        BsdfKind::Plastic(Plastic {
            diffuse,
            specular,
            eta: self.eta,
            coating: &self.coating,
            specular_weight: if d + s > 0.0 { s / (d + s) } else { 0.0 },
            alpha: self
                .roughness
                .as_ref()
                .and_then(|r| r.at(uv))
                .map(|g| Ggx { ax: g.ax, ay: g.ax }),
        })
    }
}
