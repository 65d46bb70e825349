//! Independent uniform random numbers: a hash of the pixel, dimension and sample index.

use super::Key;
use crate::hash::{mix64, u32_to_unit};
use glam::Vec2;

#[inline]
pub(super) fn sample_1d(key: &Key) -> f32 {
    u32_to_unit(bits(key) as u32)
}

#[inline]
pub(super) fn sample_2d(key: &Key) -> Vec2 {
    let b = bits(key);
    Vec2::new(u32_to_unit(b as u32), u32_to_unit((b >> 32) as u32))
}

#[inline]
fn bits(key: &Key) -> u64 {
    mix64(key.pattern ^ key.index_hash)
}
