//! Mailboxing (Amanatides and Woo 1987; Kirk and Arvo 1991): an accelerator that stores a
//! primitive in several cells remembers, per ray, which primitives it has tested, so each
//! (ray, primitive) pair is tested at most once. The marks live in a per-thread pool of
//! stamp arrays: a query takes one (nested queries, as through instances, take another),
//! stamps it with a fresh ray number, and gives it back.

use super::{Counter, PrimitiveSet};
use crate::Hit;
use penumbra_core::Ray;
use std::cell::RefCell;

pub struct Mailbox {
    ray: u32,
    marks: Vec<u32>,
}

impl Mailbox {
    /// True the first time `prim` is offered during this query, false after.
    #[inline]
    pub fn first_visit(&mut self, prim: u32) -> bool {
        let m = &mut self.marks[prim as usize];
        if *m == self.ray {
            false
        } else {
            *m = self.ray;
            true
        }
    }
}

impl Mailbox {
    /// Tests the primitives of `items` that this query has not tested yet, keeping the
    /// closest hit below `t_max` in `best`.
    #[allow(clippy::too_many_arguments)]
    pub fn closest_in<P: PrimitiveSet, C: Counter>(
        &mut self,
        prims: &P,
        items: &[u32],
        ray: &Ray,
        data: &P::RayData,
        t_max: f32,
        best: &mut Option<Hit>,
        stats: &mut C,
    ) {
        for &i in items {
            if self.first_visit(i) {
                stats.prims(1);
                if let Some(hit) = prims.intersect(i, ray, data, best.map_or(t_max, |h| h.t)) {
                    *best = Some(hit);
                }
            }
        }
    }

    /// Whether a primitive of `items` that this query has not tested yet blocks `ray`.
    pub fn any_in<P: PrimitiveSet>(
        &mut self,
        prims: &P,
        items: &[u32],
        ray: &Ray,
        data: &P::RayData,
        t_max: f32,
    ) -> bool {
        items
            .iter()
            .any(|&i| self.first_visit(i) && prims.occluded(i, ray, data, t_max))
    }
}

thread_local! {
    static POOL: RefCell<Vec<Mailbox>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with a mailbox for `prims` primitives that has no marks yet.
pub fn with_mailbox<R>(prims: usize, f: impl FnOnce(&mut Mailbox) -> R) -> R {
    let mut mb = POOL.with(|p| p.borrow_mut().pop()).unwrap_or(Mailbox {
        ray: 0,
        marks: Vec::new(),
    });
    if mb.marks.len() < prims {
        mb.marks.resize(prims, mb.ray);
    }
    mb.ray = mb.ray.wrapping_add(1);
    if mb.ray == 0 {
        // The stamp wrapped: old marks could now match, so clear them.
        mb.marks.iter_mut().for_each(|m| *m = u32::MAX);
        mb.ray = 1;
    }
    let result = f(&mut mb);
    POOL.with(|p| p.borrow_mut().push(mb));
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_once_per_query_and_nests() {
        with_mailbox(10, |outer| {
            assert!(outer.first_visit(3));
            assert!(!outer.first_visit(3));
            with_mailbox(10, |inner| {
                assert!(inner.first_visit(3), "a nested query has its own marks");
            });
            assert!(!outer.first_visit(3));
        });
        with_mailbox(10, |next| assert!(next.first_visit(3), "a new query starts clean"));
    }
}
