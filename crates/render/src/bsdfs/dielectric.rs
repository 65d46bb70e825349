//! A dielectric interface (glass, water) between the exterior and an interior of relative
//! index `eta`. Smooth: Fresnel-weighted mirror reflection and Snell refraction, one chosen
//! with probability F. Rough: the GGX microfacet BSDF of Walter et al., "Microfacet Models
//! for Refraction through Rough Surfaces" (EGSR 2007), eqs. 20-21, with the generalized
//! half vector m ∝ -(η_i wi + η_o wo), as pbrt-v4's `DielectricBxDF` writes it; normals
//! sampled by visibility (Heitz 2018) and the lobe chosen by F(wo·m).
//!
//! Radiance crossing into a denser medium is scaled by 1/η² (pbrt-v4 section 9.5.2); importance is not.

use super::microfacet::Ggx;
use super::{reflect_z, same_hemisphere, BsdfModel, BsdfSample, SpecularRays, TransportMode};
use crate::optics::{fresnel_dielectric, refract};
use glam::{Vec2, Vec3};
use penumbra_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Interior over exterior index of refraction.
    pub eta: f32,
    /// Tints on the reflected and the transmitted light (1 for physical glass).
    pub reflectance: Rgb,
    pub transmittance: Rgb,
    /// The microfacet distribution; `None` for a smooth interface.
    pub alpha: Option<Ggx>,
}

/// The relative index η_t / η_i for light leaving towards `w`'s side of normal `n`.
#[inline]
fn relative_eta(eta: f32, cos: f32) -> f32 {
    if cos > 0.0 {
        eta
    } else {
        1.0 / eta
    }
}

/// What radiance is scaled by when crossing relative index `eta_rel`.
#[inline]
fn transmission_scale(eta_rel: f32, mode: TransportMode) -> f32 {
    match mode {
        TransportMode::Radiance => 1.0 / (eta_rel * eta_rel),
        TransportMode::Importance => 1.0,
    }
}

/// One of a dielectric's two lobes, which a layered BSDF's walk asks for alone (pbrt-v4's
/// `BxDFReflTransFlags`): sampled with the Fresnel choice left out of the density.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    Reflection,
    Transmission,
}

impl Dielectric {
    /// The rough BSDF's distribution, unless the interface is smooth or index-matched.
    pub(crate) fn rough(&self) -> Option<Ggx> {
        self.alpha.filter(|_| self.eta != 1.0)
    }

    /// The generalized half vector of `wo` and `wi` on the upper side, the relative index
    /// crossed (1 for reflection) and F; `None` when a back-facing microfacet would be needed.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, f32)> {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o == 0.0 || cos_i == 0.0 {
            return None;
        }
        let etap = if cos_o * cos_i > 0.0 {
            1.0
        } else {
            relative_eta(self.eta, cos_o)
        };
        let m = (wi * etap + wo).try_normalize()?;
        let m = if m.z < 0.0 { -m } else { m };
        if m.dot(wi) * cos_i <= 0.0 || m.dot(wo) * cos_o <= 0.0 {
            return None;
        }
        let c = wo.dot(m);
        let f = fresnel_dielectric(c.abs(), relative_eta(self.eta, c));
        Some((m, etap, f))
    }

    /// The rough lobe's density of `wi` before the Fresnel choice (reflection: the visible
    /// normal's density over 4 |wo·m|; refraction: times the Jacobian |wi·m| / (wi·m +
    /// wo·m / η)²), the lobe and F; `None` for a smooth interface or an impossible pair.
    fn lobe_density(&self, wo: Vec3, wi: Vec3) -> Option<(f32, Lobe, f32)> {
        let ggx = self.rough()?;
        let (m, etap, f) = self.half_vector(wo, wi)?;
        let visible = ggx.visible_pdf(wo, m);
        Some(if etap == 1.0 {
            (visible / (4.0 * wo.dot(m).abs()), Lobe::Reflection, f)
        } else {
            let denom = (wi.dot(m) + wo.dot(m) / etap).powi(2);
            (visible * wi.dot(m).abs() / denom, Lobe::Transmission, f)
        })
    }

    /// Density with which [`Dielectric::sample_lobe`] gives `wi` for `lobe`.
    pub(crate) fn pdf_lobe(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        match self.lobe_density(wo, wi) {
            Some((density, l, _)) if l == lobe => density,
            _ => 0.0,
        }
    }

    /// A direction from `lobe` alone: the mirror or refracted direction (smooth), or about
    /// a visible microfacet normal (rough); its weight f |cos θi| / pdf carries F or 1 - F.
    /// `None` where the lobe has nothing (total internal reflection for refraction).
    pub(crate) fn sample_lobe(&self, wo: Vec3, u2: Vec2, lobe: Lobe, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let Some(ggx) = self.rough() else {
            let eta_rel = relative_eta(self.eta, wo.z);
            let f = fresnel_dielectric(wo.z.abs(), eta_rel);
            return match lobe {
                Lobe::Reflection => (f > 0.0).then(|| BsdfSample {
                    wi: reflect_z(wo),
                    weight: self.reflectance * f,
                    pdf: 1.0,
                    delta: true,
                    eta: 1.0,
                }),
                Lobe::Transmission => refract(wo, Vec3::Z * wo.z.signum(), eta_rel)
                    .filter(|_| f < 1.0)
                    .map(|wi| BsdfSample {
                        wi,
                        weight: self.transmittance * ((1.0 - f) * transmission_scale(eta_rel, mode)),
                        pdf: 1.0,
                        delta: true,
                        eta: eta_rel,
                    }),
            };
        };
        let m = Vec3::from(ggx.sample_visible(wo, u2.into()));
        let c = wo.dot(m);
        let eta_rel = relative_eta(self.eta, c);
        let (wi, eta) = match lobe {
            Lobe::Reflection => (2.0 * c * m - wo, 1.0),
            Lobe::Transmission => (refract(wo, if c > 0.0 { m } else { -m }, eta_rel)?, eta_rel),
        };
        if same_hemisphere(wo, wi) != (lobe == Lobe::Reflection) {
            return None;
        }
        let pdf = self.pdf_lobe(wo, wi, lobe);
        let weight = self.eval(wo, wi, mode) * (wi.z.abs() / pdf);
        (pdf > 0.0 && !weight.is_black()).then_some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
            eta,
        })
    }

    fn sample_smooth(&self, wo: Vec3, u: f32, mode: TransportMode) -> Option<BsdfSample> {
        let eta_rel = relative_eta(self.eta, wo.z);
        let f = fresnel_dielectric(wo.z.abs(), eta_rel);
        if u < f {
            return Some(BsdfSample {
                wi: reflect_z(wo),
                weight: self.reflectance,
                pdf: f,
                delta: true,
                eta: 1.0,
            });
        }
        let wi = refract(wo, Vec3::Z * wo.z.signum(), eta_rel)?;
        Some(BsdfSample {
            wi,
            weight: self.transmittance * transmission_scale(eta_rel, mode),
            pdf: 1.0 - f,
            delta: true,
            eta: eta_rel,
        })
    }
}

impl BsdfModel for Dielectric {
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        let Some(ggx) = self.rough() else {
            return Rgb::BLACK;
        };
        let Some((m, etap, f)) = self.half_vector(wo, wi) else {
            return Rgb::BLACK;
        };
        let (cos_o, cos_i) = (wo.z, wi.z);
        let dg = ggx.d(m) * ggx.g2(wo, wi);
        if etap == 1.0 {
            return self.reflectance * (dg * f / (4.0 * cos_i * cos_o).abs());
        }
        let denom = (wi.dot(m) + wo.dot(m) / etap).powi(2) * cos_i * cos_o;
        let ft = dg * (1.0 - f) * (wi.dot(m) * wo.dot(m) / denom).abs();
        self.transmittance * (ft * transmission_scale(etap, mode))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        match self.lobe_density(wo, wi) {
            Some((density, Lobe::Reflection, f)) => density * f,
            Some((density, Lobe::Transmission, f)) => density * (1.0 - f),
            None => 0.0,
        }
    }

    fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let Some(ggx) = self.rough() else {
            return self.sample_smooth(wo, u, mode);
        };
        let m = Vec3::from(ggx.sample_visible(wo, u2.into()));
        let c = wo.dot(m);
        let eta_rel = relative_eta(self.eta, c);
        let f = fresnel_dielectric(c.abs(), eta_rel);
        let (wi, eta) = if u < f {
            (2.0 * c * m - wo, 1.0)
        } else {
            let wi = refract(wo, if c > 0.0 { m } else { -m }, eta_rel)?;
            if same_hemisphere(wo, wi) {
                return None;
            }
            (wi, eta_rel)
        };
        if (u < f) != same_hemisphere(wo, wi) {
            return None;
        }
        let pdf = self.pdf(wo, wi, mode);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: self.eval(wo, wi, mode) * (wi.z.abs() / pdf),
            pdf,
            delta: false,
            eta,
        })
    }

    fn specular_rays(&self, wo: Vec3, mode: TransportMode, rays: &mut SpecularRays) {
        if self.rough().is_some() || wo.z == 0.0 {
            return;
        }
        let eta_rel = relative_eta(self.eta, wo.z);
        let f = fresnel_dielectric(wo.z.abs(), eta_rel);
        rays.push(reflect_z(wo), self.reflectance * f);
        if let Some(wi) = refract(wo, Vec3::Z * wo.z.signum(), eta_rel) {
            rays.push(wi, self.transmittance * ((1.0 - f) * transmission_scale(eta_rel, mode)));
        }
    }

    fn has_smooth(&self) -> bool {
        self.rough().is_some()
    }

    fn albedo(&self) -> Rgb {
        self.transmittance
    }
}
