//! The GGX (Trowbridge-Reitz) microfacet distribution, anisotropic, with the height-correlated
//! Smith shadowing-masking function and sampling of the visible normals (Heitz, "Sampling
//! the GGX Distribution of Visible Normals", JCGT 2018). Walter et al. 2007 for D and G1;
//! Heitz 2014 ("Understanding the Masking-Shadowing Function") for G2.

use glam::{Vec2, Vec3};
use penumbra_core::trig;
use std::f32::consts::PI;

/// Roughness below this is treated as a perfectly smooth surface (as pbrt-v4 does): the
/// distribution would be too peaked to evaluate in single precision.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// GGX with roughness `ax` along the tangent (x) and `ay` along the bitangent (y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub ax: f32,
    pub ay: f32,
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

    /// Density of microfacet normals `m` per unit projected area: D(m).
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let t = (m.x / self.ax).powi(2) + (m.y / self.ay).powi(2) + m.z * m.z;
        1.0 / (PI * self.ax * self.ay * t * t)
    }

    /// Smith's Λ(w) for GGX (symmetric in the side of `w`).
    pub fn lambda(&self, w: Vec3) -> f32 {
        if w.z == 0.0 {
            return f32::INFINITY;
        }
        let a2_tan2 = ((w.x * self.ax).powi(2) + (w.y * self.ay).powi(2)) / (w.z * w.z);
        0.5 * ((1.0 + a2_tan2).sqrt() - 1.0)
    }

    /// Masking of direction `w`: G1 = 1 / (1 + Λ).
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing: G2 = 1 / (1 + Λ(wo) + Λ(wi)).
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// A microfacet normal visible from `wo` (on either side; the normal is on the upper
    /// side), with density [`Ggx::visible_pdf`].
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let wo = if wo.z < 0.0 { -wo } else { wo };
        // The view direction stretched to the hemisphere configuration (alpha = 1).
        let vh = Vec3::new(self.ax * wo.x, self.ay * wo.y, wo.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        // A point on the projected disk, warped to the visible half.
        let r = u.x.sqrt();
        let (sin_phi, cos_phi) = trig::sin_cos_turns(u.y);
        let p1 = r * cos_phi;
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sin_phi;
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        // Back to the ellipsoid configuration.
        Vec3::new(self.ax * nh.x, self.ay * nh.y, nh.z.max(1e-6)).normalize()
    }

    /// The half vector of a reflection from `wo` to `wi`, when both are above the surface.
    pub fn reflection_half_vector(wo: Vec3, wi: Vec3) -> Option<Vec3> {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        (wo + wi).try_normalize()
    }

    /// The reflection BRDF without Fresnel at half vector `m`: D(m) G2 / (4 cos θo cos θi)
    /// (Walter et al. 2007, eq. 20).
    pub fn reflection(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.d(m) * self.g2(wo, wi) / (4.0 * wo.z * wi.z)
    }

    /// Density of the direction [`Ggx::sample_reflection`] gives, mirrored about `m`:
    /// D_wo(m) / (4 wo·m).
    pub fn reflection_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        self.visible_pdf(wo, m) / (4.0 * wo.dot(m))
    }

    /// `wo` mirrored about a normal visible from it, and that normal; `None` when the
    /// reflection goes below the surface.
    pub fn sample_reflection(&self, wo: Vec3, u: Vec2) -> Option<(Vec3, Vec3)> {
        let m = self.sample_visible(wo, u);
        let cos_om = wo.dot(m);
        let wi = 2.0 * cos_om * m - wo;
        (wi.z > 0.0 && cos_om > 0.0).then_some((wi, m))
    }

    /// Density of [`Ggx::sample_visible`]: D_wo(m) = G1(wo) max(0, wo·m) D(m) / |cos θo|.
    pub fn visible_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        let wo = if wo.z < 0.0 { -wo } else { wo };
        let cos_om = wo.dot(m);
        if cos_om <= 0.0 || wo.z == 0.0 {
            return 0.0;
        }
        self.g1(wo) * cos_om * self.d(m) / wo.z
    }
}
