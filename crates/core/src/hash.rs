//! Integer hashing: the source of every per-pixel, per-sample random decision.

/// The 64-bit finaliser of SplitMix64 (Steele et al. 2014): a bijective mixer whose
/// output bits each depend on every input bit.
#[inline]
pub fn mix64(mut x: u64) -> u64 {
    x ^= x >> 30;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// Hashes a sequence of words into one 64-bit value, order-sensitively.
#[inline]
pub fn hash_words(words: &[u64]) -> u64 {
    words.iter().fold(0x9e37_79b9_7f4a_7c15, |h, &w| {
        mix64(h ^ mix64(w.wrapping_add(0x632b_e59b_d9b4_e019)))
    })
}

/// A float in [0, 1) from the top 24 bits of a 32-bit value.
#[inline]
pub fn u32_to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}
