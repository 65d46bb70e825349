//! Analytic shapes and the ray-triangle test. Each shape is a closed-enum variant with
//! `bounds`, `intersect` (distance and shape coordinates) and `surface` (the full hit).
//!
//! Adding a shape: a new file with those three functions, one variant below and one arm
//! in each match. A shape's `surface` is the one-lane instance of its [`SurfaceKernel`],
//! written once over the lane type, which eight shapes of a kind gathered
//! ([`GatherSurface`]) run in eight lanes.

mod cuboid;
mod disk;
#[cfg(test)]
mod lanes_tests;
mod plane;
mod quad;
pub(crate) mod sphere;
pub mod triangle;
pub mod triangle4;
pub mod triangle_box;

pub use cuboid::{Cuboid, CuboidLanes};
pub use disk::Disk;
pub use plane::{Plane, PlaneLanes};
pub use quad::Quad;
pub use sphere::{Sphere, SphereLanes};

use crate::triangle_lanes::SurfaceLanes;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::{Aabb, Ray};

/// Where a ray meets a shape: distance and shape-specific coordinates.
pub type ShapeHit = (f32, Vec2);

/// The surface at a shape hit: position, unit outward normal, texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSurface {
    pub p: Vec3,
    pub n: Vec3,
    pub uv: Vec2,
    /// ∂p/∂u, the direction of increasing u (not normalised; zero where undefined).
    pub dpdu: Vec3,
}

/// A shape kind's surface at hits, in lanes of any [`Real`] type: lane `k` gives the bits
/// of the one-lane instance for lane `k`'s shape and hit.
pub trait SurfaceKernel<R: Real> {
    /// The surface where the ray `(origin, dir)` met the shape at `t`, with shape
    /// coordinates `uv` (the shape's normal as both `ng` and `ns`).
    fn surface(&self, origin: V3<R>, dir: V3<R>, t: R, uv: (R, R)) -> SurfaceLanes<R>;
}

/// A kind's one-lane surface kernel, eight of which make an eight-lane one.
pub trait GatherSurface: Copy {
    type Lanes<L: Lane8>: SurfaceKernel<L>;
    fn gather<L: Lane8>(one: &[Self; 8]) -> Self::Lanes<L>;
}

/// The one-lane kernel `k`'s surface at `hit` as a [`ShapeSurface`].
#[inline(always)]
fn one_lane(k: &impl SurfaceKernel<f32>, ray: &Ray, (t, uv): ShapeHit) -> ShapeSurface {
    let s = k.surface(ray.origin.into(), ray.dir.into(), t, (uv.x, uv.y));
    ShapeSurface {
        p: s.p.into(),
        n: s.ng.into(),
        uv: Vec2::new(s.uv.0, s.uv.1),
        dpdu: s.dpdu.into(),
    }
}

/// The surface of a flat shape `origin + a e1 + b e2` (quads, whose texture coordinates
/// are (a, b), and disks, whose unit disk maps to [0, 1]² by (0.5 (a + 1), 0.5 (b + 1))),
/// per lane.
#[derive(Clone, Copy)]
pub struct FlatLanes<R: Real> {
    pub origin: V3<R>,
    pub e1: V3<R>,
    pub e2: V3<R>,
    pub n: V3<R>,
    pub disk: R::Mask,
}

impl<R: Real> SurfaceKernel<R> for FlatLanes<R> {
    #[inline(always)]
    fn surface(&self, _origin: V3<R>, _dir: V3<R>, _t: R, (a, b): (R, R)) -> SurfaceLanes<R> {
        let (one, half) = (R::splat(1.0), R::splat(0.5));
        SurfaceLanes {
            p: self.origin + self.e1.scale(a) + self.e2.scale(b),
            ng: self.n,
            ns: self.n,
            uv: (
                R::select(self.disk, half * (a + one), a),
                R::select(self.disk, half * (b + one), b),
            ),
            dpdu: self.e1,
        }
    }
}

impl GatherSurface for FlatLanes<f32> {
    type Lanes<L: Lane8> = FlatLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> FlatLanes<L> {
        FlatLanes {
            origin: V3::gather(one, |s| s.origin),
            e1: V3::gather(one, |s| s.e1),
            e2: V3::gather(one, |s| s.e2),
            n: V3::gather(one, |s| s.n),
            disk: L::mask_of(one.map(|s| s.disk)),
        }
    }
}

/// Every analytic shape the renderer knows.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Sphere(Sphere),
    Plane(Plane),
    Quad(Quad),
    Disk(Disk),
    Cuboid(Cuboid),
}

impl Shape {
    pub fn bounds(&self) -> Aabb {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Plane(_) => Aabb::INFINITE,
            Shape::Quad(s) => s.bounds(),
            Shape::Disk(s) => s.bounds(),
            Shape::Cuboid(s) => s.bounds(),
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Plane(s) => s.intersect(ray, t_max),
            Shape::Quad(s) => s.intersect(ray, t_max),
            Shape::Disk(s) => s.intersect(ray, t_max),
            Shape::Cuboid(s) => s.intersect(ray, t_max),
        }
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ShapeSurface {
        match self {
            Shape::Sphere(s) => s.surface(ray, hit),
            Shape::Plane(s) => s.surface(ray, hit),
            Shape::Quad(s) => s.surface(ray, hit),
            Shape::Disk(s) => s.surface(ray, hit),
            Shape::Cuboid(s) => s.surface(ray, hit),
        }
    }
}

/// The ray parameter where `ray` meets the plane through `origin` with normal `n`, if it
/// lies in `(0, t_max)`. Shared by the flat shapes.
#[inline]
pub(crate) fn plane_hit(ray: &Ray, origin: Vec3, n: Vec3, t_max: f32) -> Option<f32> {
    let denom = n.dot(ray.dir);
    if denom == 0.0 {
        return None;
    }
    let t = n.dot(origin - ray.origin) / denom;
    (t > 0.0 && t < t_max).then_some(t)
}

/// The unit normal of the plane spanned by the world-space edges `e1`, `e2`, on the side of
/// `front` (the object-space front mapped by the normal transform, which a mirroring
/// transform does not flip), and the vector `w` that [`plane_coordinates`] needs; `None` if
/// the edges are parallel or zero.
#[inline]
pub(crate) fn plane_frame(e1: Vec3, e2: Vec3, front: Vec3) -> Option<(Vec3, Vec3)> {
    let cross = e1.cross(e2);
    let n = cross.try_normalize()?;
    Some((if n.dot(front) < 0.0 { -n } else { n }, cross / cross.length_squared()))
}

/// Coordinates `(a, b)` of the point `q` in the plane spanned by edges `e1`, `e2` at
/// `origin`, so that `q = origin + a e1 + b e2`. `w` is `(e1 x e2) / |e1 x e2|^2`.
#[inline]
pub(crate) fn plane_coordinates(q: Vec3, origin: Vec3, e1: Vec3, e2: Vec3, w: Vec3) -> Vec2 {
    let d = q - origin;
    Vec2::new(w.dot(d.cross(e2)), w.dot(e1.cross(d)))
}
