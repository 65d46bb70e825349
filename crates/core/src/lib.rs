//! Penumbra core: the math, colour, random numbers and samplers every other layer builds on.
//!
//! Vectors and matrices come from [`glam`]; this crate adds what a renderer needs on top:
//! rays with robust origin offsets, bounding boxes, orthonormal frames, affine transforms,
//! linear RGB colour, a PCG32 generator and deterministic per-pixel samplers.

pub mod alias;
pub mod bounds;
pub mod color;
pub mod distribution;
pub mod distribution2d;
pub mod frame;
pub mod hash;
pub mod lanes;
pub mod lanes_avx;
pub mod ray;
pub mod rng;
pub mod samplers;
pub mod simd;
pub mod spectral;
pub mod spectrum;
pub mod spherical;
pub mod transform;
pub mod trig;
mod v3;
pub mod warp;

pub use bounds::Aabb;
pub use color::Rgb;
pub use distribution::Distribution1D;
pub use distribution2d::{Distribution2D, Draw};
pub use frame::Frame;
pub use glam::{Mat3, Mat4, UVec2, Vec2, Vec3};
pub use ray::Ray;
pub use rng::Pcg32;
pub use samplers::{Draws, PixelSampler, SamplerKind};
pub use transform::Transform;
