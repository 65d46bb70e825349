//! Layered BSDFs: a dielectric coating over a diffuse or conductor base, with a medium
//! between them (pbrt-v4's `coateddiffuse` and `coatedconductor`). There is no closed
//! form: [`Layered`]'s `eval`, `sample` and `pdf` are Monte Carlo estimates by random walks
//! between the two interfaces, the position-free method of Guo, Hašan and Zhao,
//! "Position-Free Monte Carlo Simulation for Arbitrary Layered BSDFs" (ACM TOG 37(6), 2018),
//! as pbrt-v4's `LayeredBxDF` writes it (Pharr, Jakob and Humphreys, 4th ed., section
//! 14.3.2). `eval` walks in through the coating towards `wo` and, at every bounce on the
//! base or scattering in the medium, adds a next-event estimate out through the coating
//! towards `wi`, weighing by the power heuristic the direction sampled from `wi` against
//! the walk's own. The medium's extinction is 1 per unit of thickness: with albedo 0 it only
//! absorbs, exp(-thickness / |cos θ|) per crossing (pbrt-v4's `Tr`); otherwise the walk
//! samples free flights and Henyey-Greenstein scattering. Walks are at most `max_depth`
//! interface or scattering events long and cut by Russian roulette after four. The random
//! numbers come from a generator seeded by hashing the arguments, so that an estimate is a
//! deterministic function of them (as pbrt-v4 seeds its `RNG`): images stay reproducible.
//!
//! A smooth coating over a Lambertian base of albedo ρ gives, in expectation, exactly
//! f = (1 - F(θo)) (1 - F(θi)) ρ / (π η² (1 - ρ F_dr,int)): the diffuse light bounces
//! between base and coating any number of times (Mitsuba's `nonlinear` plastic; the
//! linear one divides by 1 - F_dr,int instead). The tests hold the walk to that.
//!
//! `sample`'s weight is the walk's f |cos θi| / pdf; the density it reports for multiple
//! importance sampling is [`Layered`]'s `pdf`, an estimate (pbrt-v4's
//! `pdfIsProportional`): 0.9 times the estimated density of the coating's reflection and
//! the base's lobe seen through the coating, plus 0.1 of uniform density (pbrt mixes with
//! the uniform sphere; the base is opaque here, so we use the upper hemisphere, where all
//! of the samples go). Any positive density keeps the MIS weights summing to one.

use super::{reflect_z, BsdfModel, BsdfSample, Conductor, Dielectric, Diffuse, Lobe, SpecularRays, TransportMode};
use crate::mis::MisHeuristic;
use crate::optics::{fresnel_dielectric, refract};
use crate::phase::HenyeyGreenstein;
use glam::{Vec2, Vec3};
use penumbra_core::hash::hash_words;
use penumbra_core::{Pcg32, Rgb};
use std::f32::consts::PI;

#[cfg(test)]
#[path = "layered_tests.rs"]
mod tests;

/// What lies under the coating.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LayerBase {
    Diffuse(Diffuse),
    /// A conductor whose complex index is relative to the coating's (η and k over its η).
    Conductor(Conductor),
}

impl LayerBase {
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        match self {
            LayerBase::Diffuse(b) => b.eval(wo, wi, mode),
            LayerBase::Conductor(b) => b.eval(wo, wi, mode),
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        match self {
            LayerBase::Diffuse(b) => b.pdf(wo, wi, mode),
            LayerBase::Conductor(b) => b.pdf(wo, wi, mode),
        }
    }

    fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self {
            LayerBase::Diffuse(b) => b.sample(wo, u, u2, mode),
            LayerBase::Conductor(b) => b.sample(wo, u, u2, mode),
        }
        .filter(|s| s.pdf > 0.0 && s.wi.z != 0.0 && !s.weight.is_black())
    }

    /// A smooth mirror: no density to weigh, nothing for next-event estimation.
    fn specular(&self) -> bool {
        matches!(self, LayerBase::Conductor(c) if c.alpha.is_none())
    }

    fn albedo(&self) -> Rgb {
        match self {
            LayerBase::Diffuse(b) => b.albedo(),
            LayerBase::Conductor(b) => b.albedo(),
        }
    }
}

/// A coating over a base, `thickness` apart, with a medium of single-scattering `albedo`
/// and Henyey-Greenstein asymmetry `g` between; estimates use `samples` walks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layered {
    /// The coating: a dielectric interface (reflectance and transmittance tints 1).
    pub coat: Dielectric,
    pub base: LayerBase,
    pub thickness: f32,
    pub albedo: Rgb,
    pub g: f32,
    pub max_depth: u32,
    pub samples: u32,
}

/// The walk's random numbers, seeded by the estimate's arguments.
struct Walk(Pcg32);

impl Walk {
    fn new(a: [f32; 3], b: [f32; 3]) -> Self {
        let words = |v: [f32; 3]| hash_words(&v.map(|x| x.to_bits() as u64));
        Walk(Pcg32::new(words(a), words(b)))
    }

    fn next(&mut self) -> f32 {
        self.0.next_f32()
    }

    fn next2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
}

/// Veach's power heuristic (β = 2) for one sample of each of two strategies.
fn power_heuristic(a: f32, b: f32) -> f32 {
    MisHeuristic::Power.weight(a, b)
}

/// Transmittance across a height `dz` of the unit-extinction medium along `w`.
fn transmittance(dz: f32, w: Vec3) -> f32 {
    if dz.abs() <= f32::MIN_POSITIVE {
        1.0
    } else {
        (-(dz / w.z).abs()).exp()
    }
}

/// Russian roulette on a throughput `beta` after the fourth event (pbrt-v4's rule):
/// `None` when the walk ends, else the survival probability.
fn roulette(depth: u32, beta: Rgb, walk: &mut Walk) -> Option<f32> {
    let b = beta.max_component();
    if depth <= 3 || b >= 0.25 {
        return Some(1.0);
    }
    let q = (1.0 - b).max(0.0);
    (walk.next() >= q).then_some(1.0 - q)
}

impl Layered {
    fn coat_specular(&self) -> bool {
        self.coat.rough().is_none()
    }

    fn scatters(&self) -> bool {
        !self.albedo.is_black()
    }

    fn phase(&self) -> HenyeyGreenstein {
        HenyeyGreenstein::new(self.g)
    }

    /// The coating's lobe `lobe` sampled from `w`, kept only when it carries light.
    fn coat_lobe(&self, w: Vec3, u: Vec2, lobe: Lobe, mode: TransportMode) -> Option<BsdfSample> {
        self.coat
            .sample_lobe(w, u, lobe, mode)
            .filter(|s| s.pdf > 0.0 && s.wi.z != 0.0 && !s.weight.is_black())
    }

    /// One walk's estimate of f(wo, wi) without the coating's direct reflection (pbrt-v4's
    /// `LayeredBxDF::f` loop body, with the top as the entrance and exit interface).
    fn walk_eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode, walk: &mut Walk) -> Rgb {
        let mut f = Rgb::BLACK;
        // The walk in from wo, and the direction sampled in from wi for the estimates out
        // along it. When that one fails (a microfacet that totally reflects), only those
        // estimates are lost: the others, out along the walk's own directions, still count.
        let wos = self.coat_lobe(wo, walk.next2(), Lobe::Transmission, mode);
        let wis = self.coat_lobe(wi, walk.next2(), Lobe::Transmission, mode.adjoint());
        let Some(wos) = wos else {
            return f;
        };
        let (h, phase) = (self.thickness, self.phase());
        let (mut beta, mut z, mut w) = (wos.weight, h, wos.wi);
        // A next-event estimate at event `depth` stands for a walk that leaves at event
        // `depth + 1`: stopping one event early keeps eval's walks as long as sample's
        // (pbrt-v4 runs both to max_depth, so its f counts, behind a medium, walks one
        // event longer than its sampling can make: 0.8% more light, measured).
        for depth in 0..self.max_depth.saturating_sub(1) {
            let Some(survive) = roulette(depth, beta, walk) else {
                break;
            };
            beta = beta / survive;
            if !self.scatters() {
                z = if z == h { 0.0 } else { h };
                beta = beta * transmittance(h, w);
            } else {
                let dz = -(1.0 - walk.next()).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    continue;
                }
                if 0.0 < zp && zp < h {
                    // Scattering in the medium: out along wis, then on by the phase function
                    // and out along its direction, the two weighed against each other.
                    if let Some(wis) = &wis {
                        let wt = if self.coat_specular() {
                            1.0
                        } else {
                            power_heuristic(wis.pdf, phase.p(-w, -wis.wi))
                        };
                        let out = transmittance(zp - h, wis.wi) * wt * phase.p(-w, -wis.wi) / wis.wi.z.abs();
                        f += beta * self.albedo * wis.weight * out;
                    }
                    let (next, pdf) = phase.sample(-w, walk.next2());
                    if pdf <= 0.0 || next.z == 0.0 {
                        continue;
                    }
                    beta *= self.albedo;
                    (w, z) = (next, zp);
                    if w.z > 0.0 && !self.coat_specular() {
                        let f_exit = self.coat.eval(-w, wi, mode);
                        if !f_exit.is_black() {
                            let wt = power_heuristic(pdf, self.coat.pdf_lobe(wi, -w, Lobe::Transmission));
                            f += beta * f_exit * (transmittance(zp - h, w) * wt);
                        }
                    }
                    continue;
                }
                z = zp.clamp(0.0, h);
            }
            if z == h {
                // Back down off the coating's underside.
                let Some(s) = self.coat_lobe(-w, walk.next2(), Lobe::Reflection, mode) else {
                    break;
                };
                (beta, w) = (beta * s.weight, s.wi);
                continue;
            }
            // On the base: out along wis, then a bounce, and out along the bounce's direction.
            if let Some(wis) = wis.as_ref().filter(|_| !self.base.specular()) {
                let wt = if self.coat_specular() {
                    1.0
                } else {
                    power_heuristic(wis.pdf, self.base.pdf(-w, -wis.wi, mode))
                };
                let fb = self.base.eval(-w, -wis.wi, mode);
                f += beta * fb * wis.weight * (wt * transmittance(h, wis.wi));
            }
            let Some(s) = self.base.sample(-w, walk.next(), walk.next2(), mode) else {
                break;
            };
            (beta, w) = (beta * s.weight, s.wi);
            if !self.coat_specular() {
                let f_exit = self.coat.eval(-w, wi, mode);
                if !f_exit.is_black() {
                    let wt = if self.base.specular() {
                        1.0
                    } else {
                        power_heuristic(s.pdf, self.coat.pdf_lobe(wi, -w, Lobe::Transmission))
                    };
                    f += beta * f_exit * (transmittance(h, w) * wt);
                }
            }
        }
        f
    }

    /// The unscattered specular reflection's weight towards `wo`: the coating's F plus, over
    /// a smooth conductor, the light refracted in that bounces between the two as many
    /// times as a walk of `max_depth` events allows, (1 - F)² Σ_k (F F_c T²)^k F_c T².
    fn specular_weight(&self, wo: Vec3) -> Rgb {
        let f = fresnel_dielectric(wo.z, self.coat.eta);
        let mut weight = Rgb::splat(f);
        let LayerBase::Conductor(c) = &self.base else {
            return weight;
        };
        let Some(wt) = refract(wo, Vec3::Z, self.coat.eta).filter(|_| c.alpha.is_none()) else {
            return weight;
        };
        let t2 = transmittance(self.thickness, wt).powi(2);
        let inside = fresnel_dielectric(-wt.z, 1.0 / self.coat.eta);
        let once = c.fresnel(-wt.z) * t2;
        let round = once * inside;
        let (mut sum, mut power) = (Rgb::BLACK, Rgb::WHITE);
        // A walk that leaves after k reflections inside ends at event 2k + 1 (none before
        // event 1 can: with fewer than two events no light comes back out).
        let terms = if self.max_depth >= 2 {
            (self.max_depth - 2) / 2 + 1
        } else {
            0
        };
        for _ in 0..terms {
            sum += power;
            power *= round;
        }
        // (In radiance, 1/η² in and η² out cancel; in importance neither applies.)
        weight += once * sum * ((1.0 - f) * (1.0 - inside));
        weight
    }
}

impl BsdfModel for Layered {
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let n = self.samples.max(1);
        let mut walk = Walk::new(wo.to_array(), wi.to_array());
        let mut f = self.coat.eval(wo, wi, mode) * n as f32;
        for _ in 0..n {
            f += self.walk_eval(wo, wi, mode, &mut walk);
        }
        f / n as f32
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let n = self.samples.max(1);
        let mut walk = Walk::new(wi.to_array(), wo.to_array());
        let mut sum = n as f32 * self.coat.pdf_lobe(wo, wi, Lobe::Reflection);
        for _ in 0..n {
            let (Some(wos), Some(wis)) = (
                self.coat_lobe(wo, walk.next2(), Lobe::Transmission, mode),
                self.coat_lobe(wi, walk.next2(), Lobe::Transmission, mode.adjoint()),
            ) else {
                continue;
            };
            if self.coat_specular() {
                sum += self.base.pdf(-wos.wi, -wis.wi, mode);
                continue;
            }
            let Some(rs) = self.base.sample(-wos.wi, walk.next(), walk.next2(), mode) else {
                continue;
            };
            if self.base.specular() {
                sum += self.coat.pdf(-rs.wi, wi, mode);
            } else {
                // The base's density at the pair, and the coating's at the bounce, each
                // weighed against the other strategy for the same direction.
                let r_pdf = self.base.pdf(-wos.wi, -wis.wi, mode);
                let t_pdf = self.coat.pdf(-rs.wi, wi, mode);
                sum += power_heuristic(wis.pdf, r_pdf) * r_pdf + power_heuristic(rs.pdf, t_pdf) * t_pdf;
            }
        }
        0.1 / (2.0 * PI) + 0.9 * sum / n as f32
    }

    fn sample(&self, wo: Vec3, u: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let first = self.coat.sample(wo, u, u2, mode)?;
        if first.weight.is_black() || first.wi.z == 0.0 {
            return None;
        }
        if first.wi.z > 0.0 {
            let pdf = if first.delta {
                first.pdf
            } else {
                self.pdf(wo, first.wi, mode)
            };
            return Some(BsdfSample { pdf, ..first });
        }
        let mut walk = Walk::new(wo.to_array(), [u, u2.x, u2.y]);
        let (h, phase) = (self.thickness, self.phase());
        let (mut beta, mut pdf, mut delta) = (first.weight, first.pdf, first.delta);
        let (mut z, mut w) = (h, first.wi);
        for depth in 0..self.max_depth {
            let survive = roulette(depth, beta, &mut walk)?;
            (beta, pdf) = (beta / survive, pdf * survive);
            if self.scatters() {
                let dz = -(1.0 - walk.next()).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    return None;
                }
                if 0.0 < zp && zp < h {
                    let (next, p) = phase.sample(-w, walk.next2());
                    if p <= 0.0 || next.z == 0.0 {
                        return None;
                    }
                    (beta, pdf, delta) = (beta * self.albedo, pdf * p, false);
                    (w, z) = (next, zp);
                    continue;
                }
                z = zp.clamp(0.0, h);
            } else {
                z = if z == h { 0.0 } else { h };
                beta = beta * transmittance(h, w);
            }
            let s = if z == 0.0 {
                self.base.sample(-w, walk.next(), walk.next2(), mode)?
            } else {
                self.coat.sample(-w, walk.next(), walk.next2(), mode)?
            };
            if s.weight.is_black() || s.pdf <= 0.0 || s.wi.z == 0.0 {
                return None;
            }
            (beta, pdf, delta, w) = (beta * s.weight, pdf * s.pdf, delta && s.delta, s.wi);
            if z == h && w.z > 0.0 {
                // Out through the coating. (A delta walk's product of choices may underflow
                // to 0 after many events: it is still the walk's, and kept.)
                let pdf = if delta {
                    pdf.max(f32::MIN_POSITIVE)
                } else {
                    self.pdf(wo, w, mode)
                };
                return (pdf > 0.0).then_some(BsdfSample {
                    wi: w,
                    weight: beta,
                    pdf,
                    delta,
                    eta: 1.0,
                });
            }
        }
        None
    }

    fn specular_rays(&self, wo: Vec3, _mode: TransportMode, rays: &mut SpecularRays) {
        if wo.z > 0.0 && self.coat_specular() {
            rays.push(reflect_z(wo), self.specular_weight(wo));
        }
    }

    fn has_smooth(&self) -> bool {
        !self.coat_specular() || !self.base.specular() || self.scatters()
    }

    fn albedo(&self) -> Rgb {
        self.base.albedo()
    }

    fn stochastic(&self) -> bool {
        true
    }
}
