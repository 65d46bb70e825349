//! The GGX (Trowbridge-Reitz) microfacet distribution, anisotropic, with the height-correlated
//! Smith shadowing-masking function and sampling of the visible normals (Heitz, "Sampling
//! the GGX Distribution of Visible Normals", JCGT 2018). Walter et al. 2007 for D and G1;
//! Heitz 2014 ("Understanding the Masking-Shadowing Function") for G2.
//!
//! Written once over the lane type [`Real`] (`Ggx<f32>` for one path, `Ggx<F8>` for
//! eight): branches are selects, so lane `k` of a lane result is bit for bit the scalar
//! result for lane `k`'s inputs.

use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Real, V3};
use penumbra_core::trig;
use std::f32::consts::PI;

/// Roughness below this is treated as a perfectly smooth surface (as pbrt-v4 does): the
/// distribution would be too peaked to evaluate in single precision.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// GGX with roughness `ax` along the tangent (x) and `ay` along the bitangent (y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx<R = f32> {
    pub ax: R,
    pub ay: R,
}

impl Ggx {
    /// The distribution for roughnesses `(ax, ay)`, or `None` when both are below
    /// [`SMOOTH_ALPHA`] (a smooth surface).
    pub fn new(ax: f32, ay: f32) -> Option<Self> {
        (ax.max(ay) >= SMOOTH_ALPHA).then(|| Ggx {
            ax: ax.max(SMOOTH_ALPHA),
            ay: ay.max(SMOOTH_ALPHA),
        })
    }

    /// `wo` mirrored about a normal visible from it, and that normal; `None` when the
    /// reflection goes below the surface ([`Ggx::sample_reflection_lanes`]).
    pub fn sample_reflection(&self, wo: Vec3, u: Vec2) -> Option<(Vec3, Vec3)> {
        let (wi, m, ok) = self.sample_reflection_lanes(wo.into(), (u.x, u.y));
        ok.then(|| (wi.into(), m.into()))
    }

    /// The half vector of a reflection from `wo` to `wi`, when both are above the surface.
    pub fn reflection_half_vector(wo: Vec3, wi: Vec3) -> Option<Vec3> {
        let (m, ok) = Ggx::half_vector_lanes(wo.into(), wi.into());
        ok.then(|| m.into())
    }
}

impl<R: Real> Ggx<R> {
    /// Density of microfacet normals `m` per unit projected area: D(m).
    #[inline(always)]
    pub fn d(&self, m: impl Into<V3<R>>) -> R {
        let m = m.into();
        let (x, y) = (m.x / self.ax, m.y / self.ay);
        let t = x * x + y * y + m.z * m.z;
        let d = R::splat(1.0) / (R::splat(PI) * self.ax * self.ay * t * t);
        R::select(m.z.cmp_gt(R::splat(0.0)), d, R::splat(0.0))
    }

    /// Smith's Λ(w) for GGX (symmetric in the side of `w`).
    #[inline(always)]
    pub fn lambda(&self, w: impl Into<V3<R>>) -> R {
        let w = w.into();
        let (x, y) = (w.x * self.ax, w.y * self.ay);
        let a2_tan2 = (x * x + y * y) / (w.z * w.z);
        let l = R::splat(0.5) * ((R::splat(1.0) + a2_tan2).sqrt() - R::splat(1.0));
        R::select(w.z.cmp_eq(R::splat(0.0)), R::splat(f32::INFINITY), l)
    }

    /// Masking of direction `w`: G1 = 1 / (1 + Λ).
    #[inline(always)]
    pub fn g1(&self, w: impl Into<V3<R>>) -> R {
        R::splat(1.0) / (R::splat(1.0) + self.lambda(w))
    }

    /// Height-correlated masking-shadowing: G2 = 1 / (1 + Λ(wo) + Λ(wi)).
    #[inline(always)]
    pub fn g2(&self, wo: impl Into<V3<R>>, wi: impl Into<V3<R>>) -> R {
        R::splat(1.0) / (R::splat(1.0) + self.lambda(wo) + self.lambda(wi))
    }

    /// A microfacet normal visible from `wo` (on either side; the normal is on the upper
    /// side), with density [`Ggx::visible_pdf`].
    #[inline(always)]
    pub fn sample_visible(&self, wo: impl Into<V3<R>>, u: (R, R)) -> V3<R> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let wo = wo.into();
        let wo = V3::select(wo.z.cmp_lt(zero), -wo, wo);
        // The view direction stretched to the hemisphere configuration (alpha = 1).
        let vh = V3::new(self.ax * wo.x, self.ay * wo.y, wo.z).try_normalize().0;
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = V3::select(
            len2.cmp_gt(zero),
            V3::new(-vh.y, vh.x, zero).div_by(len2.sqrt()),
            V3::new(one, zero, zero),
        );
        let t2 = vh.cross(t1);
        // A point on the projected disk, warped to the visible half.
        let r = u.0.sqrt();
        let (sin_phi, cos_phi) = trig::sin_cos_turns(u.1);
        let p1 = r * cos_phi;
        let s = R::splat(0.5) * (one + vh.z);
        let p2 = (one - s) * (one - p1 * p1).max(zero).sqrt() + s * r * sin_phi;
        let nh = t1.scale(p1) + t2.scale(p2) + vh.scale((one - p1 * p1 - p2 * p2).max(zero).sqrt());
        // Back to the ellipsoid configuration.
        V3::new(self.ax * nh.x, self.ay * nh.y, nh.z.max(R::splat(1e-6)))
            .try_normalize()
            .0
    }

    /// The half vector of a reflection from `wo` to `wi`, and where both are above the
    /// surface (and the half vector exists).
    #[inline(always)]
    pub fn half_vector_lanes(wo: V3<R>, wi: V3<R>) -> (V3<R>, R::Mask) {
        let zero = R::splat(0.0);
        let (m, ok) = (wo + wi).try_normalize();
        (m, R::and(ok, R::and(wo.z.cmp_gt(zero), wi.z.cmp_gt(zero))))
    }

    /// The reflection BRDF without Fresnel at half vector `m`: D(m) G2 / (4 cos θo cos θi)
    /// (Walter et al. 2007, eq. 20).
    #[inline(always)]
    pub fn reflection(&self, wo: impl Into<V3<R>>, wi: impl Into<V3<R>>, m: impl Into<V3<R>>) -> R {
        let (wo, wi) = (wo.into(), wi.into());
        self.d(m) * self.g2(wo, wi) / (R::splat(4.0) * wo.z * wi.z)
    }

    /// Density of the direction [`Ggx::sample_reflection_lanes`] gives, mirrored about `m`:
    /// D_wo(m) / (4 wo·m).
    #[inline(always)]
    pub fn reflection_pdf(&self, wo: impl Into<V3<R>>, m: impl Into<V3<R>>) -> R {
        let (wo, m) = (wo.into(), m.into());
        self.visible_pdf(wo, m) / (R::splat(4.0) * wo.dot(m))
    }

    /// `wo` mirrored about a normal visible from it, that normal, and where the
    /// reflection stays above the surface.
    #[inline(always)]
    pub fn sample_reflection_lanes(&self, wo: V3<R>, u: (R, R)) -> (V3<R>, V3<R>, R::Mask) {
        let zero = R::splat(0.0);
        let m = self.sample_visible(wo, u);
        let cos_om = wo.dot(m);
        let wi = m.scale(R::splat(2.0) * cos_om) - wo;
        (wi, m, R::and(wi.z.cmp_gt(zero), cos_om.cmp_gt(zero)))
    }

    /// Density of [`Ggx::sample_visible`]: D_wo(m) = G1(wo) max(0, wo·m) D(m) / |cos θo|.
    #[inline(always)]
    pub fn visible_pdf(&self, wo: impl Into<V3<R>>, m: impl Into<V3<R>>) -> R {
        let zero = R::splat(0.0);
        let (wo, m) = (wo.into(), m.into());
        let wo = V3::select(wo.z.cmp_lt(zero), -wo, wo);
        let cos_om = wo.dot(m);
        let pdf = self.g1(wo) * cos_om * self.d(m) / wo.z;
        R::select(R::or(cos_om.cmp_le(zero), wo.z.cmp_eq(zero)), zero, pdf)
    }
}
