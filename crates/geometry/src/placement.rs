//! The placement of a canonical shape in the world: an affine map and its inverse.

use glam::{Affine3A, Mat3A, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::{Aabb, Ray, Transform};

/// Object-to-world and world-to-object maps of one shape, with the normal matrix.
/// Rays are mapped to object space without renormalising the direction, so the ray
/// parameter `t` is the same in both spaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    to_world: Affine3A,
    to_object: Affine3A,
    normal: Mat3A,
}

impl Placement {
    pub fn new(t: &Transform) -> Self {
        let to_world = Affine3A::from_mat4(t.m);
        let to_object = Affine3A::from_mat4(t.inv);
        Placement {
            to_world,
            to_object,
            normal: to_object.matrix3.transpose(),
        }
    }

    /// The one-lane instance of the maps.
    #[inline(always)]
    pub fn lanes(&self) -> PlacementLanes<f32> {
        PlacementLanes {
            to_world: AffineLanes::of(&self.to_world.matrix3, self.to_world.translation.into()),
            to_object: AffineLanes::of(&self.to_object.matrix3, self.to_object.translation.into()),
            normal: AffineLanes::of(&self.normal, Vec3::ZERO),
        }
    }

    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        let (o, d) = self.lanes().ray_to_object(ray.origin.into(), ray.dir.into());
        Ray::new(o.into(), d.into())
    }

    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.lanes().to_world.point(p.into()).into()
    }

    /// A world-space vector from an object-space vector.
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.lanes().to_world.vector(v.into()).into()
    }

    /// A world-space unit normal from an object-space normal.
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        self.lanes().normal_to_world(n.into()).into()
    }

    pub fn bounds(&self, object: Aabb) -> Aabb {
        Transform {
            m: glam::Mat4::from(self.to_world),
            inv: glam::Mat4::from(self.to_object),
        }
        .bounds(object)
    }
}

/// An affine map in lanes of any [`Real`] type: its linear part's columns and its
/// translation, applied with the products and sums of glam's `Affine3A` in the same order,
/// so that the one-lane instance gives its bits.
#[derive(Clone, Copy, Debug)]
pub struct AffineLanes<R: Real> {
    pub x: V3<R>,
    pub y: V3<R>,
    pub z: V3<R>,
    pub t: V3<R>,
}

impl<R: Real> AffineLanes<R> {
    /// The image of the point `p`.
    #[inline(always)]
    pub fn point(&self, p: V3<R>) -> V3<R> {
        self.vector(p) + self.t
    }

    /// The image of the vector `v` (the linear part alone).
    #[inline(always)]
    pub fn vector(&self, v: V3<R>) -> V3<R> {
        self.x.scale(v.x) + self.y.scale(v.y) + self.z.scale(v.z)
    }
}

impl AffineLanes<f32> {
    fn of(m: &Mat3A, t: Vec3) -> Self {
        AffineLanes {
            x: Vec3::from(m.x_axis).into(),
            y: Vec3::from(m.y_axis).into(),
            z: Vec3::from(m.z_axis).into(),
            t: t.into(),
        }
    }

    /// Eight one-lane maps as one eight-lane map.
    #[inline(always)]
    pub fn gather<L: Lane8>(one: &[Self; 8]) -> AffineLanes<L> {
        AffineLanes {
            x: V3::gather(one, |a| a.x),
            y: V3::gather(one, |a| a.y),
            z: V3::gather(one, |a| a.z),
            t: V3::gather(one, |a| a.t),
        }
    }
}

/// A [`Placement`] in lanes: each lane its own shape's maps.
#[derive(Clone, Copy, Debug)]
pub struct PlacementLanes<R: Real> {
    pub to_world: AffineLanes<R>,
    pub to_object: AffineLanes<R>,
    /// The normal matrix (no translation).
    pub normal: AffineLanes<R>,
}

impl<R: Real> PlacementLanes<R> {
    /// The ray `(origin, dir)` in object space, the direction not renormalised.
    #[inline(always)]
    pub fn ray_to_object(&self, origin: V3<R>, dir: V3<R>) -> (V3<R>, V3<R>) {
        (self.to_object.point(origin), self.to_object.vector(dir))
    }

    /// A world-space unit normal from an object-space normal.
    #[inline(always)]
    pub fn normal_to_world(&self, n: V3<R>) -> V3<R> {
        self.normal.vector(n).try_normalize().0
    }
}

impl PlacementLanes<f32> {
    /// Eight one-lane placements as one eight-lane placement.
    #[inline(always)]
    pub fn gather<L: Lane8>(one: &[Self; 8]) -> PlacementLanes<L> {
        PlacementLanes {
            to_world: AffineLanes::gather(&one.map(|p| p.to_world)),
            to_object: AffineLanes::gather(&one.map(|p| p.to_object)),
            normal: AffineLanes::gather(&one.map(|p| p.normal)),
        }
    }
}
