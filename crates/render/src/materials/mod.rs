//! Materials: the scene's description of how a surface scatters light, with textures;
//! [`Material::bsdf`] turns one into the [`Bsdf`] at a surface point.
//!
//! Adding a material: its file here with a parameters struct (each field with its default
//! in `Default`, so that a new parameter breaks no constructor) and its `bsdf`, a variant in
//! [`Material`] and its arm in [`Material::bsdf`]; the BSDF in its own file under `bsdfs/`.

mod coated;
mod conductor;
mod dielectric;
mod diffuse;
mod metals;
mod phong;
mod plastic;

pub use coated::{Coated, CoatedBase};
pub use conductor::ConductorMaterial;
pub use dielectric::DielectricMaterial;
pub use diffuse::DiffuseMaterial;
pub use metals::{metal_ior, METALS};
pub use phong::Phong;
pub use plastic::PlasticMaterial;

use crate::bsdfs::microfacet::Ggx;
use crate::bsdfs::{Blend, Bsdf, BsdfKind};
use crate::Texture;
use glam::{Vec2, Vec3};
use penumbra_core::{Frame, Rgb};
use penumbra_geometry::SurfaceHit;

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
    Diffuse(DiffuseMaterial),
    /// A metal, smooth or rough (GGX).
    Conductor(ConductorMaterial),
    /// Glass and other dielectric interfaces, smooth or rough.
    Dielectric(DielectricMaterial),
    /// A diffuse base under a dielectric coating, smooth or rough (isotropic).
    Plastic(PlasticMaterial),
    /// A dielectric coating over a diffuse or metal base (pbrt-v4's coated materials).
    Coated(Coated),
    /// (1 - weight) a + weight b.
    Blend {
        a: Box<Material>,
        b: Box<Material>,
        weight: Texture,
    },
    /// The material on both sides of the surface (the others reflect on the side the
    /// shading normal faces only, except `Phong` and `Dielectric`, which have two sides).
    TwoSided(Box<Material>),
    /// `inner` with its shading normal taken from a tangent-space normal map: the texel
    /// (r, g, b), linear, is the normal 2 (r, g, b) − 1 in the frame of the tangent ∂p/∂u,
    /// the bitangent and the surface's shading normal (Mitsuba's `normalmap`).
    NormalMapped { map: Texture, inner: Box<Material> },
}

/// The deepest a material may nest blends, two-sided and normal-mapped wrappers: each
/// level costs a recursion per BSDF call, and no real scene comes near it.
pub const MAX_NESTING: usize = 32;

impl Material {
    /// How deep blends and wrappers nest in this material (1 for a plain one).
    pub fn nesting(&self) -> usize {
        match self {
            Material::Blend { a, b, .. } => 1 + a.nesting().max(b.nesting()),
            Material::TwoSided(inner) | Material::NormalMapped { inner, .. } => 1 + inner.nesting(),
            _ => 1,
        }
    }

    /// A plastic material (see [`PlasticMaterial::new`]).
    pub fn plastic(diffuse: Texture, specular: Texture, eta: f32, roughness: Option<Roughness>) -> Self {
        Material::Plastic(PlasticMaterial::new(diffuse, specular, eta, roughness))
    }

    /// The shading frame at `s`: the shading normal with the tangent ∂p/∂u, or the normal
    /// a normal map gives (ignored where the texel points below the surface). Only the
    /// outermost material's map counts: a blend's parts keep the surface's normal.
    pub fn shading_frame(&self, s: &SurfaceHit) -> Frame {
        let frame = Frame::from_normal_tangent(s.ns, s.dpdu);
        let Material::NormalMapped { map, .. } = self else {
            return frame;
        };
        let c = map.eval(s.uv);
        let local = Vec3::new(2.0 * c.r - 1.0, 2.0 * c.g - 1.0, 2.0 * c.b - 1.0);
        match frame.to_world(local).try_normalize() {
            Some(n) if local.z > 0.0 => Frame::from_normal_tangent(n, frame.s),
            _ => frame,
        }
    }

    /// The BSDF at texture coordinates `uv`.
    pub fn bsdf(&self, uv: Vec2) -> Bsdf<'_> {
        let kind = match self {
            Material::Phong(m) => {
                return Bsdf {
                    kind: BsdfKind::Phong(m.bsdf(uv)),
                    two_sided: false,
                }
            }
            Material::Diffuse(m) => m.bsdf(uv),
            Material::Conductor(m) => m.bsdf(uv),
            Material::Dielectric(m) => m.bsdf(uv),
            Material::Plastic(m) => m.bsdf(uv),
            Material::Blend { a, b, weight } => BsdfKind::Blend(Blend {
                a,
                b,
                weight: weight.eval(uv).r.clamp(0.0, 1.0),
                uv,
            }),
            Material::Coated(m) => return m.bsdf(uv),
            Material::NormalMapped { inner, .. } => return inner.bsdf(uv),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn surface() -> SurfaceHit {
        SurfaceHit {
            p: Vec3::ZERO,
            ng: Vec3::Z,
            ns: Vec3::Z,
            uv: Vec2::ZERO,
            dpdu: Vec3::new(3.0, 0.0, 0.5),
            object: 0,
            triangle: 0,
        }
    }

    #[test]
    fn the_shading_frame_follows_the_tangent_and_the_normal_map() {
        let plain = Material::Diffuse(DiffuseMaterial {
            reflectance: Texture::Constant(Rgb::splat(0.5)),
        });
        let f = plain.shading_frame(&surface());
        assert!((f.s - Vec3::X).length() < 1e-6 && f.n == Vec3::Z && (f.t - Vec3::Y).length() < 1e-6);
        // A map encoding the normal tilted 30 degrees towards the tangent.
        let a = 30f32.to_radians();
        let encode = |n: Vec3| Rgb::new(0.5 * n.x + 0.5, 0.5 * n.y + 0.5, 0.5 * n.z + 0.5);
        let mapped = |n: Vec3| Material::NormalMapped {
            map: Texture::Constant(encode(n)),
            inner: Box::new(plain.clone()),
        };
        let tilted = Vec3::new(a.sin(), 0.0, a.cos());
        let f = mapped(tilted).shading_frame(&surface());
        assert!((f.n - tilted).length() < 1e-5, "{}", f.n);
        assert!(
            f.s.dot(f.n).abs() < 1e-6 && f.s.y.abs() < 1e-6 && f.s.x > 0.0,
            "{}",
            f.s
        );
        // A texel pointing below the surface is ignored.
        let f = mapped(Vec3::new(0.0, 0.6, -0.8)).shading_frame(&surface());
        assert_eq!(f.n, Vec3::Z);
        // The BSDF is the inner material's.
        assert!(matches!(mapped(tilted).bsdf(Vec2::ZERO).kind, BsdfKind::Diffuse(_)));
    }
}
