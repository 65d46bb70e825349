//! A BSDF's answers at one point in any payload `S` (RGB, or the values at a path's
//! wavelengths: [`crate::spectral::Tint`]): the kind's one-lane kernel, its colours turned
//! into `S` by their [`Role`]. The same kernels as every other use of the BSDF; only the
//! payload differs.

use super::{flip, Bsdf, BsdfKind, LaneKernel, Role, TransportMode};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::V3;
use penumbra_core::spectrum::Spectrum;

/// A direction drawn by [`Bsdf::sample_in`] (as [`super::BsdfSample`], the weight in `S`).
#[derive(Clone, Copy, Debug)]
pub struct SampleIn<S> {
    pub wi: Vec3,
    pub weight: S,
    pub pdf: f32,
    pub delta: bool,
    pub eta: f32,
}

impl<'a> Bsdf<'a> {
    /// Whether the kind has a kernel over any payload (blends and layered BSDFs do not
    /// yet).
    pub fn has_payload_kernel(&self) -> bool {
        !matches!(self.kind, BsdfKind::Blend(_) | BsdfKind::Layered(_))
    }

    /// `f` of the one-lane kernel with its colours turned into `S` by `to`; `None` for a
    /// kind without one ([`Bsdf::has_payload_kernel`]).
    fn with_kernel<S: Spectrum<f32>, O>(
        &self,
        mode: TransportMode,
        to: &impl Fn(Role, V3<f32>) -> S,
        f: impl FnOnce(&dyn LaneKernel<f32, S>) -> O,
    ) -> Option<O> {
        Some(match self.kind {
            BsdfKind::Diffuse(b) => f(&b.lanes(mode).with_spectrum(to)),
            BsdfKind::Conductor(b) => f(&b.lanes(mode).with_spectrum(to)),
            BsdfKind::Dielectric(b) => f(&b.lanes(mode).with_spectrum(to)),
            BsdfKind::Plastic(b) => f(&b.lanes(mode).with_spectrum(to)),
            BsdfKind::Phong(b) => f(&b.lanes(mode).with_spectrum(to)),
            BsdfKind::Blend(_) | BsdfKind::Layered(_) => return None,
        })
    }

    /// [`Bsdf::eval`] in `S` and [`Bsdf::pdf`] (the payload's channels weighing the
    /// choice between lobes), from one kernel.
    pub fn eval_pdf_in<S: Spectrum<f32>>(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        to: &impl Fn(Role, V3<f32>) -> S,
    ) -> Option<(S, f32)> {
        let (wo, wi) = if self.mirrored(wo) {
            (flip(wo), flip(wi))
        } else {
            (wo, wi)
        };
        self.with_kernel(mode, to, |k| {
            (k.eval(wo.into(), wi.into()), k.pdf(wo.into(), wi.into()))
        })
    }

    /// [`Bsdf::sample`] in `S`: `None` without a kernel, `Some(None)` where no usable
    /// direction was drawn.
    pub fn sample_in<S: Spectrum<f32>>(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
        to: &impl Fn(Role, V3<f32>) -> S,
    ) -> Option<Option<SampleIn<S>>> {
        let mirrored = self.mirrored(wo);
        let wo = if mirrored { flip(wo) } else { wo };
        self.with_kernel(mode, to, |k| {
            let s = k.sample(wo.into(), u_lobe, u.into());
            let wi: Vec3 = s.wi.into();
            let finite = (0..S::CHANNELS).all(|i| s.weight.channel(i).is_finite());
            (s.ok && s.pdf > 0.0 && finite && wi.is_finite()).then_some(SampleIn {
                wi: if mirrored { flip(wi) } else { wi },
                weight: s.weight,
                pdf: s.pdf,
                delta: s.delta,
                eta: s.eta,
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::microfacet::Ggx;
    use super::super::{Conductor, Dielectric, Diffuse, MetalFresnel};
    use super::*;
    use penumbra_core::{Pcg32, Rgb};

    /// In the RGB payload the answers are the scalar BSDF's, bit for bit (two-sided
    /// mirroring included).
    #[test]
    fn the_rgb_payload_gives_the_scalar_answers() {
        let rgb = |_: Role, c: V3<f32>| c;
        let kinds = [
            BsdfKind::Diffuse(Diffuse {
                reflectance: Rgb::new(0.2, 0.5, 0.8),
            }),
            BsdfKind::Conductor(Conductor {
                fresnel: MetalFresnel::Complex {
                    eta: Rgb::new(0.2, 0.9, 1.1),
                    k: Rgb::new(3.9, 2.4, 2.1),
                },
                specular: Rgb::WHITE,
                alpha: Ggx::new(0.3, 0.3),
            }),
            BsdfKind::Dielectric(Dielectric {
                eta: 1.5,
                reflectance: Rgb::WHITE,
                transmittance: Rgb::WHITE,
                alpha: Ggx::new(0.2, 0.1),
            }),
        ];
        let mut rng = Pcg32::new(2, 3);
        for kind in kinds {
            for two_sided in [false, true] {
                let b = Bsdf { kind, two_sided };
                for _ in 0..200 {
                    let mut dir =
                        || Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5).normalize();
                    let (wo, wi) = (dir(), dir());
                    let mode = TransportMode::Radiance;
                    let (f, pdf) = b.eval_pdf_in(wo, wi, mode, &rgb).unwrap();
                    assert_eq!(Rgb::from(f), b.eval(wo, wi, mode));
                    assert_eq!(pdf.to_bits(), b.pdf(wo, wi, mode).to_bits());
                    let (u_lobe, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
                    let a = b.sample_in(wo, u_lobe, u, mode, &rgb).unwrap();
                    let s = b.sample(wo, u_lobe, u, mode);
                    assert_eq!(a.is_some(), s.is_some());
                    if let (Some(a), Some(s)) = (a, s) {
                        assert_eq!(
                            (a.wi, Rgb::from(a.weight), a.pdf, a.delta),
                            (s.wi, s.weight, s.pdf, s.delta)
                        );
                    }
                }
            }
        }
    }
}
