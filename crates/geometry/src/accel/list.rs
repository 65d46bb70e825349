//! The brute-force accelerator: every primitive, every ray. The reference the others are
//! tested against.

use super::{Counter, PrimitiveSet, Traverse};
use crate::Hit;
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

pub struct List<P> {
    prims: Arc<P>,
    bounds: Aabb,
}

impl<P: PrimitiveSet> List<P> {
    pub fn new(prims: Arc<P>) -> Self {
        let bounds = (0..prims.len() as u32).fold(Aabb::EMPTY, |b, i| b.union(prims.bounds(i)));
        List { prims, bounds }
    }
}

/// The closest hit among primitives `ids` of `prims`, counting the tests.
#[inline]
pub fn closest_of<P: PrimitiveSet, C: Counter>(
    prims: &P,
    ids: impl Iterator<Item = u32>,
    ray: &Ray,
    mut t_max: f32,
    stats: &mut C,
) -> Option<Hit> {
    let mut closest = None;
    let data = prims.prepare(ray);
    for i in ids {
        stats.prims(1);
        if let Some(hit) = prims.intersect(i, ray, &data, t_max) {
            t_max = hit.t;
            closest = Some(hit);
        }
    }
    closest
}

impl<P: PrimitiveSet> Traverse for List<P> {
    fn closest<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        closest_of(self.prims.as_ref(), 0..self.prims.len() as u32, ray, t_max, stats)
    }

    fn any_hit(&self, ray: &Ray, t_max: f32) -> bool {
        let data = self.prims.prepare(ray);
        (0..self.prims.len() as u32).any(|i| self.prims.occluded(i, ray, &data, t_max))
    }

    fn extent(&self) -> Aabb {
        self.bounds
    }

    fn prim_bytes(&self) -> usize {
        self.prims.memory_bytes()
    }

    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
    }
}
