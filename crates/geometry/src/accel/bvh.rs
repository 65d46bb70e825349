//! Bounding volume hierarchy: a binned surface-area-heuristic build (Wald, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies", 2007), run in parallel over
//! subtrees, then collapsed into an 8-wide tree (as in Embree's BVH8) whose eight child
//! boxes are tested at once with SIMD slab tests. Traversal visits hit children nearest
//! first and culls entries farther than the closest hit found; shadow rays stop at the
//! first hit.

use super::{Counter, PrimitiveSet, Traverse, PAD};
use crate::Hit;
use glam::Vec3;
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
use glam::Vec4;
use penumbra_core::{Aabb, Ray};
use rayon::prelude::*;
use std::mem::MaybeUninit;
use std::sync::Arc;

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
struct LeafRule {
    /// Primitives tested at once: a side of `n` costs `ceil(n / group)` tests.
    group: usize,
    /// Sets of at most this many primitives become leaves.
    max: usize,
    /// Whether a set of up to `2 * max` may stay a leaf where the SAH finds that cheaper.
    sah: bool,
}

impl LeafRule {
    fn for_set(len: usize, group: usize) -> Self {
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
struct Node {
    min: [f32; 3],
    offset: u32,
    max: [f32; 3],
    count: u16,
}

impl Node {
    /// A slot no subtree used (subtrees reserve room for their largest possible size).
    const UNUSED: Node = Node {
        min: [0.0; 3],
        offset: 0,
        max: [0.0; 3],
        count: 0,
    };
}

/// Children per node.
const WIDTH: usize = 8;

/// A wide node: the children's boxes in structure-of-arrays form, one SIMD lane each.
/// `bounds[2 * axis]` holds the minima along `axis`, `bounds[2 * axis + 1]` the maxima;
/// unused lanes hold an empty box that no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct WideNode {
    bounds: [[f32; WIDTH]; 6],
    /// Interior child: index of its node. Leaf child: its first slot in `order`.
    child: [u32; WIDTH],
    /// Primitives in a leaf child; 0 for an interior child or an unused lane.
    count: [u16; WIDTH],
}

pub struct Bvh<P> {
    prims: Arc<P>,
    nodes: Vec<WideNode>,
    /// The primitive in each leaf slot; empty when `prims` is stored in leaf order.
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

/// Largest traversal stack: a node pushes at most `WIDTH - 1` entries, and the build caps
/// the depth at `MAX_DEPTH`.
const STACK: usize = (WIDTH - 1) * MAX_DEPTH + 1;

impl<P: PrimitiveSet> Bvh<P> {
    pub fn new(prims: Arc<P>) -> Self {
        let mut info: Vec<PrimInfo> = (0..prims.len() as u32)
            .into_par_iter()
            .map(|index| {
                let bounds = prims.bounds(index);
                PrimInfo {
                    bounds,
                    centroid: bounds.centroid(),
                    index,
                }
            })
            .collect();
        let group = prims.group().max(1);
        // A subtree over n primitives has at most 2n - 1 nodes: each subtree builds into its
        // own range of one array, so the threads never copy or merge node lists.
        let mut binary = vec![Node::UNUSED; (2 * info.len()).saturating_sub(1)];
        let rule = LeafRule::for_set(info.len(), group);
        if !info.is_empty() {
            build(&mut info, 0, 0, rule, &mut binary, 0);
        }
        let mut order: Vec<u32> = info.iter().map(|p| p.index).collect();
        if group > 1 {
            order = align_leaves(&mut binary, &order, group);
        }
        let prims = match prims.reordered(&order) {
            Some(reordered) => {
                order = Vec::new();
                Arc::new(reordered)
            }
            None => prims,
        };
        let bounds = binary.first().map_or(Aabb::EMPTY, |n| Aabb {
            min: n.min.into(),
            max: n.max.into(),
        });
        let mut nodes = Vec::new();
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

    /// Number of wide nodes, for statistics.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Visits the leaves the ray may hit, nearest first. `visit(first, count, t_max)`
    /// tests the primitives in slots `first..first + count` and returns the new `t_max` and
    /// whether to stop. The node being visited is kept out of the stack: of the children a
    /// node's box test hits, the nearest is visited next and the others are pushed, farthest
    /// first, with their entry distances, so that popped entries beyond `t_max` are culled.
    #[inline(always)]
    fn traverse<C: Counter>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut C,
        mut visit: impl FnMut(usize, usize, f32, &mut C) -> (f32, bool),
    ) {
        if let Some((first, count)) = self.root_leaf {
            if self.bounds.hit(ray, ray.dir.recip(), t_max).is_some() {
                visit(first as usize, count as usize, t_max, stats);
            }
            return;
        }
        if self.nodes.is_empty() {
            return;
        }
        let inv = ray.dir.recip();
        let rs = RaySlabs::new(ray.origin, inv);
        // Pending subtrees (a node, or a leaf with its count in the high half) and their
        // entry distances; only slots below `top` are ever read, so they start uninitialised.
        let mut refs = [MaybeUninit::<u64>::uninit(); STACK];
        let mut dists = [MaybeUninit::<f32>::uninit(); STACK];
        let mut top = 0;
        let mut current = 0u64;
        loop {
            let index = current as u32 as usize;
            let count = (current >> 32) as usize;
            if count > 0 {
                let (t, stop) = visit(index, count, t_max, stats);
                if stop {
                    return;
                }
                t_max = t;
            } else {
                let node = &self.nodes[index];
                stats.node();
                let (mask, t0) = slabs(node, &rs, t_max);
                let mut mask = mask;
                if mask != 0 {
                    let entry = |lane: usize| node.child[lane] as u64 | (node.count[lane] as u64) << 32;
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        current = entry(first);
                        continue;
                    }
                    // Push every hit child, keeping the pushed run sorted by decreasing
                    // distance; then the nearest, on top, becomes the current node.
                    let start = top;
                    let mut lane = first;
                    loop {
                        let (r, d) = (entry(lane), t0[lane]);
                        if node.count[lane] == 0 {
                            prefetch(self.nodes.get(node.child[lane] as usize));
                        }
                        let mut k = top;
                        // SAFETY: slots below `top` were written.
                        while k > start && unsafe { dists[k - 1].assume_init() } < d {
                            refs[k] = refs[k - 1];
                            dists[k] = dists[k - 1];
                            k -= 1;
                        }
                        refs[k].write(r);
                        dists[k].write(d);
                        top += 1;
                        if mask == 0 {
                            break;
                        }
                        lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                    }
                    top -= 1;
                    // SAFETY: slot `top` was just written.
                    current = unsafe { refs[top].assume_init() };
                    continue;
                }
            }
            // Pop the nearest pending subtree that may still hold a closer hit.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                // SAFETY: slots below the old `top` were written.
                if unsafe { dists[top].assume_init() } <= t_max {
                    current = unsafe { refs[top].assume_init() };
                    break;
                }
            }
        }
    }

    fn closest_hit<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        let data = self.prims.prepare(ray);
        let mut closest = None;
        self.traverse(
            ray,
            t_max,
            stats,
            #[inline(always)]
            |first, count, mut t_max, stats| {
                stats.prims(count as u64);
                if self.order.is_empty() {
                    if let Some(hit) = self.prims.intersect_run(first, count, ray, &data, t_max) {
                        t_max = hit.t;
                        closest = Some(hit);
                    }
                    return (t_max, false);
                }
                for &prim in &self.order[first..first + count] {
                    if let Some(hit) = self.prims.intersect(prim, ray, &data, t_max) {
                        t_max = hit.t;
                        closest = Some(hit);
                    }
                }
                (t_max, false)
            },
        );
        closest
    }
}

/// Asks the caches for a node about to be pushed: by the time it is popped its cache lines
/// are more likely there, which helps incoherent rays most.
#[inline(always)]
fn prefetch(node: Option<&WideNode>) {
    #[cfg(target_arch = "x86_64")]
    if let Some(node) = node {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = node as *const WideNode as *const i8;
        for line in (0..std::mem::size_of::<WideNode>()).step_by(64) {
            // SAFETY: a prefetch is only a hint, and the address lies inside `node`.
            unsafe { _mm_prefetch(p.add(line), _MM_HINT_T0) };
        }
    }
}

/// What the slab test needs of a ray: origin and inverse direction per axis, and which of
/// each axis's two planes the ray meets first.
struct RaySlabs {
    origin: [f32; 3],
    inv: [f32; 3],
    near: [usize; 3],
}

impl RaySlabs {
    #[inline(always)]
    fn new(origin: Vec3, inv: Vec3) -> Self {
        // The near plane of each axis is the minimum for a positive direction, else the maximum.
        RaySlabs {
            origin: origin.into(),
            inv: inv.into(),
            near: [
                (inv.x < 0.0) as usize,
                2 + (inv.y < 0.0) as usize,
                4 + (inv.z < 0.0) as usize,
            ],
        }
    }
}

/// The slab test of a ray against a node's children: the mask of children entered before
/// `t_max`, and each child's entry distance. Exit distances are widened by `ROUNDING`.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
fn slabs(node: &WideNode, r: &RaySlabs, t_max: f32) -> (u32, [f32; WIDTH]) {
    use std::arch::x86_64::*;
    // SAFETY: the target has AVX (checked at compile time) and every load reads a whole
    // row of eight floats.
    unsafe {
        let plane = |k: usize| _mm256_loadu_ps(node.bounds[k].as_ptr());
        let axis = |a: usize, k: usize| {
            _mm256_mul_ps(
                _mm256_sub_ps(plane(k), _mm256_set1_ps(r.origin[a])),
                _mm256_set1_ps(r.inv[a]),
            )
        };
        // max/min return their second operand when either is NaN: each slab distance goes
        // first, so a NaN one (a ray inside a face's plane, 0 * inf) is ignored.
        let near = _mm256_max_ps(
            axis(0, r.near[0]),
            _mm256_max_ps(
                axis(1, r.near[1]),
                _mm256_max_ps(axis(2, r.near[2]), _mm256_setzero_ps()),
            ),
        );
        let far = _mm256_mul_ps(
            _mm256_min_ps(
                axis(0, r.near[0] ^ 1),
                _mm256_min_ps(
                    axis(1, r.near[1] ^ 1),
                    _mm256_min_ps(axis(2, r.near[2] ^ 1), _mm256_set1_ps(t_max)),
                ),
            ),
            _mm256_set1_ps(ROUNDING),
        );
        let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(near, far)) as u32;
        let mut t0 = [0.0f32; WIDTH];
        _mm256_storeu_ps(t0.as_mut_ptr(), near);
        (mask, t0)
    }
}

/// [`slabs`] four lanes at a time.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
fn slabs(node: &WideNode, r: &RaySlabs, t_max: f32) -> (u32, [f32; WIDTH]) {
    let mut t0 = [0.0f32; WIDTH];
    let mut mask = 0;
    for half in 0..WIDTH / 4 {
        let plane = |k: usize| Vec4::from_slice(&node.bounds[k][4 * half..4 * half + 4]);
        let axis = |a: usize, k: usize| (plane(k) - Vec4::splat(r.origin[a])) * Vec4::splat(r.inv[a]);
        // As above: each slab distance is the first operand, so NaN ones are ignored.
        let near = axis(0, r.near[0]).max(axis(1, r.near[1]).max(axis(2, r.near[2]).max(Vec4::ZERO)));
        let far = axis(0, r.near[0] ^ 1)
            .min(axis(1, r.near[1] ^ 1).min(axis(2, r.near[2] ^ 1).min(Vec4::splat(t_max))))
            * ROUNDING;
        mask |= near.cmple(far).bitmask() << (4 * half);
        near.write_to_slice(&mut t0[4 * half..4 * half + 4]);
    }
    (mask, t0)
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
        self.traverse(
            ray,
            t_max,
            &mut (),
            #[inline(always)]
            |first, count, t_max, _| {
                hit = if self.order.is_empty() {
                    self.prims.occluded_run(first, count, ray, &data, t_max)
                } else {
                    self.order[first..first + count]
                        .iter()
                        .any(|&prim| self.prims.occluded(prim, ray, &data, t_max))
                };
                (t_max, hit)
            },
        );
        hit
    }

    fn extent(&self) -> Aabb {
        self.bounds
    }

    fn prim_bytes(&self) -> usize {
        self.prims.memory_bytes()
    }

    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.capacity() * std::mem::size_of::<WideNode>()
            + self.order.capacity() * std::mem::size_of::<u32>()
    }
}

/// Collapses the binary subtree at `index` into wide nodes appended to `out`; returns the
/// index of its node. Each node adopts up to `WIDTH` descendants by repeatedly opening the
/// interior child with the largest surface area.
fn collapse(binary: &[Node], index: usize, out: &mut Vec<WideNode>) -> u32 {
    let node = &binary[index];
    let mut children = [0usize; WIDTH];
    children[..2].copy_from_slice(&[index + 1, node.offset as usize]);
    let mut len = 2;
    while len < WIDTH {
        let open = (0..len)
            .filter(|&k| binary[children[k]].count == 0)
            .max_by(|&a, &b| area(&binary[children[a]]).total_cmp(&area(&binary[children[b]])));
        let Some(k) = open else { break };
        let c = children[k];
        children[k] = c + 1;
        children[len] = binary[c].offset as usize;
        len += 1;
    }
    let children = &children[..len];
    let me = out.len();
    out.push(WideNode {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [0; WIDTH],
        count: [0; WIDTH],
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

/// Builds the subtree over `prims` (which it reorders) at `depth` into `out`, its root at
/// `out[0]` (index `base` of the whole array), its first child right after it and its
/// second child after the first child's range; leaves point at `first + index within
/// prims`. `out` has room for `2 * prims.len() - 1` nodes.
fn build(prims: &mut [PrimInfo], first: usize, depth: usize, leaves: LeafRule, out: &mut [Node], base: usize) {
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
fn align_leaves(binary: &mut [Node], order: &[u32], group: usize) -> Vec<u32> {
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
