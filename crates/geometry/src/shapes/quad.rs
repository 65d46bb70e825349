//! The quad: a parallelogram `corner + a * edge1 + b * edge2`, a, b in [0, 1]. Affine
//! transforms map parallelograms to parallelograms, so placement is baked in.

use super::{one_lane, plane_coordinates, plane_frame, plane_hit, FlatLanes, ShapeHit, ShapeSurface};
use glam::Vec3;
use penumbra_core::{Aabb, Ray, Transform};

#[derive(Clone, Debug, PartialEq)]
pub struct Quad {
    corner: Vec3,
    edge1: Vec3,
    edge2: Vec3,
    n: Vec3,
    w: Vec3,
}

impl Quad {
    /// `None` if the edges are parallel or zero. The front (normal) is `edge1 x edge2`.
    pub fn new(corner: Vec3, edge1: Vec3, edge2: Vec3, to_world: &Transform) -> Option<Self> {
        let front = to_world.normal(edge1.cross(edge2));
        let (corner, edge1, edge2) = (to_world.point(corner), to_world.vector(edge1), to_world.vector(edge2));
        let (n, w) = plane_frame(edge1, edge2, front)?;
        Some(Quad {
            corner,
            edge1,
            edge2,
            n,
            w,
        })
    }

    pub fn bounds(&self) -> Aabb {
        let c = self.corner;
        Aabb::from_points([c, c + self.edge1, c + self.edge2, c + self.edge1 + self.edge2])
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = plane_hit(ray, self.corner, self.n, t_max)?;
        let ab = plane_coordinates(ray.at(t), self.corner, self.edge1, self.edge2, self.w);
        (ab.cmpge(glam::Vec2::ZERO).all() && ab.cmple(glam::Vec2::ONE).all()).then_some((t, ab))
    }

    /// The one-lane instance of the surface kernel.
    #[inline(always)]
    pub fn lanes(&self) -> FlatLanes<f32> {
        FlatLanes {
            origin: self.corner.into(),
            e1: self.edge1.into(),
            e2: self.edge2.into(),
            n: self.n.into(),
            disk: false,
        }
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ShapeSurface {
        one_lane(&self.lanes(), ray, hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_outside_and_uv() {
        let q = Quad::new(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y, &Transform::IDENTITY).unwrap();
        let ray = Ray::new(Vec3::new(1.5, 0.25, 1.0), Vec3::NEG_Z);
        let hit = q.intersect(&ray, f32::INFINITY).unwrap();
        assert_eq!(hit.0, 1.0);
        let s = q.surface(&ray, hit);
        assert!((s.uv - glam::Vec2::new(0.75, 0.25)).length() < 1e-6);
        assert_eq!(s.n, Vec3::Z);
        assert!(q
            .intersect(&Ray::new(Vec3::new(2.1, 0.5, 1.0), Vec3::NEG_Z), f32::INFINITY)
            .is_none());
        assert!(Quad::new(Vec3::ZERO, Vec3::X, Vec3::X * 2.0, &Transform::IDENTITY).is_none());
        // A mirror keeps the front: a quad facing +z, mirrored in x, still faces +z.
        let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
        assert_eq!(Quad::new(Vec3::ZERO, Vec3::X, Vec3::Y, &mirror).unwrap().n, Vec3::Z);
    }
}
