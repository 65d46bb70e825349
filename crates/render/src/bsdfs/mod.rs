//! BSDFs: how a surface point scatters light, as small values built per hit from a
//! [`Material`](crate::Material) and its textures (no allocation per ray).
//!
//! Directions live in the local shading frame (z = shading normal, as in pbrt and Mitsuba)
//! and point away from the surface. [`Bsdf::eval`] is f(wo, wi) without the cosine, for the
//! non-delta part; [`Bsdf::sample`] draws wi from the whole BSDF, delta lobes included, and
//! returns the weight f |cos θi| / pdf; [`Bsdf::pdf`] is the solid-angle density with which
//! `sample` produces a non-delta wi (the probability of choosing the non-delta part
//! included), so that multiple importance sampling can weigh light samples against it.
//! [`Bsdf::specular_rays`] lists the delta lobes for the Whitted and direct integrators.
//!
//! Adding a BSDF: a new file whose type implements [`BsdfModel`], and one line in the
//! `bsdf_kinds!` registry below (its variant in [`BsdfKind`] and its name).

mod blend;
mod conductor;
mod dielectric;
mod diffuse;
#[cfg(test)]
mod lanes_tests;
mod layered;
mod layered_walk;
pub mod microfacet;
mod payload;
mod phong;
mod plastic;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_table;

pub(crate) use blend::part_lobe;
pub use blend::{Blend, MixtureLanes, OneBsdf};
pub use conductor::{Conductor, ConductorLanes, MetalFresnel};
pub use dielectric::{Dielectric, DielectricLanes, Lobe};
pub use diffuse::{Diffuse, DiffuseLanes};
pub use layered::{LayerBase, Layered};
pub use layered_walk::{BaseLanes, LayeredLanes};
pub use payload::SampleIn;
pub use phong::{PhongBsdf, PhongLanes};
pub use plastic::{Coating, Plastic, PlasticLanes};

use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::Rgb;

/// What a colour of a BSDF kernel is, for [`DiffuseLanes::with_spectrum`] and its kin:
/// which parameter of the material it came from, so that a spectral renderer can take it
/// from the material's spectrum for that parameter, or uplift the RGB as a reflectance
/// ([`Role::bounded`]) or as an unbounded quantity (a conductor's η and k).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// The diffuse or base reflectance.
    Reflectance,
    /// A specular reflectance or tint.
    Specular,
    /// A specular transmittance.
    Transmittance,
    /// A perfect mirror's reflectance (Phong's `mirror`).
    Mirror,
    /// A conductor's refractive index.
    Eta,
    /// A conductor's absorption coefficient.
    K,
}

impl Role {
    /// Whether the parameter is a reflectance in [0, 1] (not η or k).
    pub fn bounded(self) -> bool {
        !matches!(self, Role::Eta | Role::K)
    }
}

/// Which quantity a path carries: radiance from the camera's side, or importance from the
/// lights' (light tracing, photons). Refraction scales radiance by 1/η² and importance not.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TransportMode {
    #[default]
    Radiance,
    Importance,
}

impl TransportMode {
    /// The other quantity: what a path traced from the far end carries.
    pub fn adjoint(self) -> Self {
        match self {
            TransportMode::Radiance => TransportMode::Importance,
            TransportMode::Importance => TransportMode::Radiance,
        }
    }
}

/// A direction drawn by [`Bsdf::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    pub wi: Vec3,
    /// f |cos θi| / pdf (for a delta lobe: its weight over the probability of choosing it).
    pub weight: Rgb,
    /// Solid-angle density; for a delta lobe the probability of having chosen it.
    pub pdf: f32,
    /// Drawn from a delta (perfectly specular) lobe: no other strategy could produce it.
    pub delta: bool,
    /// Relative index of refraction η_t / η_i crossed (1 for reflection).
    pub eta: f32,
}

impl BsdfSample {
    /// Whether an integrator may follow the sample: a positive density and finite values.
    #[inline]
    pub(crate) fn usable(&self) -> bool {
        self.pdf > 0.0 && self.weight.is_finite() && self.wi.is_finite()
    }
}

/// [`BsdfSample`] in lanes of any [`Real`] type, with the lanes where a sample exists;
/// the weight in the path's payload `S` (RGB by default, see [`Spectrum`]).
#[derive(Clone, Copy, Debug)]
pub struct LaneSample<R: Real, S: Spectrum<R> = V3<R>> {
    pub wi: V3<R>,
    pub weight: S,
    pub pdf: R,
    pub delta: R::Mask,
    pub eta: R,
    pub ok: R::Mask,
}

impl LaneSample<f32> {
    /// The one lane's sample, if it exists.
    #[inline(always)]
    pub fn one(self) -> Option<BsdfSample> {
        self.ok.then(|| BsdfSample {
            wi: self.wi.into(),
            weight: self.weight.into(),
            pdf: self.pdf,
            delta: self.delta,
            eta: self.eta,
        })
    }
}

impl<R: Real, S: Spectrum<R>> penumbra_core::lanes::Choose<R> for LaneSample<R, S> {
    #[inline(always)]
    fn choose(mask: R::Mask, a: Self, b: Self) -> Self {
        LaneSample {
            wi: V3::select(mask, a.wi, b.wi),
            weight: S::select(mask, a.weight, b.weight),
            pdf: R::select(mask, a.pdf, b.pdf),
            delta: R::select_mask(mask, a.delta, b.delta),
            eta: R::select(mask, a.eta, b.eta),
            ok: R::select_mask(mask, a.ok, b.ok),
        }
    }
}

/// A BSDF kind's arithmetic written over the lane type `R` (f32 for one path, eight lanes
/// for eight): the non-delta value and density, and a sample, per lane, in the transport
/// mode the lanes were made for. Values are in the path's payload `S`: the RGB renderer's
/// three channels by default, four sampled wavelengths for spectral rendering, by the same
/// code ([`Spectrum`]).
pub trait LaneKernel<R: Real, S: Spectrum<R> = V3<R>> {
    /// f(wo, wi) without the cosine.
    fn eval(&self, wo: V3<R>, wi: V3<R>) -> S;
    /// Density with which `sample` gives the non-delta direction `wi`.
    fn pdf(&self, wo: V3<R>, wi: V3<R>) -> R;
    /// A direction from the whole BSDF: `u_lobe` chooses among lobes, `u` within one.
    fn sample(&self, wo: V3<R>, u_lobe: R, u: (R, R)) -> LaneSample<R, S>;
}

/// A kind's one-lane instance that eight of make an eight-lane one (the wavefront's
/// gather): `Self` is the kind's kernel at `f32`, `Lanes<L>` the same kernel at `L`.
pub trait Gather: Copy {
    type Lanes<L: Lane8>: LaneKernel<L>;
    fn gather<L: Lane8>(one: &[Self; 8]) -> Self::Lanes<L>;
}

/// The scalar [`BsdfModel`] methods `eval`, `pdf` and `sample` of a kind whose
/// arithmetic is a [`LaneKernel`], by its one-lane instance `self.lanes(mode)`.
macro_rules! one_lane_methods {
    () => {
        fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
            LaneKernel::eval(&self.lanes(mode), wo.into(), wi.into()).into()
        }

        fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
            LaneKernel::pdf(&self.lanes(mode), wo.into(), wi.into())
        }

        fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
            LaneKernel::sample(&self.lanes(mode), wo.into(), u_lobe, u.into()).one()
        }
    };
}
use one_lane_methods;

/// A perfectly specular direction and its weight f |cos θi| (per unit of delta).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpecularRay {
    pub wi: Vec3,
    pub weight: Rgb,
}

/// Up to [`MAX_SPECULAR_RAYS`] perfectly specular rays, kept on the stack; rays in the
/// same direction are merged (a blend of two glasses has two reflections along one line).
/// A surface with more distinct delta directions than that (a blend of many glasses of
/// different indices) keeps the strongest and counts the weight of those it drops in
/// [`SpecularRays::dropped`], for the integrator to warn about; it never fails.
#[derive(Clone, Copy, Debug, Default)]
pub struct SpecularRays {
    rays: [SpecularRay; MAX_SPECULAR_RAYS],
    len: usize,
    dropped: f32,
}

/// Room for a blend of blends of eight glasses (a shared reflection and eight refractions)
/// and then some.
pub const MAX_SPECULAR_RAYS: usize = 16;

impl SpecularRays {
    pub fn push(&mut self, wi: Vec3, weight: Rgb) {
        if weight.is_black() {
            return;
        }
        if let Some(same) = self.rays[..self.len].iter_mut().find(|r| r.wi == wi) {
            same.weight += weight;
            return;
        }
        if self.len < MAX_SPECULAR_RAYS {
            self.rays[self.len] = SpecularRay { wi, weight };
            self.len += 1;
            return;
        }
        // Full: the weakest of the kept rays and the new one is dropped.
        let strength = |w: Rgb| w.max_component();
        let weakest = (0..self.len)
            .min_by(|&a, &b| strength(self.rays[a].weight).total_cmp(&strength(self.rays[b].weight)))
            .unwrap_or(0);
        let lost = if strength(weight) > strength(self.rays[weakest].weight) {
            std::mem::replace(&mut self.rays[weakest], SpecularRay { wi, weight }).weight
        } else {
            weight
        };
        self.dropped += strength(lost);
    }

    pub fn as_slice(&self) -> &[SpecularRay] {
        &self.rays[..self.len]
    }

    /// The summed largest channel of the rays dropped for want of room (0 almost always).
    pub fn dropped(&self) -> f32 {
        self.dropped
    }

    /// Every ray of `other`, each weighted by `scale`, added as [`SpecularRays::push`]
    /// adds one (its dropped weight carried over).
    pub fn extend_scaled(&mut self, other: &SpecularRays, scale: f32) {
        for r in other.as_slice() {
            self.push(r.wi, r.weight * scale);
        }
        self.dropped += other.dropped * scale;
    }
}

/// What every scattering function provides; each kind's file implements it for its type.
/// Directions are in the local shading frame, as the module documentation says.
pub trait BsdfModel {
    /// f(wo, wi) of the non-delta part, without the cosine.
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb;
    /// Density with which `sample` produces the non-delta direction `wi`.
    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32;
    /// A direction from the whole BSDF: `u` chooses among lobes, `u2` within one.
    fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample>;
    /// The perfectly specular rays leaving towards `wo` (none by default).
    fn specular_rays(&self, _wo: Vec3, _mode: TransportMode, _rays: &mut SpecularRays) {}
    /// Whether there is a non-delta part (worth sampling lights for).
    fn has_smooth(&self) -> bool;
    /// A colour for the albedo AOV and ambient light.
    fn albedo(&self) -> Rgb;
    /// Whether `eval` and `pdf` are unbiased estimates by random walks (layered BSDFs)
    /// rather than closed forms: the test table checks such a kind in expectation, and its
    /// sample weight is the walk's, not eval |cos| / pdf.
    fn stochastic(&self) -> bool {
        false
    }
}

/// The registry of BSDF kinds: one line per kind (variant, type, name) generates
/// [`BsdfKind`], its static dispatch and [`BsdfKind::NAMES`], which the test table checks
/// it covers. Adding a BSDF: its file, implementing [`BsdfModel`], and one line here.
macro_rules! bsdf_kinds {
    ($lt:lifetime; $($variant:ident($ty:ty) = $name:literal),* $(,)?) => {
        /// The scattering functions this renderer knows.
        #[derive(Clone, Copy, Debug)]
        pub enum BsdfKind<$lt> {
            $($variant($ty)),*
        }

        impl<$lt> BsdfKind<$lt> {
            /// Every kind's name, in registry order.
            pub const NAMES: &'static [&'static str] = &[$($name),*];

            pub fn name(&self) -> &'static str {
                match self {
                    $(BsdfKind::$variant(_) => $name),*
                }
            }

            /// The kind as its model, for code that is not on the per-ray hot path.
            pub fn model(&self) -> &dyn BsdfModel {
                match self {
                    $(BsdfKind::$variant(b) => b),*
                }
            }

            pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
                match self {
                    $(BsdfKind::$variant(b) => b.eval(wo, wi, mode)),*
                }
            }

            pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
                match self {
                    $(BsdfKind::$variant(b) => b.pdf(wo, wi, mode)),*
                }
            }

            pub fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
                let s = match self {
                    $(BsdfKind::$variant(b) => b.sample(wo, u, u2, mode)),*
                }?;
                s.usable().then_some(s)
            }

            pub fn specular_rays(&self, wo: Vec3, mode: TransportMode) -> SpecularRays {
                let mut rays = SpecularRays::default();
                match self {
                    $(BsdfKind::$variant(b) => b.specular_rays(wo, mode, &mut rays)),*
                }
                rays
            }

            pub fn has_smooth(&self) -> bool {
                self.model().has_smooth()
            }

            pub fn albedo(&self) -> Rgb {
                self.model().albedo()
            }

            pub fn stochastic(&self) -> bool {
                self.model().stochastic()
            }
        }
    };
}

bsdf_kinds! { 'a;
    Diffuse(Diffuse) = "diffuse",
    Phong(PhongBsdf) = "phong",
    Conductor(Conductor) = "conductor",
    Dielectric(Dielectric) = "dielectric",
    Plastic(Plastic<'a>) = "plastic",
    Blend(Blend<'a>) = "blend",
    Layered(Layered) = "layered",
}

/// A BSDF at one surface point. A one-sided BSDF reflects on the side its shading normal
/// faces; `two_sided` mirrors it onto the back (Mitsuba's `twosided`).
#[derive(Clone, Copy, Debug)]
pub struct Bsdf<'a> {
    pub kind: BsdfKind<'a>,
    pub two_sided: bool,
}

/// z flipped: the direction mirrored through the tangent plane.
#[inline]
pub(crate) fn flip(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl<'a> Bsdf<'a> {
    pub fn one_sided(kind: BsdfKind<'a>) -> Self {
        Bsdf { kind, two_sided: false }
    }

    /// Whether directions about `wo` must be mirrored onto the front first.
    #[inline]
    pub(crate) fn mirrored(&self, wo: Vec3) -> bool {
        self.two_sided && wo.z < 0.0
    }

    /// f(wo, wi) of the non-delta part, without the cosine.
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        if self.mirrored(wo) {
            return self.kind.eval(flip(wo), flip(wi), mode);
        }
        self.kind.eval(wo, wi, mode)
    }

    /// Density with which [`Bsdf::sample`] produces the non-delta direction `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if self.mirrored(wo) {
            return self.kind.pdf(flip(wo), flip(wi), mode);
        }
        self.kind.pdf(wo, wi, mode)
    }

    /// A direction from the whole BSDF: `u` chooses among lobes, `u2` within one.
    pub fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if self.mirrored(wo) {
            return self
                .kind
                .sample(flip(wo), u, u2, mode)
                .map(|s| BsdfSample { wi: flip(s.wi), ..s });
        }
        self.kind.sample(wo, u, u2, mode)
    }

    /// The perfectly specular rays leaving towards `wo`, with their weights.
    pub fn specular_rays(&self, wo: Vec3, mode: TransportMode) -> SpecularRays {
        if self.mirrored(wo) {
            let inner = self.kind.specular_rays(flip(wo), mode);
            let mut rays = SpecularRays {
                dropped: inner.dropped,
                ..SpecularRays::default()
            };
            for r in inner.as_slice() {
                rays.push(flip(r.wi), r.weight);
            }
            return rays;
        }
        self.kind.specular_rays(wo, mode)
    }

    /// Whether the BSDF has a non-delta part (worth sampling lights for).
    pub fn has_smooth(&self) -> bool {
        self.kind.has_smooth()
    }

    /// A colour for the albedo AOV and ambient light: the diffuse reflectance, or the
    /// specular colour of a material without one.
    pub fn albedo(&self) -> Rgb {
        self.kind.albedo()
    }

    /// Whether eval and pdf are estimates (see [`BsdfModel::stochastic`]).
    pub fn stochastic(&self) -> bool {
        self.kind.stochastic()
    }
}

/// Mirror reflection about the normal, in the local frame.
#[inline]
pub(crate) fn reflect_z(w: Vec3) -> Vec3 {
    reflect_z_lanes(w.into()).into()
}

/// [`reflect_z`] per lane of any [`Real`] type.
#[inline(always)]
pub(crate) fn reflect_z_lanes<R: Real>(w: V3<R>) -> V3<R> {
    V3::new(-w.x, -w.y, w.z)
}
