//! Affine transforms of points, vectors and normals.

use crate::Aabb;
use glam::{Mat3, Mat4, Vec3};

/// An affine transform with its inverse, so that normals and inverse mappings are cheap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub m: Mat4,
    pub inv: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        m: Mat4::IDENTITY,
        inv: Mat4::IDENTITY,
    };

    /// A transform from a matrix; `None` when the matrix is singular or not affine.
    pub fn from_matrix(m: Mat4) -> Option<Self> {
        let affine = m.row(3).abs_diff_eq(glam::Vec4::W, 1e-6);
        let det = m.determinant();
        (affine && det.is_finite() && det.abs() > 1e-12).then(|| Transform { m, inv: m.inverse() })
    }

    pub fn translate(t: Vec3) -> Self {
        Transform {
            m: Mat4::from_translation(t),
            inv: Mat4::from_translation(-t),
        }
    }

    /// A scale; `None` if any factor is zero or its inverse is not a finite number.
    pub fn scale(s: Vec3) -> Option<Self> {
        let inv = s.recip();
        (s.is_finite() && inv.is_finite() && s.cmpne(Vec3::ZERO).all()).then(|| Transform {
            m: Mat4::from_scale(s),
            inv: Mat4::from_scale(inv),
        })
    }

    /// A rotation by `degrees` about `axis` (right-handed); `None` for a zero axis.
    pub fn rotate(axis: Vec3, degrees: f32) -> Option<Self> {
        let axis = axis.try_normalize()?;
        let m = Mat4::from_axis_angle(axis, degrees.to_radians());
        Some(Transform { m, inv: m.transpose() })
    }

    /// The camera-to-world transform of a camera at `eye` looking at `target`: the camera
    /// looks down its local -z axis with +y up (OpenGL convention). `None` when the view
    /// direction is zero or parallel to `up`.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Option<Self> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let true_up = right.cross(forward);
        let m = Mat4::from_cols(
            right.extend(0.0),
            true_up.extend(0.0),
            (-forward).extend(0.0),
            eye.extend(1.0),
        );
        Transform::from_matrix(m)
    }

    /// The transform that applies `self` first and then `outer`.
    pub fn then(self, outer: Transform) -> Transform {
        Transform {
            m: outer.m * self.m,
            inv: self.inv * outer.inv,
        }
    }

    pub fn inverse(self) -> Transform {
        Transform {
            m: self.inv,
            inv: self.m,
        }
    }

    pub fn is_identity(&self) -> bool {
        self.m == Mat4::IDENTITY
    }

    pub fn point(&self, p: Vec3) -> Vec3 {
        self.m.transform_point3(p)
    }

    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3(v)
    }

    /// Transforms a normal by the inverse transpose (not normalised).
    pub fn normal(&self, n: Vec3) -> Vec3 {
        Mat3::from_mat4(self.inv).transpose() * n
    }

    /// True when the transform flips handedness (negative determinant).
    pub fn swaps_handedness(&self) -> bool {
        Mat3::from_mat4(self.m).determinant() < 0.0
    }

    /// A box containing the image of `b`.
    pub fn bounds(&self, b: Aabb) -> Aabb {
        // Arvo 1990, "Transforming Axis-Aligned Bounding Boxes" (Graphics Gems).
        let m = Mat3::from_mat4(self.m);
        let t = self.m.w_axis.truncate();
        let (mut lo, mut hi) = (t, t);
        for col in 0..3 {
            let axis = m.col(col);
            let a = axis * b.min[col];
            let c = axis * b.max[col];
            lo += a.min(c);
            hi += a.max(c);
        }
        Aabb { min: lo, max: hi }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compose_and_invert() {
        let t = Transform::scale(Vec3::new(2.0, 1.0, 0.5))
            .unwrap()
            .then(Transform::rotate(Vec3::Y, 30.0).unwrap())
            .then(Transform::translate(Vec3::new(1.0, 2.0, 3.0)));
        let p = Vec3::new(0.3, -1.0, 4.0);
        assert!((t.inverse().point(t.point(p)) - p).length() < 1e-5);
        // Scale first, then rotate, then translate.
        let q = Transform::rotate(Vec3::Y, 30.0)
            .unwrap()
            .point(p * Vec3::new(2.0, 1.0, 0.5))
            + Vec3::new(1.0, 2.0, 3.0);
        assert!((t.point(p) - q).length() < 1e-5);
    }

    #[test]
    fn normals_stay_perpendicular() {
        let t = Transform::scale(Vec3::new(3.0, 1.0, 1.0))
            .unwrap()
            .then(Transform::rotate(Vec3::Z, 45.0).unwrap());
        let (tangent, n) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));
        assert!(t.vector(tangent).dot(t.normal(n)).abs() < 1e-5);
    }

    #[test]
    fn bounds_contain_corners() {
        let t = Transform::rotate(Vec3::new(1.0, 2.0, 3.0), 37.0)
            .unwrap()
            .then(Transform::translate(Vec3::X));
        let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 2.5));
        let tb = t.bounds(b);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            let p = t.point(c);
            assert!(p.cmpge(tb.min - 1e-5).all() && p.cmple(tb.max + 1e-5).all());
        }
    }

    #[test]
    fn look_at_degenerate() {
        assert!(Transform::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y).is_none());
        assert!(Transform::look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y).is_none());
        let t = Transform::look_at(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y).unwrap();
        assert!(t.is_identity() || (t.m - Mat4::IDENTITY).abs_diff_eq(Mat4::ZERO, 1e-6));
    }
}
