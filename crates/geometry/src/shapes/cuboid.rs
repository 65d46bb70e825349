//! The box: an axis-aligned box in object space, placed by any affine transform. Hit by
//! the slab test; the face is the one whose slab the hit lies on.

use super::{one_lane, GatherSurface, ShapeHit, ShapeSurface, SurfaceKernel};
use crate::placement::PlacementLanes;
use crate::triangle_lanes::SurfaceLanes;
use crate::Placement;
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, Real, V3};
use penumbra_core::{Aabb, Ray, Transform};

#[derive(Clone, Debug, PartialEq)]
pub struct Cuboid {
    local: Aabb,
    placement: Placement,
}

impl Cuboid {
    /// `None` if the box has no volume.
    pub fn new(min: Vec3, max: Vec3, to_world: &Transform) -> Option<Self> {
        let local = Aabb::new(min, max);
        (local.extent().cmpgt(Vec3::ZERO).all()).then(|| Cuboid {
            local,
            placement: Placement::new(to_world),
        })
    }

    pub fn bounds(&self) -> Aabb {
        self.placement.bounds(self.local)
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let r = self.placement.ray_to_object(ray);
        let inv = r.dir.recip();
        let t0 = (self.local.min - r.origin) * inv;
        let t1 = (self.local.max - r.origin) * inv;
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element();
        if near > far {
            return None;
        }
        let t = if near > 0.0 { near } else { far };
        (t > 0.0 && t < t_max).then_some((t, Vec2::ZERO))
    }

    /// The one-lane instance of the surface kernel.
    #[inline(always)]
    pub fn lanes(&self) -> CuboidLanes<f32> {
        CuboidLanes {
            placement: self.placement.lanes(),
            min: self.local.min.into(),
            max: self.local.max.into(),
            centroid: self.local.centroid().into(),
            half: (0.5 * self.local.extent()).into(),
        }
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ShapeSurface {
        one_lane(&self.lanes(), ray, hit)
    }
}

/// Boxes' surfaces: each lane its own placement and object-space box (with its centre and
/// half size).
#[derive(Clone, Copy, Debug)]
pub struct CuboidLanes<R: Real> {
    pub placement: PlacementLanes<R>,
    pub min: V3<R>,
    pub max: V3<R>,
    pub centroid: V3<R>,
    pub half: V3<R>,
}

impl<R: Real> SurfaceKernel<R> for CuboidLanes<R> {
    #[inline(always)]
    fn surface(&self, origin: V3<R>, dir: V3<R>, t: R, _: (R, R)) -> SurfaceLanes<R> {
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let (o, d) = self.placement.ray_to_object(origin, dir);
        let local = o + d.scale(t);
        // The face is the axis along which the point is furthest out, relative to the half
        // size (the first of equal ones, as `Vec3::max_position`).
        let c = local - self.centroid;
        let dd = V3::new(c.x / self.half.x, c.y / self.half.y, c.z / self.half.z);
        let (ax, ay, az) = (dd.x.abs(), dd.y.abs(), dd.z.abs());
        let is_y = ay.cmp_gt(ax);
        let z_axis = az.cmp_gt(R::select(is_y, ay, ax));
        let y_axis = R::and(is_y, R::not(z_axis));
        let x_axis = R::not(R::or(y_axis, z_axis));
        let on_axis = |v: V3<R>| R::select(z_axis, v.z, R::select(y_axis, v.y, v.x));
        let sign = one.copysign(on_axis(dd));
        let n = V3::new(
            R::select(x_axis, sign, zero),
            R::select(y_axis, sign, zero),
            R::select(z_axis, sign, zero),
        );
        // The point's offset in the box, 0 to 1 along each axis of positive extent.
        let (e, off) = (self.max - self.min, local - self.min);
        let rel = |o: R, e: R| R::select(e.cmp_gt(zero), o / e, zero);
        let rel = V3::new(rel(off.x, e.x), rel(off.y, e.y), rel(off.z, e.z));
        // u runs along z on the x faces, along x on the others.
        let uv = (R::select(x_axis, rel.z, rel.x), R::select(y_axis, rel.z, rel.y));
        let face = R::select(sign.cmp_gt(zero), on_axis(self.max), on_axis(self.min));
        let p = V3::new(
            R::select(x_axis, face, local.x),
            R::select(y_axis, face, local.y),
            R::select(z_axis, face, local.z),
        );
        let du = V3::new(R::select(x_axis, zero, one), zero, R::select(x_axis, one, zero));
        let n = self.placement.normal_to_world(n);
        SurfaceLanes {
            p: self.placement.to_world.point(p),
            ng: n,
            ns: n,
            uv,
            dpdu: self.placement.to_world.vector(du),
        }
    }
}

impl GatherSurface for CuboidLanes<f32> {
    type Lanes<L: Lane8> = CuboidLanes<L>;
    #[inline(always)]
    fn gather<L: Lane8>(one: &[Self; 8]) -> CuboidLanes<L> {
        CuboidLanes {
            placement: PlacementLanes::gather(&one.map(|c| c.placement)),
            min: V3::gather(one, |c| c.min),
            max: V3::gather(one, |c| c.max),
            centroid: V3::gather(one, |c| c.centroid),
            half: V3::gather(one, |c| c.half),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_and_inside() {
        let b = Cuboid::new(Vec3::splat(-1.0), Vec3::ONE, &Transform::IDENTITY).unwrap();
        let ray = Ray::new(Vec3::new(0.2, 5.0, 0.3), Vec3::NEG_Y);
        let hit = b.intersect(&ray, f32::INFINITY).unwrap();
        assert_eq!(hit.0, 4.0);
        assert_eq!(b.surface(&ray, hit).n, Vec3::Y);
        let inside = Ray::new(Vec3::ZERO, Vec3::X);
        let hit = b.intersect(&inside, f32::INFINITY).unwrap();
        assert_eq!(hit.0, 1.0);
        assert_eq!(b.surface(&inside, hit).n, Vec3::X);
        assert!(b
            .intersect(&Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::X), f32::INFINITY)
            .is_none());
        assert!(Cuboid::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0), &Transform::IDENTITY).is_none());
    }

    #[test]
    fn rotated_box() {
        let rot = Transform::rotate(Vec3::Y, 45.0).unwrap();
        let b = Cuboid::new(Vec3::splat(-1.0), Vec3::ONE, &rot).unwrap();
        let ray = Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::NEG_X);
        let hit = b.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.0 - (5.0 - 2f32.sqrt())).abs() < 1e-5);
    }
}
