//! Coated materials, pbrt-v4's `coateddiffuse` and `coatedconductor`: a dielectric coating
//! over a diffuse or metal base, with a thin medium between, rendered by the [`Layered`]
//! BSDF (see `bsdfs/layered.rs` for the method). The fields carry pbrt-v4's parameters;
//! each defaults to pbrt-v4's value:
//!
//! | field | pbrt-v4 names | default |
//! |---|---|---|
//! | `base` | `reflectance` (diffuse); `conductor.eta`, `conductor.k`, `conductor.reflectance`, `conductor.roughness` | diffuse 0.5 |
//! | `eta` | `eta`, `interface.eta` | 1.5 |
//! | `roughness` | `roughness`, `interface.roughness` (and the `u`/`v` forms) | 0 (smooth) |
//! | `thickness` | `thickness` | 0.01 |
//! | `albedo`, `g` | `albedo`, `g` (the medium's single-scattering albedo and asymmetry) | 0, 0 |
//! | `max_depth`, `samples` | `maxdepth`, `nsamples` | 10, 1 |
//!
//! Both sides of the surface are coated (pbrt-v4's coated BSDFs are two-sided).

use super::Roughness;
use crate::bsdfs::{Bsdf, BsdfKind, Conductor, Dielectric, Diffuse, LayerBase, Layered, MetalFresnel};
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

/// What is under the coating.
#[derive(Clone, Debug, PartialEq)]
pub enum CoatedBase {
    Diffuse {
        reflectance: Texture,
    },
    /// A metal; its complex index is given against vacuum, as pbrt-v4's parameters are,
    /// and divided by the coating's at the surface.
    Conductor {
        fresnel: MetalFresnel,
        specular: Texture,
        roughness: Option<Roughness>,
    },
}

/// A coated material's parameters (see the module documentation for names and defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct Coated {
    pub base: CoatedBase,
    /// Coating over exterior index of refraction.
    pub eta: f32,
    /// The coating's GGX roughness; `None` for a smooth coating.
    pub roughness: Option<Roughness>,
    /// The medium's thickness, in units of its mean free path.
    pub thickness: f32,
    pub albedo: Texture,
    pub g: f32,
    pub max_depth: u32,
    pub samples: u32,
}

impl Default for Coated {
    fn default() -> Self {
        Coated {
            base: CoatedBase::Diffuse {
                reflectance: Texture::Constant(Rgb::splat(0.5)),
            },
            eta: 1.5,
            roughness: None,
            thickness: 0.01,
            albedo: Texture::Constant(Rgb::BLACK),
            g: 0.0,
            max_depth: 10,
            samples: 1,
        }
    }
}

impl Coated {
    /// The layered BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> Bsdf<'_> {
        // An index of 0 (or not a number) means none: index-matched, as pbrt-v4 takes it.
        let eta = if self.eta > 0.0 && self.eta.is_finite() {
            self.eta
        } else {
            1.0
        };
        let base = match &self.base {
            CoatedBase::Diffuse { reflectance } => LayerBase::Diffuse(Diffuse {
                reflectance: reflectance.eval(uv),
            }),
            CoatedBase::Conductor {
                fresnel,
                specular,
                roughness,
            } => LayerBase::Conductor(Conductor {
                fresnel: match *fresnel {
                    MetalFresnel::Complex { eta: n, k } => MetalFresnel::Complex {
                        eta: n / eta,
                        k: k / eta,
                    },
                    schlick => schlick,
                },
                specular: specular.eval(uv),
                alpha: roughness.as_ref().and_then(|r| r.at(uv)),
            }),
        };
        let layered = Layered {
            coat: Dielectric {
                eta,
                reflectance: Rgb::WHITE,
                transmittance: Rgb::WHITE,
                alpha: self.roughness.as_ref().and_then(|r| r.at(uv)),
            },
            base,
            thickness: self.thickness.max(f32::MIN_POSITIVE),
            albedo: self.albedo.eval(uv),
            g: self.g,
            max_depth: self.max_depth,
            samples: self.samples.max(1),
        };
        Bsdf {
            kind: BsdfKind::Layered(layered),
            two_sided: true,
        }
    }
}
