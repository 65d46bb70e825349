//! glTF's metallic-roughness material (glTF 2.0 spec, appendix B) on our BSDFs:
//!
//! - the dielectric part, `fresnel_mix(ior 1.5, diffuse(base colour), GGX)`, is our rough
//!   plastic (a diffuse base under a GGX coating of index 1.5, or KHR_materials_ior's);
//! - the metal, `conductor_fresnel(f0 = base colour, GGX)`, is our conductor with
//!   Schlick's Fresnel term;
//! - `metallic` blends the two, `roughness`² is GGX's alpha (both from the B and G channels
//!   of the metallicRoughness texture times their factors, baked into textures of their
//!   own); KHR_materials_transmission blends in a rough dielectric of the same index;
//! - the normal texture (scaled by its `scale`) perturbs the shading normal in the frame of
//!   ∂p/∂u; emission is the emissive factor (times KHR_materials_emissive_strength) times
//!   the emissive texture.
//!
//! Every material is two-sided, as a viewer draws a closed mesh's back faces only where
//! they show through; `doubleSided` decides whether emission leaves both sides. The
//! occlusion texture is not used: a path tracer finds occlusion by tracing it.

use super::{Fail, Reader};
use crate::desc::{Emission, MaterialDesc};
use crate::image_input::srgb_decode;
use gltf::texture::WrappingMode;
use penumbra_core::Rgb;
use penumbra_render::bsdfs::MetalFresnel;
use penumbra_render::materials::Roughness;
use penumbra_render::materials::{ConductorMaterial, DielectricMaterial};
use penumbra_render::texture::{TextureImage, Wrap};
use penumbra_render::{Material, Texture};
use std::sync::Arc;

type Made = (usize, Option<Emission>);

impl Reader {
    /// The scene material (its index) and emission of glTF material `m`.
    pub(super) fn material(&mut self, m: &gltf::Material) -> Result<Made, Fail> {
        let path = match m.index() {
            Some(i) => format!("materials[{i}]"),
            None => "meshes".to_string(),
        };
        if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
            self.warn(
                "alpha",
                &format!("{path}.alphaMode"),
                format!(
                    "alphaMode {:?} is not supported: the surface is drawn opaque",
                    m.alpha_mode()
                ),
            );
        }
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let base_factor = Rgb::new(r, g, b);
        let base = match pbr.base_color_texture() {
            Some(info) => self.texture(&info, &path, true, |c| c * base_factor)?,
            None => Texture::Constant(base_factor),
        };
        let (metal, rough) = (pbr.metallic_factor(), pbr.roughness_factor());
        let (metallic, alpha) = match pbr.metallic_roughness_texture() {
            Some(info) => (
                self.texture(&info, &path, false, |c| Rgb::splat(metal * c.b))?,
                self.texture(&info, &path, false, |c| Rgb::splat((rough * c.g).powi(2)))?,
            ),
            None => (
                Texture::Constant(Rgb::splat(metal)),
                Texture::Constant(Rgb::splat(rough * rough)),
            ),
        };
        let roughness = Some(Roughness {
            alpha_u: alpha.clone(),
            alpha_v: alpha,
        });
        let eta = m.ior().unwrap_or(1.5).max(1.0);
        let plastic = Material::plastic(base.clone(), Texture::Constant(Rgb::WHITE), eta, roughness.clone());
        let dielectric = match m.transmission() {
            Some(t) if t.transmission_factor() > 0.0 => {
                let factor = t.transmission_factor();
                let weight = match t.transmission_texture() {
                    Some(info) => self.texture(&info, &path, false, |c| Rgb::splat(factor * c.r))?,
                    None => Texture::Constant(Rgb::splat(factor)),
                };
                let glass = Material::Dielectric(DielectricMaterial {
                    eta,
                    reflectance: Texture::Constant(Rgb::WHITE),
                    transmittance: base.clone(),
                    roughness: roughness.clone(),
                });
                blend(plastic, glass, weight)
            }
            _ => plastic,
        };
        let conductor = Material::Conductor(ConductorMaterial {
            fresnel: MetalFresnel::Schlick,
            specular: base,
            roughness,
        });
        let mut material = Material::TwoSided(Box::new(blend(dielectric, conductor, metallic)));
        if let Some(normal) = m.normal_texture() {
            let scale = normal.scale();
            let info_path = format!("{path}.normalTexture");
            let map = self.image_texture(&normal.texture(), normal.tex_coord(), &info_path, false, |c| {
                Rgb::new(0.5 + (c.r - 0.5) * scale, 0.5 + (c.g - 0.5) * scale, c.b)
            })?;
            material = Material::NormalMapped {
                map,
                inner: Box::new(material),
            };
        }
        let strength = m.emissive_strength().unwrap_or(1.0);
        let [er, eg, eb] = m.emissive_factor();
        let radiance = Rgb::new(er, eg, eb) * strength;
        let emission = match (radiance.max_component() > 0.0, m.emissive_texture()) {
            (false, _) => None,
            (true, info) => Some(Emission {
                radiance,
                two_sided: m.double_sided(),
                texture: match info {
                    Some(info) => Some(self.texture(&info, &path, true, |c| c)?),
                    None => None,
                },
                spectrum: None,
            }),
        };
        self.desc.materials.push(MaterialDesc {
            name: m.name().unwrap_or("glTF material").to_string(),
            material,
            spectra: None,
        });
        Ok((self.desc.materials.len() - 1, emission))
    }

    /// The texture `info` names, its texels (sRGB-decoded if `srgb`) mapped by `map`.
    fn texture(
        &mut self,
        info: &gltf::texture::Info,
        path: &str,
        srgb: bool,
        map: impl Fn(Rgb) -> Rgb,
    ) -> Result<Texture, Fail> {
        if info.texture_transform().is_some() {
            self.warn(
                "KHR_texture_transform",
                path,
                "KHR_texture_transform is not supported: textures are placed untransformed",
            );
        }
        self.image_texture(&info.texture(), info.tex_coord(), path, srgb, map)
    }

    fn image_texture(
        &mut self,
        texture: &gltf::Texture,
        tex_coord: u32,
        path: &str,
        srgb: bool,
        map: impl Fn(Rgb) -> Rgb,
    ) -> Result<Texture, Fail> {
        if tex_coord != 0 {
            self.warn(
                "texCoord",
                path,
                format!("texture coordinate set {tex_coord} is not supported: set 0 is used"),
            );
        }
        let sampler = texture.sampler();
        let wrap = [sampler.wrap_s(), sampler.wrap_t()].map(|w| match w {
            WrappingMode::Repeat => Wrap::Repeat,
            WrappingMode::MirroredRepeat => Wrap::Mirror,
            WrappingMode::ClampToEdge => Wrap::Clamp,
        });
        let source = texture.source();
        let raw = match self.images.get(&source.index()) {
            Some(raw) => raw.clone(),
            None => {
                let raw = self.buffers.image(&source, &self.dir)?;
                self.images.insert(source.index(), raw.clone());
                raw
            }
        };
        let decode = |x: f32| if srgb { srgb_decode(x) } else { x };
        Ok(Texture::Image(penumbra_render::texture::ImageTexture {
            image: Arc::new(TextureImage {
                wrap,
                width: raw.width,
                height: raw.height,
                pixels: raw
                    .pixels
                    .iter()
                    .map(|c| map(Rgb::new(decode(c.r), decode(c.g), decode(c.b))))
                    .collect(),
            }),
            scale: 1.0,
        }))
    }
}

/// `(1 - weight) a + weight b`, or just `a` or `b` where the weight is a constant 0 or 1.
fn blend(a: Material, b: Material, weight: Texture) -> Material {
    match weight {
        Texture::Constant(w) if w.r <= 0.0 => a,
        Texture::Constant(w) if w.r >= 1.0 => b,
        weight => Material::Blend {
            a: Box::new(a),
            b: Box::new(b),
            weight,
        },
    }
}
