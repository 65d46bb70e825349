//! The brute-force accelerator: every primitive, every ray. The reference the others are
//! tested against.

use super::{Accel, PrimitiveSet};
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

impl<P: PrimitiveSet> Accel for List<P> {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut closest = None;
        let mut t_max = t_max;
        for i in 0..self.prims.len() as u32 {
            if let Some(hit) = self.prims.intersect(i, ray, t_max) {
                t_max = hit.t;
                closest = Some(hit);
            }
        }
        closest
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        (0..self.prims.len() as u32).any(|i| self.prims.occluded(i, ray, t_max))
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }
}
