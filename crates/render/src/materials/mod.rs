//! Materials: the scene's description of how a surface scatters light, with textures;
//! [`Material::bsdf`] turns one into the [`Bsdf`] at a surface point.
//!
//! Adding a material: a variant here and its arm in [`Material::bsdf`], with the BSDF in
//! its own file under `bsdfs/`.

mod metals;
mod phong;

pub use metals::{metal_ior, METALS};
pub use phong::Phong;

use crate::bsdfs::microfacet::Ggx;
use crate::bsdfs::{Blend, Bsdf, BsdfKind, Conductor, Dielectric, Diffuse, Plastic};
use crate::optics::fresnel_diffuse_reflectance;
use crate::Texture;
use glam::Vec2;
use penumbra_core::Rgb;

/// GGX roughness α along the tangent and bitangent (equal for an isotropic surface), as
/// textures (their red channel).
#[derive(Clone, Debug, PartialEq)]
pub struct Roughness {
    pub alpha_u: Texture,
    pub alpha_v: Texture,
}

impl Roughness {
    pub fn isotropic(alpha: f32) -> Self {
        Roughness {
            alpha_u: Texture::Constant(Rgb::splat(alpha)),
            alpha_v: Texture::Constant(Rgb::splat(alpha)),
        }
    }

    /// The distribution at `uv`; `None` when it is effectively smooth.
    fn at(&self, uv: Vec2) -> Option<Ggx> {
        Ggx::new(self.alpha_u.eval(uv).r, self.alpha_v.eval(uv).r)
    }
}

/// Every material the renderer knows.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// The classic ray-tracing material: diffuse, Phong glossy, mirror, glass.
    Phong(Phong),
    /// Lambertian reflection.
    Diffuse { reflectance: Texture },
    /// A metal of complex index `eta + i k`, smooth or rough (GGX).
    Conductor {
        eta: Rgb,
        k: Rgb,
        specular: Texture,
        roughness: Option<Roughness>,
    },
    /// Glass and other dielectric interfaces, smooth or rough.
    Dielectric {
        /// Interior over exterior index of refraction.
        eta: f32,
        reflectance: Texture,
        transmittance: Texture,
        roughness: Option<Roughness>,
    },
    /// A diffuse base under a dielectric coating, smooth or rough (isotropic).
    Plastic {
        diffuse: Texture,
        specular: Texture,
        eta: f32,
        /// The coating's diffuse internal reflectance, from [`Material::plastic`].
        fdr_int: f32,
        roughness: Option<Roughness>,
    },
    /// (1 - weight) a + weight b.
    Blend {
        a: Box<Material>,
        b: Box<Material>,
        weight: Texture,
    },
    /// The material on both sides of the surface (the others reflect on the side the
    /// shading normal faces only, except `Phong` and `Dielectric`, which have two sides).
    TwoSided(Box<Material>),
}

impl Material {
    /// A plastic material, its coating's internal reflectance worked out.
    pub fn plastic(diffuse: Texture, specular: Texture, eta: f32, roughness: Option<Roughness>) -> Self {
        Material::Plastic {
            diffuse,
            specular,
            eta,
            fdr_int: fresnel_diffuse_reflectance(1.0 / eta),
            roughness,
        }
    }

    /// The BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> Bsdf<'_> {
        let rough = |r: &Option<Roughness>| r.as_ref().and_then(|r| r.at(uv));
        let kind = match self {
            Material::Phong(m) => {
                return Bsdf {
                    kind: BsdfKind::Phong(m.bsdf(uv)),
                    two_sided: false,
                }
            }
            Material::Diffuse { reflectance } => BsdfKind::Diffuse(Diffuse {
                reflectance: reflectance.eval(uv),
            }),
            Material::Conductor {
                eta,
                k,
                specular,
                roughness,
            } => BsdfKind::Conductor(Conductor {
                eta: *eta,
                k: *k,
                specular: specular.eval(uv),
                alpha: rough(roughness),
            }),
            Material::Dielectric {
                eta,
                reflectance,
                transmittance,
                roughness,
            } => BsdfKind::Dielectric(Dielectric {
                eta: *eta,
                reflectance: reflectance.eval(uv),
                transmittance: transmittance.eval(uv),
                alpha: rough(roughness),
            }),
            Material::Plastic {
                diffuse,
                specular,
                eta,
                fdr_int,
                roughness,
            } => {
                let (diffuse, specular) = (diffuse.eval(uv), specular.eval(uv));
                let (d, s) = (diffuse.mean(), specular.mean());
                BsdfKind::Plastic(Plastic {
                    diffuse,
                    specular,
                    eta: *eta,
                    fdr_int: *fdr_int,
                    specular_weight: if d + s > 0.0 { s / (d + s) } else { 0.0 },
                    alpha: rough(roughness).map(|g| Ggx { ax: g.ax, ay: g.ax }),
                })
            }
            Material::Blend { a, b, weight } => BsdfKind::Blend(Blend {
                a,
                b,
                weight: weight.eval(uv).r.clamp(0.0, 1.0),
                uv,
            }),
            Material::TwoSided(inner) => {
                return Bsdf {
                    two_sided: true,
                    ..inner.bsdf(uv)
                }
            }
        };
        Bsdf::one_sided(kind)
    }
}
