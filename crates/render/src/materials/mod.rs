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
mod metal_spectra;
mod metals;
mod phong;
mod plastic;

pub use coated::{Coated, CoatedBase};
pub use conductor::ConductorMaterial;
pub use dielectric::DielectricMaterial;
pub use diffuse::DiffuseMaterial;
pub use metals::{metal_ior, metal_spectra, METALS};
pub use phong::Phong;
pub use plastic::PlasticMaterial;

use crate::bsdfs::microfacet::Ggx;
use crate::bsdfs::{Blend, Bsdf, BsdfKind};
use crate::Texture;
use glam::Vec2;
use penumbra_core::frame::Basis;
use penumbra_core::lanes::{Real, V3};
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

    /// The surface that is only a boundary between media (Mitsuba's `null` BSDF,
    /// pbrt-v4's `interface` material): a smooth dielectric of relative index 1, through
    /// which light goes straight on. Integrators without media see it as a perfectly
    /// specular pass-through; `volpath` steps over it ([`Material::is_null`]).
    pub fn null() -> Self {
        Material::Dielectric(DielectricMaterial {
            eta: 1.0,
            ..DielectricMaterial::default()
        })
    }

    /// Whether this is the [`Material::null`] boundary.
    pub fn is_null(&self) -> bool {
        *self == Material::null()
    }

    /// A plastic material (see [`PlasticMaterial::new`]).
    pub fn plastic(diffuse: Texture, specular: Texture, eta: f32, roughness: Option<Roughness>) -> Self {
        Material::Plastic(PlasticMaterial::new(diffuse, specular, eta, roughness))
    }

    /// The shading frame at `s`: the shading normal with the tangent ∂p/∂u, or the normal
    /// a normal map gives (ignored where the texel points below the surface). Only the
    /// outermost material's map counts: a blend's parts keep the surface's normal.
    pub fn shading_frame(&self, s: &SurfaceHit) -> Frame {
        self.shading_frame_lanes(s.ns.into(), s.dpdu.into(), s.uv.x, s.uv.y)
            .into()
    }

    /// [`Material::shading_frame`] for lanes of any [`Real`] type whose surfaces share this
    /// material: shading normal `ns`, tangent `dpdu`, texture coordinates (`u`, `v`).
    #[inline(always)]
    pub fn shading_frame_lanes<R: Real>(&self, ns: V3<R>, dpdu: V3<R>, u: R, v: R) -> Basis<R> {
        let frame = Basis::from_normal_tangent(ns, dpdu);
        let Material::NormalMapped { map, .. } = self else {
            return frame;
        };
        let (one, two) = (R::splat(1.0), R::splat(2.0));
        let c = map.eval_lanes(u, v);
        let local = V3::new(two * c.x - one, two * c.y - one, two * c.z - one);
        let (n, ok) = frame.to_world(local).try_normalize();
        let mapped = Basis::from_normal_tangent(n, frame.s);
        let keep = R::and(ok, local.z.cmp_gt(R::splat(0.0)));
        Basis {
            s: V3::select(keep, mapped.s, frame.s),
            t: V3::select(keep, mapped.t, frame.t),
            n: V3::select(keep, mapped.n, frame.n),
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
    use glam::Vec3;

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

    /// Eight surfaces of one material in lanes get, lane by lane, the bits of the one-lane
    /// frame: plain, and normal-mapped by an image whose texels point every way (some
    /// below the surface, some nowhere: (0.5, 0.5, 0.5) encodes the zero vector).
    #[test]
    fn lanes_give_each_lane_the_scalar_frame() {
        use crate::texture::{ImageTexture, TextureImage};
        use penumbra_core::lanes::{Lane8, F8};
        let mut rng = penumbra_core::Pcg32::new(21, 4);
        let pixels = (0..64)
            .map(|i| match i % 7 {
                0 => Rgb::splat(0.5),
                _ => Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
            })
            .collect();
        let image = TextureImage {
            width: 8,
            height: 8,
            pixels,
            wrap: Default::default(),
        };
        let plain = Material::Diffuse(DiffuseMaterial::default());
        let mapped = Material::NormalMapped {
            map: Texture::Image(ImageTexture {
                image: std::sync::Arc::new(image),
                scale: 1.0,
            }),
            inner: Box::new(plain.clone()),
        };
        let dir = |rng: &mut penumbra_core::Pcg32| {
            penumbra_core::warp::uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()))
        };
        for material in [&plain, &mapped] {
            for _ in 0..2_000 {
                let ns: [Vec3; 8] = std::array::from_fn(|_| dir(&mut rng));
                // Some tangents along the normal (the frame's fallback).
                let dpdu: [Vec3; 8] = std::array::from_fn(|k| if k == 5 { ns[k] } else { dir(&mut rng) * 2.0 });
                let uv: [Vec2; 8] = std::array::from_fn(|_| Vec2::new(rng.next_f32(), rng.next_f32()) * 3.0);
                let b = material.shading_frame_lanes(
                    V3::<F8>::from_lanes(&ns),
                    V3::from_lanes(&dpdu),
                    F8::from_array(uv.map(|p| p.x)),
                    F8::from_array(uv.map(|p| p.y)),
                );
                let (s, t, n) = (b.s.to_lanes(), b.t.to_lanes(), b.n.to_lanes());
                for k in 0..8 {
                    let surface = SurfaceHit {
                        ns: ns[k],
                        dpdu: dpdu[k],
                        uv: uv[k],
                        ..surface()
                    };
                    let f = material.shading_frame(&surface);
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(
                        [bits(s[k]), bits(t[k]), bits(n[k])],
                        [bits(f.s), bits(f.t), bits(f.n)],
                        "lane {k}"
                    );
                }
            }
        }
    }
}
