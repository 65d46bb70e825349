//! Bounding volume hierarchy: a binned surface-area-heuristic build (Wald, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies", 2007), run in parallel over
//! subtrees, then collapsed into a 4-wide tree (as in Embree's BVH4) whose four child
//! boxes are tested at once with SIMD slab tests. Traversal visits hit children nearest
//! first and culls entries farther than the closest hit found; shadow rays stop at the
//! first hit.

use super::{Counter, PrimitiveSet, Traverse};
use crate::Hit;
use glam::{Vec3, Vec4};
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

/// A node of the binary build tree: an interior node's first child follows it, `offset` is
/// its second child; a leaf (`count > 0`) holds primitives `order[offset..offset + count]`.
#[derive(Clone, Copy, Debug)]
struct Node {
    min: [f32; 3],
    offset: u32,
    max: [f32; 3],
    count: u16,
}

/// A 4-wide node: the children's boxes in structure-of-arrays form, one SIMD lane each.
/// `bounds[2 * axis]` holds the minima along `axis`, `bounds[2 * axis + 1]` the maxima;
/// unused lanes hold an empty box that no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Node4 {
    bounds: [[f32; 4]; 6],
    /// Interior child: index of its node. Leaf child: its first slot in `order`.
    child: [u32; 4],
    /// Primitives in a leaf child; 0 for an interior child or an unused lane.
    count: [u16; 4],
}

pub struct Bvh<P> {
    prims: Arc<P>,
    nodes: Vec<Node4>,
    order: Vec<u32>,
    bounds: Aabb,
    /// The whole tree is one leaf (a single primitive or coincident ones).
    root_leaf: Option<(u32, u16)>,
}

#[derive(Clone, Copy)]
struct PrimInfo {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

/// Largest traversal stack: a 4-wide tree pushes at most 3 entries per level, and the
/// build caps the depth at `MAX_DEPTH`.
const STACK: usize = 128;

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
        let binary = if info.is_empty() {
            Vec::new()
        } else {
            build(&mut info, 0, 0)
        };
        let order = info.iter().map(|p| p.index).collect();
        let bounds = binary.first().map_or(Aabb::EMPTY, |n| Aabb {
            min: n.min.into(),
            max: n.max.into(),
        });
        let mut nodes = Vec::with_capacity(binary.len() / 2 + 1);
        let root_leaf = match binary.first() {
            Some(root) if root.count > 0 => Some((root.offset, root.count)),
            Some(_) => {
                collapse(&binary, 0, &mut nodes);
                None
            }
            None => None,
        };
        nodes.shrink_to_fit();
        Bvh {
            prims,
            nodes,
            order,
            bounds,
            root_leaf,
        }
    }

    /// Number of 4-wide nodes, for statistics.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Visits the leaves the ray may hit, nearest first. `visit(first, count, t_max)`
    /// tests a leaf and returns the new `t_max` and whether to stop.
    #[inline]
    fn traverse<C: Counter>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut C,
        mut visit: impl FnMut(&[u32], f32, &mut C) -> (f32, bool),
    ) {
        if let Some((first, count)) = self.root_leaf {
            let leaf = &self.order[first as usize..first as usize + count as usize];
            if self.bounds.hit(ray, safe_recip(ray.dir), t_max).is_some() {
                visit(leaf, t_max, stats);
            }
            return;
        }
        if self.nodes.is_empty() {
            return;
        }
        let inv = safe_recip(ray.dir);
        let (ox, oy, oz) = (
            Vec4::splat(ray.origin.x),
            Vec4::splat(ray.origin.y),
            Vec4::splat(ray.origin.z),
        );
        let (ix, iy, iz) = (Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z));
        // The near plane of each axis is the minimum for a positive direction, else the maximum.
        let near = [
            (inv.x < 0.0) as usize,
            2 + (inv.y < 0.0) as usize,
            4 + (inv.z < 0.0) as usize,
        ];
        let far = [near[0] ^ 1, near[1] ^ 1, near[2] ^ 1];
        // Entries: node index, or a leaf as (LEAF | first, count); and the entry distance.
        let mut stack = [(0u32, 0u16, 0f32); STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (index, count, t_near) = stack[top];
            if t_near > t_max {
                continue;
            }
            if count > 0 {
                let leaf = &self.order[index as usize..index as usize + count as usize];
                let (t, stop) = visit(leaf, t_max, stats);
                if stop {
                    return;
                }
                t_max = t;
                continue;
            }
            let node = &self.nodes[index as usize];
            stats.node();
            let b = &node.bounds;
            let t0 = ((Vec4::from(b[near[0]]) - ox) * ix)
                .max((Vec4::from(b[near[1]]) - oy) * iy)
                .max((Vec4::from(b[near[2]]) - oz) * iz)
                .max(Vec4::ZERO);
            let t1 = ((Vec4::from(b[far[0]]) - ox) * ix)
                .min((Vec4::from(b[far[1]]) - oy) * iy)
                .min((Vec4::from(b[far[2]]) - oz) * iz)
                .min(Vec4::splat(t_max))
                * ROUNDING;
            let mut mask = t0.cmple(t1).bitmask();
            if mask == 0 {
                continue;
            }
            // Push the hit children farthest first, so the nearest is popped next.
            let t0 = t0.to_array();
            let start = top;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let entry = (node.child[lane], node.count[lane], t0[lane]);
                // Insertion into the pushed run, ordered by decreasing distance.
                let mut k = top;
                while k > start && stack[k - 1].2 < entry.2 {
                    stack[k] = stack[k - 1];
                    k -= 1;
                }
                stack[k] = entry;
                top += 1;
            }
        }
    }

    fn closest_hit<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        let data = self.prims.prepare(ray);
        let mut closest = None;
        self.traverse(ray, t_max, stats, |leaf, mut t_max, stats| {
            stats.prims(leaf.len() as u64);
            for &prim in leaf {
                if let Some(hit) = self.prims.intersect(prim, ray, &data, t_max) {
                    t_max = hit.t;
                    closest = Some(hit);
                }
            }
            (t_max, false)
        });
        closest
    }
}

/// `1 / dir`, with zero components replaced by tiny ones of the same sign so that slab
/// distances are never NaN.
#[inline]
fn safe_recip(dir: Vec3) -> Vec3 {
    let tiny = |x: f32| if x.abs() < 1e-30 { 1e-30f32.copysign(x) } else { x };
    Vec3::new(tiny(dir.x), tiny(dir.y), tiny(dir.z)).recip()
}

/// Widens exit distances by pbrt-v4's 1 + 2 gamma(3) so rounding never skips a box.
const ROUNDING: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl<P: PrimitiveSet> Traverse for Bvh<P> {
    fn closest<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        self.closest_hit(ray, t_max, stats)
    }

    fn any_hit(&self, ray: &Ray, t_max: f32) -> bool {
        let data = self.prims.prepare(ray);
        let mut hit = false;
        self.traverse(ray, t_max, &mut (), |leaf, t_max, _| {
            hit = leaf.iter().any(|&prim| self.prims.occluded(prim, ray, &data, t_max));
            (t_max, hit)
        });
        hit
    }

    fn extent(&self) -> Aabb {
        self.bounds
    }

    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.capacity() * std::mem::size_of::<Node4>()
            + self.order.capacity() * std::mem::size_of::<u32>()
    }
}

/// Collapses the binary subtree at `index` into 4-wide nodes appended to `out`; returns the
/// index of its node. Each node adopts up to four descendants by repeatedly opening the
/// interior child with the largest surface area.
fn collapse(binary: &[Node], index: usize, out: &mut Vec<Node4>) -> u32 {
    let node = &binary[index];
    let mut children: Vec<usize> = vec![index + 1, node.offset as usize];
    while children.len() < 4 {
        let open = children
            .iter()
            .enumerate()
            .filter(|(_, &c)| binary[c].count == 0)
            .max_by(|a, b| area(&binary[*a.1]).total_cmp(&area(&binary[*b.1])));
        let Some((k, &c)) = open else { break };
        children.swap_remove(k);
        children.push(c + 1);
        children.push(binary[c].offset as usize);
    }
    let me = out.len();
    out.push(Node4 {
        bounds: [
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
        ],
        child: [0; 4],
        count: [0; 4],
    });
    for (lane, &c) in children.iter().enumerate() {
        let n = &binary[c];
        let child = if n.count > 0 {
            n.offset
        } else {
            collapse(binary, c, out)
        };
        let slot = &mut out[me];
        for axis in 0..3 {
            slot.bounds[2 * axis][lane] = n.min[axis];
            slot.bounds[2 * axis + 1][lane] = n.max[axis];
        }
        slot.child[lane] = child;
        slot.count[lane] = n.count;
    }
    me as u32
}

fn area(n: &Node) -> f32 {
    Aabb {
        min: n.min.into(),
        max: n.max.into(),
    }
    .surface_area()
}

/// Binary tree depth beyond which the build makes leaves, keeping traversal stacks bounded.
const MAX_DEPTH: usize = 40;

/// Builds the subtree over `prims` (which it reorders) at `depth`, its leaves pointing at
/// `first + index within prims`; returns its nodes, root first.
fn build(prims: &mut [PrimInfo], first: usize, depth: usize) -> Vec<Node> {
    let bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.union(p.bounds));
    let leaf = |prims: &[PrimInfo]| Node {
        min: bounds.min.into(),
        offset: first as u32,
        max: bounds.max.into(),
        count: prims.len() as u16,
    };
    if prims.len() <= 1 || (depth >= MAX_DEPTH && prims.len() <= u16::MAX as usize) {
        return vec![leaf(prims)];
    }
    let mid = match choose_split(prims, &bounds) {
        Some(mid) => mid,
        None => {
            // A leaf is cheaper, or every centroid coincides: a leaf unless it is too large,
            // in which case halve the set by index.
            if prims.len() <= MAX_COINCIDENT_LEAF {
                return vec![leaf(prims)];
            }
            let axis = prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid)).max_axis();
            let mid = prims.len() / 2;
            prims.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
            mid
        }
    };
    let (left, right) = prims.split_at_mut(mid);
    let (left_nodes, right_nodes) = if left.len() + right.len() > PARALLEL_THRESHOLD {
        rayon::join(
            || build(left, first, depth + 1),
            || build(right, first + mid, depth + 1),
        )
    } else {
        (build(left, first, depth + 1), build(right, first + mid, depth + 1))
    };
    let mut nodes = Vec::with_capacity(1 + left_nodes.len() + right_nodes.len());
    let second = 1 + left_nodes.len();
    nodes.push(Node {
        min: bounds.min.into(),
        offset: second as u32,
        max: bounds.max.into(),
        count: 0,
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

/// The best binned SAH split: the number of primitives on the left, after partitioning
/// `prims` in place. `None` when a leaf is cheaper or centroids coincide.
fn choose_split(prims: &mut [PrimInfo], bounds: &Aabb) -> Option<usize> {
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
    if !best.0.is_finite() || prims.len() <= MAX_LEAF || split_cost >= leaf_cost && prims.len() <= 2 * MAX_LEAF {
        return None;
    }
    let mut mid = 0;
    for i in 0..prims.len() {
        if bin_of(&prims[i]) <= best.1 {
            prims.swap(i, mid);
            mid += 1;
        }
    }
    Some(mid)
}
