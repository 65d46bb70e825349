//! [`Spectrum`]: what a path carries per lane, its radiance, throughput and the values of
//! BSDFs and lights, as lane-generic shading code sees it. The RGB renderer carries three
//! channels ([`V3`], whose one-lane instance gives `Rgb`'s bits); spectral rendering
//! carries the values at a path's four sampled wavelengths ([`Sampled4`], pbrt-v4's
//! `SampledSpectrum` with four samples, "hero wavelength" sampling after Wilkie et al.
//! 2014). A kernel written over `S: Spectrum<R>` is one program for both: the payload is a
//! type parameter, not a second copy of the shading.
//!
//! Every operation but [`Spectrum::brightness`] and [`Spectrum::is_black`] (which weigh all
//! channels, for choices between lobes) acts channel by channel with the same
//! floating-point operations in the same order, so that a kernel's values in channel `i`
//! are those of the RGB run in the channel it holds (the kernels' tests check this).

use crate::lanes::{Choose, Real};
use crate::v3::V3;
use std::ops::{Add, Sub};

/// The channels a path carries in lanes of the [`Real`] type `R`.
pub trait Spectrum<R: Real>: Copy + Add<Output = Self> + Sub<Output = Self> + Choose<R> {
    /// How many channels: 3 for RGB, 4 for four sampled wavelengths.
    const CHANNELS: usize;
    /// Every channel `v`.
    fn splat(v: f32) -> Self;
    /// Channel `i` (below [`Spectrum::CHANNELS`]).
    fn channel(&self, i: usize) -> R;
    /// Channel `i`, to be written.
    fn channel_mut(&mut self, i: usize) -> &mut R;
    /// Every channel times `s`.
    #[inline(always)]
    fn scale(self, s: R) -> Self {
        let mut out = self;
        for i in 0..Self::CHANNELS {
            *out.channel_mut(i) = self.channel(i) * s;
        }
        out
    }
    /// Channel by channel product.
    #[inline(always)]
    fn mul_each(self, o: Self) -> Self {
        let mut out = self;
        for i in 0..Self::CHANNELS {
            *out.channel_mut(i) = self.channel(i) * o.channel(i);
        }
        out
    }
    /// Every channel over `s` (a division, no reciprocal).
    #[inline(always)]
    fn div_by(self, s: R) -> Self {
        let mut out = self;
        for i in 0..Self::CHANNELS {
            *out.channel_mut(i) = self.channel(i) / s;
        }
        out
    }
    /// Per lane: `t` where `mask` holds, else `f`.
    #[inline(always)]
    fn select(mask: R::Mask, t: Self, f: Self) -> Self {
        Choose::choose(mask, t, f)
    }
    /// Per lane: whether every channel is zero.
    #[inline(always)]
    fn is_black(self) -> R::Mask {
        let zero = R::splat(0.0);
        let mut black = self.channel(0).cmp_eq(zero);
        for i in 1..Self::CHANNELS {
            black = R::and(black, self.channel(i).cmp_eq(zero));
        }
        black
    }
    /// Per lane: how bright, as choices between lobes weigh it: the luminance of RGB (as
    /// `Rgb::luminance` sums it), the mean of wavelength samples.
    fn brightness(self) -> R;
    /// Per lane: the largest channel (as `Rgb::max_component` takes it).
    #[inline(always)]
    fn max_channel(self) -> R {
        let mut m = self.channel(0);
        for i in 1..Self::CHANNELS {
            m = m.max(self.channel(i));
        }
        m
    }
}

impl<R: Real> Spectrum<R> for V3<R> {
    const CHANNELS: usize = 3;

    #[inline(always)]
    fn splat(v: f32) -> Self {
        V3::splat(v)
    }

    #[inline(always)]
    fn brightness(self) -> R {
        self.luminance()
    }

    #[inline(always)]
    fn channel(&self, i: usize) -> R {
        match i {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }

    #[inline(always)]
    fn channel_mut(&mut self, i: usize) -> &mut R {
        match i {
            0 => &mut self.x,
            1 => &mut self.y,
            _ => &mut self.z,
        }
    }
}

/// A path's values at four sampled wavelengths, in lanes of `R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampled4<R>(pub [R; 4]);

impl<R: Real> Spectrum<R> for Sampled4<R> {
    const CHANNELS: usize = 4;

    #[inline(always)]
    fn splat(v: f32) -> Self {
        Sampled4([R::splat(v); 4])
    }

    #[inline(always)]
    fn brightness(self) -> R {
        (self.0[0] + self.0[1] + self.0[2] + self.0[3]) * R::splat(0.25)
    }

    #[inline(always)]
    fn channel(&self, i: usize) -> R {
        self.0[i]
    }

    #[inline(always)]
    fn channel_mut(&mut self, i: usize) -> &mut R {
        &mut self.0[i]
    }
}

impl<R: Real> Choose<R> for Sampled4<R> {
    #[inline(always)]
    fn choose(mask: R::Mask, a: Self, b: Self) -> Self {
        let mut out = a;
        for i in 0..4 {
            out.0[i] = R::select(mask, a.0[i], b.0[i]);
        }
        out
    }
}

impl<R: Real> Add for Sampled4<R> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        let mut out = self;
        for i in 0..4 {
            out.0[i] = self.0[i] + o.0[i];
        }
        out
    }
}

impl<R: Real> Sub for Sampled4<R> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        let mut out = self;
        for i in 0..4 {
            out.0[i] = self.0[i] - o.0[i];
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::{Lane8, F8};
    use crate::Rgb;

    /// Every operation of a four-channel payload gives, channel by channel, the floats of
    /// the RGB payload on the same values (channel 3 repeats channel 0).
    #[test]
    fn four_wavelengths_give_the_rgb_channels_floats() {
        let mut rng = crate::Pcg32::new(7, 1);
        let mut lanes = || F8::from_array(std::array::from_fn(|_| (rng.next_f32() - 0.3) * 4.0));
        for _ in 0..200 {
            let (a, b, s) = (
                V3::new(lanes(), lanes(), lanes()),
                V3::new(lanes(), lanes(), lanes()),
                lanes(),
            );
            let four = |v: V3<F8>| Sampled4([v.x, v.y, v.z, v.x]);
            let mask = s.cmp_gt(F8::splat(0.5));
            let pairs = [
                (Spectrum::scale(a, s), Spectrum::scale(four(a), s)),
                (Spectrum::mul_each(a, b), Spectrum::mul_each(four(a), four(b))),
                (Spectrum::div_by(a, s), Spectrum::div_by(four(a), s)),
                (a + b, four(a) + four(b)),
                (a - b, four(a) - four(b)),
                (Spectrum::select(mask, a, b), Spectrum::select(mask, four(a), four(b))),
            ];
            for (rgb, s4) in pairs {
                for i in 0..4 {
                    let bits = |x: F8| x.to_array().map(f32::to_bits);
                    assert_eq!(bits(rgb.channel(i % 3)), bits(s4.channel(i)), "channel {i}");
                }
            }
            // `Rgb::max_component`'s answer per lane.
            let rgb_max: [f32; 8] = std::array::from_fn(|k| {
                let v = a.lane(k);
                Rgb::new(v.x, v.y, v.z).max_component()
            });
            assert_eq!(a.max_channel().to_array(), rgb_max);
            assert_eq!(four(a).max_channel().to_array(), rgb_max);
            assert_eq!(F8::bits(Spectrum::is_black(a)), F8::bits(Spectrum::is_black(four(a))));
        }
    }
}
