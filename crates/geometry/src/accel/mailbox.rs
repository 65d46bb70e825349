//! Mailboxing (Amanatides and Woo 1987; Kirk and Arvo 1991): an accelerator that stores a
//! primitive in several cells remembers, per ray, which primitives it has tested, so each
//! (ray, primitive) pair is tested at most once. The marks live in a per-thread pool of
//! stamp arrays: a query takes one (nested queries, as through instances, take another),
//! stamps it with a fresh ray number, and gives it back.

use super::{Counter, PrimitiveSet, Traverse};
use crate::Hit;
use penumbra_core::{Aabb, Ray};
use std::cell::RefCell;

struct Mailbox {
    ray: u32,
    marks: Vec<u32>,
}

impl Mailbox {
    /// True the first time `prim` is offered during this query, false after.
    #[inline]
    fn first_visit(&mut self, prim: u32) -> bool {
        let m = &mut self.marks[prim as usize];
        if *m == self.ray {
            false
        } else {
            *m = self.ray;
            true
        }
    }
}

/// The visitor a [`CellWalk`] calls with each cell's primitives and the distance at which
/// the ray leaves the cell; it returns the closest hit distance found so far, or
/// `f32::NEG_INFINITY` to end the walk.
pub type CellVisitor<'a, C> = dyn FnMut(&[u32], f32, &mut C) -> f32 + 'a;

/// A spatial subdivision that may list a primitive in several cells and hands the cells
/// along a ray to a visitor, nearest first. The walk ends once the closest distance the
/// visitor reports lies within the cell just visited: nothing nearer can remain.
pub trait CellWalk: Send + Sync {
    type Prims: PrimitiveSet;
    fn prims(&self) -> &Self::Prims;
    fn walk<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>);
    /// Bounds of everything in the structure.
    fn extent(&self) -> Aabb;
    /// Bytes the structure holds, not counting the primitives.
    fn bytes(&self) -> usize;
}

/// A cell walk answers every query: closest and any hit with mailboxing, written once.
impl<W: CellWalk> Traverse for W {
    fn closest<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        closest_in_cells(self, ray, t_max, stats)
    }
    fn any_hit(&self, ray: &Ray, t_max: f32) -> bool {
        occluded_in_cells(self, ray, t_max)
    }
    fn extent(&self) -> Aabb {
        CellWalk::extent(self)
    }
    fn bytes(&self) -> usize {
        CellWalk::bytes(self)
    }
    fn prim_bytes(&self) -> usize {
        self.prims().memory_bytes()
    }
}

/// The closest hit of a cell walk, each primitive tested at most once.
pub fn closest_in_cells<W: CellWalk, C: Counter>(w: &W, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
    let prims = w.prims();
    let data = prims.prepare(ray);
    with_mailbox(prims.len(), |mailbox| {
        let mut best: Option<Hit> = None;
        w.walk(ray, t_max, stats, &mut |items, _, stats| {
            for &i in items {
                if mailbox.first_visit(i) {
                    stats.prims(1);
                    if let Some(hit) = prims.intersect(i, ray, &data, best.map_or(t_max, |h| h.t)) {
                        best = Some(hit);
                    }
                }
            }
            best.map_or(f32::INFINITY, |h| h.t)
        });
        best
    })
}

/// Whether anything blocks `ray` before `t_max`, by a cell walk.
pub fn occluded_in_cells<W: CellWalk>(w: &W, ray: &Ray, t_max: f32) -> bool {
    let prims = w.prims();
    let data = prims.prepare(ray);
    with_mailbox(prims.len(), |mailbox| {
        let mut hit = false;
        w.walk(ray, t_max, &mut (), &mut |items, _, _| {
            hit = items
                .iter()
                .any(|&i| mailbox.first_visit(i) && prims.occluded(i, ray, &data, t_max));
            if hit {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            }
        });
        hit
    })
}

thread_local! {
    static POOL: RefCell<Vec<Mailbox>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with a mailbox for `prims` primitives that has no marks yet.
fn with_mailbox<R>(prims: usize, f: impl FnOnce(&mut Mailbox) -> R) -> R {
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
