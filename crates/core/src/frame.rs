//! Orthonormal frames: the local shading coordinate system (z = normal).

use crate::lanes::{Real, V3};
use glam::Vec3;

/// An orthonormal basis `(s, t, n)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// A frame around the unit vector `n`, after Duff et al., "Building an Orthonormal
    /// Basis, Revisited" (JCGT 2017): branchless and continuous except at one sign flip.
    pub fn from_normal(n: Vec3) -> Self {
        Basis::from_normal(V3::from(n)).into()
    }

    /// A frame around the unit vector `n` whose first axis is the tangent `t` made
    /// orthogonal to `n` (Gram-Schmidt); [`Frame::from_normal`] when `t` is zero or along `n`.
    pub fn from_normal_tangent(n: Vec3, t: Vec3) -> Self {
        Basis::from_normal_tangent(V3::from(n), V3::from(t)).into()
    }

    pub fn to_local(&self, v: Vec3) -> Vec3 {
        self.basis().to_local(v.into()).into()
    }

    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.basis().to_world(v.into()).into()
    }

    fn basis(&self) -> Basis<f32> {
        Basis {
            s: self.s.into(),
            t: self.t.into(),
            n: self.n.into(),
        }
    }
}

/// The one-lane basis as a frame (the same three vectors).
impl From<Basis<f32>> for Frame {
    #[inline(always)]
    fn from(b: Basis<f32>) -> Self {
        Frame {
            s: b.s.into(),
            t: b.t.into(),
            n: b.n.into(),
        }
    }
}

/// [`Frame::from_normal`]'s basis for lanes of any [`Real`] type.
#[derive(Clone, Copy, Debug)]
pub struct Basis<R> {
    pub s: V3<R>,
    pub t: V3<R>,
    pub n: V3<R>,
}

impl<R: Real> Basis<R> {
    /// Duff et al.'s basis around the unit vector `n` (see [`Frame::from_normal`]).
    #[inline(always)]
    pub fn from_normal(n: V3<R>) -> Self {
        let one = R::splat(1.0);
        let sign = one.copysign(n.z);
        let a = -one / (sign + n.z);
        let b = n.x * n.y * a;
        let s = V3::new(one + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = V3::new(b, sign + n.y * n.y * a, -n.y);
        Basis { s, t, n }
    }

    /// [`Frame::from_normal_tangent`]'s basis: `t` made orthogonal to `n` (Gram-Schmidt),
    /// or Duff et al.'s basis where that leaves no direction.
    #[inline(always)]
    pub fn from_normal_tangent(n: V3<R>, t: V3<R>) -> Self {
        let (s, ok) = (t - n.scale(n.dot(t))).try_normalize();
        let fallback = Basis::from_normal(n);
        Basis {
            s: V3::select(ok, s, fallback.s),
            t: V3::select(ok, n.cross(s), fallback.t),
            n,
        }
    }

    /// World vector `v` in this basis: (v·s, v·t, v·n).
    #[inline(always)]
    pub fn to_local(&self, v: V3<R>) -> V3<R> {
        V3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// `v` given in this basis, in world coordinates: s v.x + t v.y + n v.z.
    #[inline(always)]
    pub fn to_world(&self, v: V3<R>) -> V3<R> {
        self.s.scale(v.x) + self.t.scale(v.y) + self.n.scale(v.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orthonormal_and_round_trip() {
        for n in [
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::X,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!(f.s.dot(f.t).abs() < 1e-5 && f.s.dot(n).abs() < 1e-5 && f.t.dot(n).abs() < 1e-5);
            assert!((f.s.cross(f.t) - n).length() < 1e-5, "right-handed");
            let v = Vec3::new(0.2, 0.7, -0.1);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
        }
    }
}
