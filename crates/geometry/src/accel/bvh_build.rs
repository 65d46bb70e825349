//! The binary SAH build of the [`super::bvh::Bvh`]: binned (Wald, "On fast Construction
//! of SAH-based Bounding Volume Hierarchies", 2007), in parallel over subtrees, into one
//! array of binary nodes that `bvh.rs` collapses into 8-wide ones.

use super::PAD;
use glam::Vec3;
use penumbra_core::Aabb;
use rayon::prelude::*;

const BINS: usize = 16;
/// Leaves of large sets hold at most this many primitives unless their centroids coincide,
/// or twice as many where the SAH finds a leaf cheaper than a split.
const MAX_LEAF: usize = 4;
/// Sets of up to this many primitives are built finer: split down to leaves of at most
/// [`MAX_SMALL_SET_LEAF`], whatever the SAH says. The SAH weighs a box by the chance that a
/// ray from outside meets it, but in a closed room every ray starts inside, and a leaf of
/// big triangles from different walls spans the room and is entered by every ray: on the
/// Cornell box this cut triangle tests per camera ray from 11.4 to 2.0 and the path
/// tracer's instructions per sample from 11,000 to 8,400 (docs/performance.md). Two leaves
/// of two triangles share one packet of four (see [`align_leaves`]), so the finer tree
/// costs only nodes, about 1.7 times as many, which a small set's tree keeps in cache (at
/// most about 1 MiB) and a large one's would not (random rays on the 327,680-triangle test
/// mesh lost some 8%, so large sets keep the SAH's leaves).
const SMALL_SET: usize = 16_384;
const MAX_SMALL_SET_LEAF: usize = 2;

/// How a build makes leaves.
#[derive(Clone, Copy)]
pub(super) struct LeafRule {
    /// Primitives tested at once: a side of `n` costs `ceil(n / group)` tests.
    group: usize,
    /// Sets of at most this many primitives become leaves.
    max: usize,
    /// Whether a set of up to `2 * max` may stay a leaf where the SAH finds that cheaper.
    sah: bool,
}

impl LeafRule {
    pub(super) fn for_set(len: usize, group: usize) -> Self {
        if len <= SMALL_SET {
            LeafRule {
                group,
                max: MAX_SMALL_SET_LEAF,
                sah: false,
            }
        } else {
            LeafRule {
                group,
                max: MAX_LEAF.max(group),
                sah: true,
            }
        }
    }
}

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
pub(super) struct Node {
    pub(super) min: [f32; 3],
    pub(super) offset: u32,
    pub(super) max: [f32; 3],
    pub(super) count: u16,
}

impl Node {
    /// A slot no subtree used (subtrees reserve room for their largest possible size).
    pub(super) const UNUSED: Node = Node {
        min: [0.0; 3],
        offset: 0,
        max: [0.0; 3],
        count: 0,
    };
}

/// A primitive as the build sees it: its bounds, their centre, its number in the set.
#[derive(Clone, Copy)]
pub(super) struct PrimInfo {
    pub(super) bounds: Aabb,
    pub(super) centroid: Vec3,
    pub(super) index: u32,
}

/// Surface area of a binary node's box.
pub(super) fn area(n: &Node) -> f32 {
    Aabb {
        min: n.min.into(),
        max: n.max.into(),
    }
    .surface_area()
}

/// Binary tree depth beyond which the build makes leaves, keeping traversal stacks bounded.
pub(super) const MAX_DEPTH: usize = 40;

/// Builds the subtree over `prims` (which it reorders) at `depth` into `out`, its root at
/// `out[0]` (index `base` of the whole array), its first child right after it and its
/// second child after the first child's range; leaves point at `first + index within
/// prims`. `out` has room for `2 * prims.len() - 1` nodes.
pub(super) fn build(
    prims: &mut [PrimInfo],
    first: usize,
    depth: usize,
    leaves: LeafRule,
    out: &mut [Node],
    base: usize,
) {
    let bounds = fold(prims, Aabb::EMPTY, |b, p| *b = b.union(p.bounds), Aabb::union);
    let leaf = Node {
        min: bounds.min.into(),
        offset: first as u32,
        max: bounds.max.into(),
        count: prims.len() as u16,
    };
    if prims.len() <= 1 || (depth >= MAX_DEPTH && prims.len() <= u16::MAX as usize) {
        out[0] = leaf;
        return;
    }
    let mid = match choose_split(prims, &bounds, leaves) {
        Some(mid) => mid,
        None => {
            // A leaf is as good, or every centroid coincides: a leaf unless it is too large,
            // in which case halve the set by index.
            if prims.len() <= MAX_COINCIDENT_LEAF {
                out[0] = leaf;
                return;
            }
            let axis = prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid)).max_axis();
            let mid = prims.len() / 2;
            prims.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
            mid
        }
    };
    let second = 2 * mid;
    out[0] = Node {
        min: bounds.min.into(),
        offset: (base + second) as u32,
        max: bounds.max.into(),
        count: 0,
    };
    let parallel = mid.min(prims.len() - mid) > PARALLEL_THRESHOLD / 2;
    let (left, right) = prims.split_at_mut(mid);
    let (left_out, right_out) = out[1..].split_at_mut(second - 1);
    let mut build_left = move || build(left, first, depth + 1, leaves, left_out, base + 1);
    let mut build_right = move || build(right, first + mid, depth + 1, leaves, right_out, base + second);
    if parallel {
        rayon::join(build_left, build_right);
    } else {
        build_left();
        build_right();
    }
}

/// Accumulates `prims` into `init` with `add`, in parallel chunks combined by `merge` when
/// there are many.
#[inline]
fn fold<T: Copy + Send + Sync>(
    prims: &[PrimInfo],
    init: T,
    add: impl Fn(&mut T, &PrimInfo) + Sync,
    merge: impl Fn(T, T) -> T + Sync,
) -> T {
    let serial = |chunk: &[PrimInfo]| {
        let mut acc = init;
        for p in chunk {
            add(&mut acc, p);
        }
        acc
    };
    if prims.len() > PARALLEL_THRESHOLD * 4 {
        prims.par_chunks(PARALLEL_THRESHOLD).map(serial).reduce(|| init, &merge)
    } else {
        serial(prims)
    }
}

/// The best binned SAH split: the number of primitives on the left, after partitioning
/// `prims` in place. `None` when a leaf will do (see [`LeafRule`]) or centroids coincide.
/// Primitives are tested `group` at a time, so a side of `n` costs `ceil(n / group)` tests
/// (as in Embree's builders for its four-triangle leaves).
fn choose_split(prims: &mut [PrimInfo], bounds: &Aabb, rule: LeafRule) -> Option<usize> {
    let group = rule.group;
    let blocks = |n: usize| n.div_ceil(group) as f32;
    let centroids = fold(prims, Aabb::EMPTY, |b, p| *b = b.grow(p.centroid), Aabb::union);
    let axis = centroids.max_axis();
    let (lo, hi) = (centroids.min[axis], centroids.max[axis]);
    if hi <= lo {
        return None;
    }
    let scale = BINS as f32 / (hi - lo);
    let bin_of = |p: &PrimInfo| (((p.centroid[axis] - lo) * scale) as usize).min(BINS - 1);
    let bins = fold(
        prims,
        [(Aabb::EMPTY, 0usize); BINS],
        |bins, p| {
            let b = &mut bins[bin_of(p)];
            b.0 = b.0.union(p.bounds);
            b.1 += 1;
        },
        |mut a, b| {
            for (a, b) in a.iter_mut().zip(b) {
                *a = (a.0.union(b.0), a.1 + b.1);
            }
            a
        },
    );
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
        let cost = acc.surface_area() * blocks(n) + right_area[i + 1] * blocks(right_count[i + 1]);
        if cost < best.0 {
            best = (cost, i);
        }
    }
    let area = bounds.surface_area();
    let split_cost = TRAVERSAL_COST + INTERSECT_COST * best.0 / area.max(f32::MIN_POSITIVE);
    let leaf_cost = INTERSECT_COST * blocks(prims.len());
    let sah_leaf = rule.sah && split_cost >= leaf_cost && prims.len() <= 2 * rule.max;
    if !best.0.is_finite() || prims.len() <= rule.max || sah_leaf {
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

/// Moves every leaf's run of slots that would straddle a boundary between groups of `group`
/// slots to start at the next multiple of `group`, filling the gap with [`PAD`]; returns
/// the padded order. Leaves that fit in what is left of a group share it (two leaves of two
/// triangles fill one packet of four, each tested with its own lanes), so small leaves cost
/// no memory. Leaves are numbered in depth-first order, which is the order of their runs.
pub(super) fn align_leaves(binary: &mut [Node], order: &[u32], group: usize) -> Vec<u32> {
    let mut padded = Vec::with_capacity(order.len() + order.len() / 2);
    for node in binary.iter_mut().filter(|n| n.count > 0) {
        if padded.len() % group + node.count as usize > group {
            padded.resize(padded.len().next_multiple_of(group), PAD);
        }
        let run = node.offset as usize..node.offset as usize + node.count as usize;
        node.offset = padded.len() as u32;
        padded.extend_from_slice(&order[run]);
    }
    padded
}
