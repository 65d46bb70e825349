//! Free-flight sampling against a medium's majorant: tentative collisions along a ray
//! drawn with density σ_maj T_maj in one RGB channel (pbrt-v4's `SampleT_maj`; Woodcock
//! tracking). The caller decides at each collision whether it absorbs, scatters or is a
//! null collision (delta tracking) or only weighs it (ratio tracking).

use super::{Medium, Segment};
use glam::Vec3;
use penumbra_core::lanes::V3;
use penumbra_core::spectrum::Spectrum;
use penumbra_core::{Pcg32, Rgb};

/// What [`Tracker::step`] met, in the path's payload `S` (RGB by default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step<S = V3<f32>> {
    /// A tentative collision at distance `t`, where the majorant is `sigma_maj`; `t_maj`
    /// is the majorant transmittance exp(-∫σ_maj) since the previous collision (or the
    /// start), per channel.
    Collision { t: f32, sigma_maj: S, t_maj: S },
    /// No collision before `t_max`; `t_maj` is the majorant transmittance from the last
    /// collision (or the start) to `t_max`.
    End { t_maj: S },
}

/// The walk along one ray through one medium (unit direction, distances in scene units),
/// its values in the payload `S` (the medium's RGB majorants converted by `convert`).
pub struct Tracker<'a, S = V3<f32>> {
    segments: &'a [Segment],
    index: usize,
    t: f32,
    channel: usize,
    t_maj: S,
    convert: &'a dyn Fn(Rgb) -> S,
}

/// The RGB payload of an RGB colour.
fn rgb_payload(c: Rgb) -> V3<f32> {
    c.into()
}

impl<'a> Tracker<'a> {
    /// The walk from `origin` along the unit `dir` over `[0, t_max)` in `medium`, sampling
    /// distances by the majorant of RGB `channel` (0, 1 or 2); `buffer` holds the
    /// majorant's segments.
    pub fn new(
        medium: &Medium,
        (origin, dir, t_max): (Vec3, Vec3, f32),
        channel: usize,
        buffer: &'a mut Vec<Segment>,
    ) -> Self {
        Tracker::new_in(medium, (origin, dir, t_max), channel, buffer, &rgb_payload)
    }
}

impl<'a, S: Spectrum<f32>> Tracker<'a, S> {
    /// [`Tracker::new`] in the payload `S`: `convert` turns the medium's RGB majorants into
    /// it (a spectral path's values at its wavelengths), and `channel` is the payload's
    /// channel that draws the distances.
    pub fn new_in(
        medium: &Medium,
        (origin, dir, t_max): (Vec3, Vec3, f32),
        channel: usize,
        buffer: &'a mut Vec<Segment>,
        convert: &'a dyn Fn(Rgb) -> S,
    ) -> Self {
        medium.segments(origin, dir, t_max, buffer);
        Tracker {
            segments: buffer,
            index: 0,
            t: 0.0,
            channel,
            t_maj: S::splat(1.0),
            convert,
        }
    }

    /// The next tentative collision, or the end of the ray; `rng` gives the exponential
    /// draws (one per collision, one per segment passed without one).
    pub fn step(&mut self, rng: &mut Pcg32) -> Step<S> {
        while let Some(seg) = self.segments.get(self.index) {
            // Between segments the medium is empty (nothing to attenuate).
            self.t = self.t.max(seg.t0);
            let sigma_maj = (self.convert)(seg.sigma_maj);
            let sigma = sigma_maj.channel(self.channel);
            if sigma > 0.0 {
                let dt = -(1.0 - rng.next_f32()).ln() / sigma;
                if self.t + dt < seg.t1 {
                    self.t += dt;
                    let t_maj = self.t_maj.mul_each(attenuation_in(sigma_maj, dt));
                    self.t_maj = S::splat(1.0);
                    return Step::Collision {
                        t: self.t,
                        sigma_maj,
                        t_maj,
                    };
                }
            }
            self.t_maj = self.t_maj.mul_each(attenuation_in(sigma_maj, seg.t1 - self.t));
            self.t = seg.t1;
            self.index += 1;
        }
        Step::End { t_maj: self.t_maj }
    }
}

/// exp(-σ d) per channel; an infinite `d` counts as the largest float, so that a channel
/// with σ = 0 keeps 1 (pbrt-v4's rule).
pub fn attenuation(sigma: Rgb, d: f32) -> Rgb {
    attenuation_in(V3::from(sigma), d).into()
}

/// [`attenuation`] in any payload.
pub fn attenuation_in<S: Spectrum<f32>>(sigma: S, d: f32) -> S {
    let d = if d.is_finite() { d } else { f32::MAX };
    let mut out = sigma;
    for i in 0..S::CHANNELS {
        let s = sigma.channel(i);
        *out.channel_mut(i) = if s == 0.0 { 1.0 } else { (-s * d).exp() };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::Homogeneous;
    use crate::phase::Phase;
    use penumbra_testkit::{chi2_test, Grid2};

    /// The first collision's distance in a homogeneous medium has density σ e^{-σt}
    /// (chi-square over [0, 3/σ) with the rest in a last bin, 200,000 draws), for the
    /// channel the walk samples by; with no collision, the end's majorant transmittance is
    /// exp(-σ t_max) per channel.
    #[test]
    fn free_flights_are_exponential() {
        let m = Medium::Homogeneous(Homogeneous {
            sigma_a: Rgb::new(0.5, 1.0, 0.0),
            sigma_s: Rgb::new(1.5, 0.2, 0.0),
            phase: Phase::Isotropic,
        });
        for (c, sigma) in [(0usize, 2.0f64), (1, 1.2)] {
            let mut rng = Pcg32::new(7, c as u64);
            let mut buffer = Vec::new();
            let t_max = 3.0 / sigma as f32;
            let mut ends = 0usize;
            let r = chi2_test(
                Grid2 {
                    min: [0.0, 0.0],
                    max: [t_max as f64, 1.0],
                    bins: [30, 1],
                },
                200_000,
                || {
                    let mut walk = Tracker::new(&m, (Vec3::ZERO, Vec3::Z, t_max), c, &mut buffer);
                    match walk.step(&mut rng) {
                        Step::Collision { t, t_maj, .. } => {
                            let expected = (-(sigma as f32) * t).exp();
                            assert!((t_maj.channel(c) - expected).abs() < 1e-5);
                            Some([t as f64, 0.5])
                        }
                        Step::End { t_maj } => {
                            ends += 1;
                            let want = m.at(Vec3::ZERO).sigma_t().map(|s| (-s * t_max).exp());
                            assert!((Rgb::from(t_maj) - want).max_component().abs() < 1e-6);
                            None
                        }
                    }
                },
                |[t, _]| sigma * (-sigma * t).exp(),
            );
            r.assert_fits(&format!("channel {c}"), 2);
            // P(no collision) = e^-3 = 0.0498; standard error of the fraction ~ 4.9e-4.
            let fraction = ends as f64 / 200_000.0;
            assert!((fraction - (-3.0f64).exp()).abs() < 4.0 * 4.9e-4, "{fraction}");
        }
    }

    /// A channel whose majorant is zero never stops the walk, and over an infinite ray
    /// its transmittance stays 1 while the others' go to 0.
    #[test]
    fn a_clear_channel_passes_infinite_rays() {
        let m = Medium::Homogeneous(Homogeneous {
            sigma_a: Rgb::new(0.0, 1.0, 0.0),
            sigma_s: Rgb::BLACK,
            phase: Phase::Isotropic,
        });
        let mut buffer = Vec::new();
        let mut walk = Tracker::new(&m, (Vec3::ZERO, Vec3::X, f32::INFINITY), 0, &mut buffer);
        let step = walk.step(&mut Pcg32::new(1, 1));
        assert_eq!(
            step,
            Step::End {
                t_maj: V3::new(1.0, 0.0, 1.0)
            }
        );
    }
}
