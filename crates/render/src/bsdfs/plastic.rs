//! Plastic (coated diffuse): a diffuse base under a dielectric coating of relative index
//! `eta`, as Mitsuba 3's `plastic` and `roughplastic` model it. Light is reflected by the
//! coating (F), or enters it, scatters diffusely in the base with multiple internal
//! reflections (the base albedo ρ divided by 1 - F_dr,int, F_dr,int the coating's diffuse
//! internal reflectance; Mitsuba's linear model), and leaves through it:
//! f_diffuse = (1 - F(cos θi)) (1 - F(cos θo)) ρ / (π η² (1 - F_dr,int)).
//! The smooth coating reflects as a mirror; the rough one by the isotropic GGX microfacet
//! BRDF. For a rough coating of constant roughness the factors are the rough ones, as
//! Mitsuba 3's `roughplastic` tabulates them ([`Coating::rough`]): 1 - F becomes the
//! albedo T(μ) of the coating's GGX transmission lobe, and F_dr,int the albedo of its
//! reflection lobe seen from inside, 2 ∫ R_int(μ) μ dμ. Shadowing and masking make both
//! smaller than the smooth terms, and the base darker: the smooth terms made the
//! env-materials sphere 15% brighter than Mitsuba's.

use super::microfacet::Ggx;
use super::Role;
use super::{
    one_lane_methods, reflect_z, BsdfModel, BsdfSample, Gather, LaneKernel, LaneSample, SpecularRays, TransportMode,
};
use crate::optics::fresnel_dielectric;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{warp, Rgb};
use std::f32::consts::FRAC_1_PI;

/// Cosines at which [`Coating::rough`] tabulates the transmittance (Mitsuba's 64).
const TABLE: usize = 64;

/// What a material's coating lets through, worked out once per material: its diffuse
/// internal reflectance, and for a rough coating its transmittance at 64 cosines.
#[derive(Clone, Debug, PartialEq)]
pub struct Coating {
    /// F_dr,int: the share of diffuse light from inside that the coating reflects back.
    pub internal_reflectance: f32,
    /// T(μ) at μ = k / (TABLE - 1); `None`: the smooth 1 - F(μ).
    transmittance: Option<Box<[f32; TABLE]>>,
}

impl Coating {
    /// A smooth coating of relative index `eta`.
    pub fn smooth(eta: f32) -> Self {
        Coating {
            internal_reflectance: crate::optics::fresnel_diffuse_reflectance(1.0 / eta),
            transmittance: None,
        }
    }

    /// A rough coating of GGX roughness `ggx` (Mitsuba 3's `roughplastic` tables): the
    /// transmittance T(μ, η) of `lobe_transmittance` at μ_k = max(1e-6, k / 63), and
    /// F_dr,int = 2 mean_k R(μ_k, 1/η) μ_k.
    pub fn rough(eta: f32, ggx: Ggx) -> Self {
        let mu = |k: usize| (k as f32 / (TABLE - 1) as f32).max(1e-6);
        let transmittance = Box::new(std::array::from_fn(|k| lobe_transmittance(ggx, mu(k), eta)));
        let internal = (0..TABLE)
            .map(|k| lobe_albedo(ggx, mu(k), 1.0 / eta) * mu(k))
            .sum::<f32>();
        Coating {
            internal_reflectance: 2.0 * internal / TABLE as f32,
            transmittance: Some(transmittance),
        }
    }
}

impl Coating {
    /// [`PlasticLanes`]'s transmittance for one path, for the tests of the tables.
    #[cfg(test)]
    fn transmittance(&self, cos: f32, eta: f32) -> f32 {
        match &self.transmittance {
            Some(t) => interpolate(t, cos),
            None => 1.0 - fresnel_dielectric(cos, eta),
        }
    }
}

/// The table `t` of a rough coating linearly interpolated at cosine `cos`.
#[inline(always)]
fn interpolate(t: &[f32; TABLE], cos: f32) -> f32 {
    let x = cos.clamp(0.0, 1.0) * (TABLE - 1) as f32;
    let k = (x as usize).min(TABLE - 2);
    let w = x - k as f32;
    (1.0 - w) * t[k] + w * t[k + 1]
}

/// The mean of `f(wo, u)` over the unit square by the midpoint rule on 32 x 32 cells, with
/// wo the direction at cos θ = μ in the xz-plane: the quadrature of the coating's tables.
fn over_sample_space(mu: f32, f: impl Fn(Vec3, Vec2) -> f32) -> f32 {
    const N: usize = 32;
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let cell = |k: usize| (k as f32 + 0.5) / N as f32;
    let sum: f64 = (0..N * N)
        .map(|k| f(wo, Vec2::new(cell(k / N), cell(k % N))) as f64)
        .sum();
    (sum / (N * N) as f64) as f32
}

/// R(μ, η): the directional albedo ∫ F(wo·m) f_ggx(wo, wi) cos θi dωi of the GGX reflection
/// lobe with the dielectric Fresnel term, seen from cos θo = μ; over the 2D sample space of
/// [`Ggx::sample_reflection`] (visible normals), where the integrand is the sample's weight.
fn lobe_albedo(ggx: Ggx, mu: f32, eta: f32) -> f32 {
    over_sample_space(mu, |wo, u| {
        let Some((wi, m)) = ggx.sample_reflection(wo, u) else {
            return 0.0;
        };
        let pdf = ggx.reflection_pdf(wo, m);
        if pdf > 0.0 {
            fresnel_dielectric(wo.dot(m), eta) * ggx.reflection(wo, wi, m) * wi.z / pdf
        } else {
            0.0
        }
    })
}

/// T(μ, η): the share of light from cos θ = μ that the rough coating refracts into the
/// base, E[(1 - F(wo·m)) G1(wt)] over normals m visible from wo, wt the refracted direction
/// (Mitsuba 3's `eval_transmittance`).
fn lobe_transmittance(ggx: Ggx, mu: f32, eta: f32) -> f32 {
    over_sample_space(mu, |wo, u| {
        let m = Vec3::from(ggx.sample_visible(wo, u.into()));
        let cos = wo.dot(m);
        match crate::optics::refract(wo, m, eta) {
            Some(wt) if wt.z < 0.0 && cos > 0.0 => (1.0 - fresnel_dielectric(cos, eta)) * ggx.g1(wt),
            _ => 0.0,
        }
    })
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic<'a> {
    pub diffuse: Rgb,
    pub specular: Rgb,
    /// Coating over exterior index of refraction.
    pub eta: f32,
    /// The coating's transmittance and internal reflectance (see [`Coating`]).
    pub coating: &'a Coating,
    /// Share of the specular lobe in sampling, before Fresnel: mean specular over the sum
    /// of the mean diffuse and specular reflectances (as Mitsuba).
    pub specular_weight: f32,
    /// The coating's roughness; `None` for a smooth coating.
    pub alpha: Option<Ggx>,
}

/// Plastic in lanes of any [`Real`] type (up to eight), each lane its own material and
/// coating table.
#[derive(Clone, Copy, Debug)]
pub struct PlasticLanes<'a, R: Real, S: Spectrum<R> = V3<R>> {
    pub diffuse: S,
    pub specular: S,
    pub eta: R,
    /// F_dr,int of each lane's coating.
    pub internal_reflectance: R,
    /// Each lane's transmittance table (`None`: a smooth coating's 1 - F).
    pub tables: [Option<&'a [f32; TABLE]>; 8],
    /// The lanes that have a table.
    pub tabulated: R::Mask,
    pub specular_weight: R,
    /// The microfacet distribution (any positive roughness where `rough` does not hold).
    pub ggx: Ggx<R>,
    pub rough: R::Mask,
}

impl<'a> Plastic<'a> {
    /// The one-lane instance of the arithmetic.
    #[inline(always)]
    pub fn lanes(&self, _mode: TransportMode) -> PlasticLanes<'a, f32> {
        let mut tables = [None; 8];
        tables[0] = self.coating.transmittance.as_deref();
        PlasticLanes {
            diffuse: self.diffuse.into(),
            specular: self.specular.into(),
            eta: self.eta,
            internal_reflectance: self.coating.internal_reflectance,
            tables,
            tabulated: tables[0].is_some(),
            specular_weight: self.specular_weight,
            ggx: self.alpha.unwrap_or(Ggx { ax: 1.0, ay: 1.0 }),
            rough: self.alpha.is_some(),
        }
    }
}

impl<'a> Gather for PlasticLanes<'a, f32> {
    type Lanes<L: Lane8> = PlasticLanes<'a, L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> PlasticLanes<'a, L> {
        PlasticLanes {
            diffuse: V3::gather(one, |p| p.diffuse),
            specular: V3::gather(one, |p| p.specular),
            eta: L::from_array(one.map(|p| p.eta)),
            internal_reflectance: L::from_array(one.map(|p| p.internal_reflectance)),
            tables: one.map(|p| p.tables[0]),
            tabulated: L::mask_of(one.map(|p| p.tabulated)),
            specular_weight: L::from_array(one.map(|p| p.specular_weight)),
            ggx: Ggx {
                ax: L::from_array(one.map(|p| p.ggx.ax)),
                ay: L::from_array(one.map(|p| p.ggx.ay)),
            },
            rough: L::mask_of(one.map(|p| p.rough)),
        }
    }
}

impl<'a, R: Real, S: Spectrum<R>> PlasticLanes<'a, R, S> {
    /// The same BSDF carrying the payload `T`, its colours converted by `to` (as a
    /// spectral renderer turns RGB parameters into values at a path's wavelengths).
    #[inline(always)]
    pub fn with_spectrum<T: Spectrum<R>>(self, to: impl Fn(Role, S) -> T) -> PlasticLanes<'a, R, T> {
        PlasticLanes {
            diffuse: to(Role::Reflectance, self.diffuse),
            specular: to(Role::Specular, self.specular),
            eta: self.eta,
            internal_reflectance: self.internal_reflectance,
            tables: self.tables,
            tabulated: self.tabulated,
            specular_weight: self.specular_weight,
            ggx: self.ggx,
            rough: self.rough,
        }
    }

    /// The share of light arriving at cosine `cos` that enters the coating (or leaves it
    /// towards `cos`): the lane's table linearly interpolated, or 1 - F.
    #[inline(always)]
    fn transmittance(&self, cos: R) -> R {
        penumbra_core::choose_lanes!(
            R,
            self.tabulated,
            R::map_lanes([cos], |k, [c]| [self.tables[k].map_or(0.0, |t| interpolate(t, c))])[0],
            R::splat(1.0) - fresnel_dielectric(cos, self.eta)
        )
    }

    /// Probability of sampling the coating's reflection, seen from cosine `cos_o`.
    #[inline(always)]
    fn specular_probability(&self, cos_o: R) -> R {
        let one = R::splat(1.0);
        let t = self.transmittance(cos_o);
        let ps = (one - t) * self.specular_weight;
        let pd = t * (one - self.specular_weight);
        R::select((ps + pd).cmp_gt(R::splat(0.0)), ps / (ps + pd), R::splat(0.0))
    }

    #[inline(always)]
    fn diffuse_part(&self, cos_o: R, cos_i: R) -> S {
        let t = self.transmittance(cos_i) * self.transmittance(cos_o);
        let scale = t * R::splat(FRAC_1_PI) / (self.eta * self.eta * (R::splat(1.0) - self.internal_reflectance));
        self.diffuse.scale(scale)
    }
}

impl<R: Real, S: Spectrum<R>> LaneKernel<R, S> for PlasticLanes<'_, R, S> {
    #[inline(always)]
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S {
        let zero = R::splat(0.0);
        let f = self.diffuse_part(wo.z, wi.z);
        let f = if R::any(self.rough) {
            let (m, ok) = Ggx::half_vector_lanes(wo, wi);
            let glossy = self
                .specular
                .scale(fresnel_dielectric(wo.dot(m), self.eta) * self.ggx.reflection(wo, wi, m));
            S::select(R::and(self.rough, ok), f + glossy, f)
        } else {
            f
        };
        let front = R::not(R::or(wo.z.cmp_le(zero), wi.z.cmp_le(zero)));
        S::select(front, f, S::splat(0.0))
    }

    #[inline(always)]
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R {
        let zero = R::splat(0.0);
        let ps = self.specular_probability(wo.z);
        let pdf = (R::splat(1.0) - ps) * (wi.z.max(zero) * R::splat(FRAC_1_PI));
        let pdf = if R::any(self.rough) {
            let (m, ok) = Ggx::half_vector_lanes(wo, wi);
            R::select(R::and(self.rough, ok), pdf + ps * self.ggx.reflection_pdf(wo, m), pdf)
        } else {
            pdf
        };
        let front = R::not(R::or(wo.z.cmp_le(zero), wi.z.cmp_le(zero)));
        R::select(front, pdf, zero)
    }

    #[inline(always)]
    fn sample(&self, wo: V3<R>, u: R, u2: (R, R)) -> LaneSample<R, S> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let ps = self.specular_probability(wo.z);
        let specular = u.cmp_lt(ps);
        let mirror = R::and(specular, R::not(self.rough));
        let glossy = R::and(specular, self.rough);
        let cosine = warp::cosine_hemisphere_lanes(u2.0, u2.1);
        let (wi, reflects) = if R::any(glossy) {
            let (reflected, _, reflects) = self.ggx.sample_reflection_lanes(wo, u2);
            (V3::select(glossy, reflected, cosine), reflects)
        } else {
            (cosine, R::splat_mask(true))
        };
        let pdf = self.pdf(wo, wi);
        let weight = self.eval(wo, wi).scale(wi.z / pdf);
        let exists = R::and(
            R::and(R::or(R::not(glossy), reflects), R::not(wi.z.cmp_le(zero))),
            pdf.cmp_gt(zero),
        );
        LaneSample {
            wi: V3::select(mirror, V3::new(-wo.x, -wo.y, wo.z), wi),
            weight: S::select(
                mirror,
                self.specular.scale(fresnel_dielectric(wo.z, self.eta) / ps),
                weight,
            ),
            pdf: R::select(mirror, ps, pdf),
            delta: mirror,
            eta: one,
            ok: R::and(R::not(wo.z.cmp_le(zero)), R::or(mirror, exists)),
        }
    }
}

impl BsdfModel for Plastic<'_> {
    one_lane_methods!();

    fn specular_rays(&self, wo: Vec3, _mode: TransportMode, rays: &mut SpecularRays) {
        if self.alpha.is_none() && wo.z > 0.0 {
            rays.push(reflect_z(wo), self.specular * fresnel_dielectric(wo.z, self.eta));
        }
    }

    fn has_smooth(&self) -> bool {
        true
    }

    fn albedo(&self) -> Rgb {
        self.diffuse
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::Pcg32;
    use std::f32::consts::PI;

    /// The quadrature of the lobe's albedo against an independent estimate: uniform
    /// hemisphere sampling of F f cos θi 2π, 400,000 samples (4 standard errors plus the
    /// quadrature's own error, 2e-3, allowed).
    #[test]
    fn lobe_albedo_agrees_with_uniform_sampling() {
        let mut rng = Pcg32::new(5, 0);
        for (alpha, mu, eta) in [(0.3, 0.5, 1.5), (0.15, 0.9, 1.49), (0.5, 0.2, 1.0 / 1.49)] {
            let ggx = Ggx::new(alpha, alpha).unwrap();
            let wo = Vec3::new((1.0f32 - mu * mu).sqrt(), 0.0, mu);
            let n = 400_000;
            let (mut sum, mut sq) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let wi = warp::uniform_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                let v = match Ggx::reflection_half_vector(wo, wi) {
                    Some(m) => {
                        (fresnel_dielectric(wo.dot(m), eta) * ggx.reflection(wo, wi, m) * wi.z * 2.0 * PI) as f64
                    }
                    None => 0.0,
                };
                sum += v;
                sq += v * v;
            }
            let mean = sum / n as f64;
            let se = ((sq / n as f64 - mean * mean) / n as f64).sqrt();
            let got = lobe_albedo(ggx, mu, eta) as f64;
            assert!(
                (got - mean).abs() < 4.0 * se + 2e-3,
                "alpha {alpha} mu {mu} eta {eta}: quadrature {got} against {mean} +- {se}"
            );
        }
    }

    /// A nearly smooth rough coating has the smooth coating's terms: 1 - F(μ) within 0.01,
    /// and F_dr,int within 2.5% (Mitsuba's 64-node mean straddles the jump of R_int to 1 at
    /// the critical angle: about 1/64 of the jump, where the 1024-cell integral is exact).
    #[test]
    fn a_nearly_smooth_coating_has_the_smooth_terms() {
        let eta = 1.49;
        let rough = Coating::rough(eta, Ggx::new(0.01, 0.01).unwrap());
        let smooth = Coating::smooth(eta);
        for mu in [0.1f32, 0.3, 0.5, 0.8, 1.0] {
            let (r, s) = (rough.transmittance(mu, eta), smooth.transmittance(mu, eta));
            assert!((r - s).abs() < 0.01, "mu {mu}: rough {r}, smooth {s}");
        }
        let (r, s) = (rough.internal_reflectance, smooth.internal_reflectance);
        assert!((r - s).abs() < 0.025 * s, "internal reflectance: rough {r}, smooth {s}");
    }

    /// Roughness loses light to shadowing and masking: the rough internal reflectance is
    /// below the smooth one, and more so the rougher the coating.
    #[test]
    fn rougher_coatings_reflect_less_inside() {
        let eta = 1.5;
        let r = [0.05, 0.15, 0.4].map(|a| Coating::rough(eta, Ggx::new(a, a).unwrap()).internal_reflectance);
        let smooth = Coating::smooth(eta).internal_reflectance;
        assert!(
            smooth > r[0] && r[0] > r[1] && r[1] > r[2],
            "smooth {smooth}, rough {r:?}"
        );
    }
}
