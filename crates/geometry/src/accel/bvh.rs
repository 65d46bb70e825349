//! Bounding volume hierarchy with a binned surface-area-heuristic build (Wald, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies", 2007), built in parallel over
//! subtrees, flattened depth-first into 32-byte nodes, traversed nearest child first.

use super::{Accel, Counter, PrimitiveSet, TraversalStats};
use crate::Hit;
use glam::Vec3;
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

const BINS: usize = 16;
/// Leaves hold at most this many primitives unless their centroids coincide.
const MAX_LEAF: usize = 4;
/// Largest leaf of primitives whose centroids all coincide (they cannot be split by position).
const MAX_COINCIDENT_LEAF: usize = 64;
/// Subtrees with more primitives than this are built on another thread.
const PARALLEL_THRESHOLD: usize = 4096;
/// SAH costs of a node traversal and a primitive test.
const TRAVERSAL_COST: f32 = 1.0;
const INTERSECT_COST: f32 = 1.0;

/// A flattened node: an interior node's first child follows it, `offset` is its second
/// child; a leaf (`count > 0`) holds primitives `order[offset..offset + count]`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    min: [f32; 3],
    offset: u32,
    max: [f32; 3],
    count: u16,
    axis: u16,
}

pub struct Bvh<P> {
    prims: Arc<P>,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

#[derive(Clone, Copy)]
struct PrimInfo {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

impl<P: PrimitiveSet> Bvh<P> {
    pub fn new(prims: Arc<P>) -> Self {
        let mut info: Vec<PrimInfo> = (0..prims.len() as u32)
            .map(|index| {
                let bounds = prims.bounds(index);
                PrimInfo {
                    bounds,
                    centroid: bounds.centroid(),
                    index,
                }
            })
            .collect();
        let nodes = if info.is_empty() {
            Vec::new()
        } else {
            build(&mut info, 0)
        };
        let order = info.iter().map(|p| p.index).collect();
        Bvh { prims, nodes, order }
    }

    /// Number of nodes, for statistics.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Visits the leaves the ray may hit, nearest first; `visit` returns a new `t_max` and
    /// whether to stop.
    #[inline]
    fn traverse<C: Counter>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut C,
        mut visit: impl FnMut(u32, f32, &mut C) -> (f32, bool),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let inv_dir = ray.dir.recip();
        let negative = [inv_dir.x < 0.0, inv_dir.y < 0.0, inv_dir.z < 0.0];
        let mut stack = [0u32; 64];
        let mut top = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            stats.node();
            let bounds = Aabb {
                min: Vec3::from(node.min),
                max: Vec3::from(node.max),
            };
            if bounds.hit(ray, inv_dir, t_max).is_some() {
                if node.count > 0 {
                    for &prim in &self.order[node.offset as usize..node.offset as usize + node.count as usize] {
                        let (t, stop) = visit(prim, t_max, stats);
                        if stop {
                            return;
                        }
                        t_max = t;
                    }
                } else if negative[node.axis as usize] {
                    stack[top] = current as u32 + 1;
                    top += 1;
                    current = node.offset as usize;
                    continue;
                } else {
                    stack[top] = node.offset;
                    top += 1;
                    current += 1;
                    continue;
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            current = stack[top] as usize;
        }
    }
}

impl<P: PrimitiveSet> Bvh<P> {
    fn closest<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        let mut closest = None;
        self.traverse(ray, t_max, stats, |prim, t_max, stats| {
            stats.prims(1);
            match self.prims.intersect(prim, ray, t_max) {
                Some(hit) => {
                    closest = Some(hit);
                    (hit.t, false)
                }
                None => (t_max, false),
            }
        });
        closest
    }
}

impl<P: PrimitiveSet> Accel for Bvh<P> {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.closest(ray, t_max, &mut ())
    }

    fn intersect_counted(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        self.closest(ray, t_max, stats)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let mut hit = false;
        self.traverse(ray, t_max, &mut (), |prim, t_max, _| {
            hit = self.prims.occluded(prim, ray, t_max);
            (t_max, hit)
        });
        hit
    }

    fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| Aabb {
            min: n.min.into(),
            max: n.max.into(),
        })
    }

    fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.order.capacity() * std::mem::size_of::<u32>()
    }
}

/// Builds the subtree over `prims` (which it reorders), its leaves pointing at
/// `first + index within prims`; returns its nodes, root first.
fn build(prims: &mut [PrimInfo], first: usize) -> Vec<Node> {
    let bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.union(p.bounds));
    let leaf = |prims: &[PrimInfo]| Node {
        min: bounds.min.into(),
        offset: first as u32,
        max: bounds.max.into(),
        count: prims.len() as u16,
        axis: 0,
    };
    if prims.len() <= 1 {
        return vec![leaf(prims)];
    }
    let (axis, mid) = match choose_split(prims, &bounds) {
        Some(split) => split,
        None => {
            // A leaf is cheaper, or every centroid coincides: a leaf unless it is too large,
            // in which case halve the set by index.
            let centroids = prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid));
            if prims.len() <= MAX_LEAF || prims.len() <= MAX_COINCIDENT_LEAF {
                return vec![leaf(prims)];
            }
            let axis = centroids.max_axis();
            let mid = prims.len() / 2;
            prims.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
            (axis, mid)
        }
    };
    let (left, right) = prims.split_at_mut(mid);
    let (left_nodes, right_nodes) = if left.len() + right.len() > PARALLEL_THRESHOLD {
        rayon::join(|| build(left, first), || build(right, first + mid))
    } else {
        (build(left, first), build(right, first + mid))
    };
    let mut nodes = Vec::with_capacity(1 + left_nodes.len() + right_nodes.len());
    let second = 1 + left_nodes.len();
    nodes.push(Node {
        min: bounds.min.into(),
        offset: second as u32,
        max: bounds.max.into(),
        count: 0,
        axis: axis as u16,
    });
    nodes.extend(left_nodes.into_iter().map(|n| shift(n, 1)));
    nodes.extend(right_nodes.into_iter().map(|n| shift(n, second)));
    nodes
}

/// Moves a subtree's node by `by` slots: interior nodes' second-child index follows.
fn shift(mut node: Node, by: usize) -> Node {
    if node.count == 0 {
        node.offset += by as u32;
    }
    node
}

/// The best binned SAH split: the axis and the number of primitives on the left, after
/// partitioning `prims` in place. `None` when a leaf is cheaper or centroids coincide.
fn choose_split(prims: &mut [PrimInfo], bounds: &Aabb) -> Option<(usize, usize)> {
    let centroids = prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid));
    let axis = centroids.max_axis();
    let (lo, hi) = (centroids.min[axis], centroids.max[axis]);
    if hi <= lo {
        return None;
    }
    let scale = BINS as f32 / (hi - lo);
    let bin_of = |p: &PrimInfo| (((p.centroid[axis] - lo) * scale) as usize).min(BINS - 1);
    let mut bins = [(Aabb::EMPTY, 0usize); BINS];
    for p in prims.iter() {
        let b = &mut bins[bin_of(p)];
        b.0 = b.0.union(p.bounds);
        b.1 += 1;
    }
    // Sweep from the right to get the cost of every right part, then from the left.
    let mut right_area = [0.0f32; BINS];
    let mut right_count = [0usize; BINS];
    let (mut acc, mut n) = (Aabb::EMPTY, 0);
    for i in (1..BINS).rev() {
        acc = acc.union(bins[i].0);
        n += bins[i].1;
        right_area[i] = acc.surface_area();
        right_count[i] = n;
    }
    let (mut acc, mut n) = (Aabb::EMPTY, 0);
    let mut best = (f32::INFINITY, 0);
    for i in 0..BINS - 1 {
        acc = acc.union(bins[i].0);
        n += bins[i].1;
        if n == 0 || right_count[i + 1] == 0 {
            continue;
        }
        let cost = acc.surface_area() * n as f32 + right_area[i + 1] * right_count[i + 1] as f32;
        if cost < best.0 {
            best = (cost, i);
        }
    }
    let area = bounds.surface_area();
    let split_cost = TRAVERSAL_COST + INTERSECT_COST * best.0 / area.max(f32::MIN_POSITIVE);
    let leaf_cost = INTERSECT_COST * prims.len() as f32;
    if !best.0.is_finite() || (prims.len() <= MAX_LEAF && split_cost >= leaf_cost) {
        return None;
    }
    let mut mid = 0;
    for i in 0..prims.len() {
        if bin_of(&prims[i]) <= best.1 {
            prims.swap(i, mid);
            mid += 1;
        }
    }
    Some((axis, mid))
}
