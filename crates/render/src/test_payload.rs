//! A test payload for the spectral-ready kernels (`penumbra_core::spectrum`): four
//! channels made of an RGB colour's three and its green one again, so that a kernel run
//! carrying it must give each channel the floats of the RGB run.

use penumbra_core::lanes::{Choose, Real, F8, V3};
use penumbra_core::spectrum::{Sampled4, Spectrum};

/// The channel of the RGB colour that each of [`Rgbg`]'s four channels holds.
pub(crate) const RGB_CHANNEL: [usize; 4] = [0, 1, 2, 1];

/// A four-channel payload for tests: the RGB channels and the green one again
/// (so that a kernel mixing up channels 0 and 3 shows), chosen between by the RGB
/// luminance (so that Phong's lobe choice is RGB's).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rgbg(pub Sampled4<F8>);

impl Rgbg {
    pub fn of(c: V3<F8>) -> Self {
        Rgbg(Sampled4([c.x, c.y, c.z, c.y]))
    }
}

impl std::ops::Add for Rgbg {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Rgbg(self.0 + o.0)
    }
}

impl std::ops::Sub for Rgbg {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Rgbg(self.0 - o.0)
    }
}

impl Choose<F8> for Rgbg {
    fn choose(mask: <F8 as Real>::Mask, a: Self, b: Self) -> Self {
        Rgbg(Choose::choose(mask, a.0, b.0))
    }
}

impl Spectrum<F8> for Rgbg {
    const CHANNELS: usize = 4;
    fn splat(v: f32) -> Self {
        Rgbg(Sampled4::splat(v))
    }
    fn channel(&self, i: usize) -> F8 {
        self.0 .0[i]
    }
    fn channel_mut(&mut self, i: usize) -> &mut F8 {
        &mut self.0 .0[i]
    }
    fn brightness(self) -> F8 {
        V3::new(self.0 .0[0], self.0 .0[1], self.0 .0[2]).luminance()
    }
}
