//! Bounding volume hierarchy: a binned surface-area-heuristic build (Wald, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies", 2007), run in parallel over
//! subtrees, then collapsed into an 8-wide tree (as in Embree's BVH8) whose eight child
//! boxes are tested at once with SIMD slab tests. Traversal visits hit children nearest
//! first and culls entries farther than the closest hit found; shadow rays stop at the
//! first hit. The slab test runs in one AVX instruction per step where the CPU has it
//! ([`penumbra_core::simd`] picks at run time), else as two four-wide halves; the floats are
//! the same. The binary build is in `bvh_build.rs`.

use super::bvh_build::{align_leaves, area, build, LeafRule, Node, PrimInfo, MAX_DEPTH};
use super::{Counter, PrimitiveSet, Traverse};
use crate::Hit;
use glam::Vec3;
use glam::Vec4;
use penumbra_core::lanes::F8;
#[cfg(target_arch = "x86_64")]
use penumbra_core::lanes_avx::F8Avx;
use penumbra_core::{Aabb, Ray};
use rayon::prelude::*;
use std::mem::MaybeUninit;
use std::sync::Arc;

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// A wide node: the children's boxes in structure-of-arrays form, one SIMD lane each.
/// `bounds[2 * axis]` holds the minima along `axis`, `bounds[2 * axis + 1]` the maxima;
/// unused lanes hold an empty box that no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct WideNode {
    pub(super) bounds: [[f32; WIDTH]; 6],
    /// Interior child: index of its node. Leaf child: its first slot in `order`.
    pub(super) child: [u32; WIDTH],
    /// Primitives in a leaf child; 0 for an interior child or an unused lane.
    pub(super) count: [u16; WIDTH],
}

pub struct Bvh<P> {
    pub(super) prims: Arc<P>,
    pub(super) nodes: Vec<WideNode>,
    /// The primitive in each leaf slot; empty when `prims` is stored in leaf order.
    pub(super) order: Vec<u32>,
    bounds: Aabb,
    /// The whole tree is one leaf (a single primitive or coincident ones).
    pub(super) root_leaf: Option<(u32, u16)>,
}

/// The traversal entry of the root node.
pub(super) const ROOT: u64 = 0;

/// Largest traversal stack: a node pushes at most `WIDTH - 1` entries, and the build caps
/// the depth at `MAX_DEPTH`.
pub(super) const STACK: usize = (WIDTH - 1) * MAX_DEPTH + 1;

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
    /// With `NEAREST_FIRST == false` (shadow rays, whose `t_max` never shrinks) the hit
    /// children are pushed as they come, without their distances: every pushed entry is
    /// entered before `t_max`, so none would be culled. `AVX`: the slab test's kernel
    /// (true only inside a function compiled for AVX2, see [`Bvh::closest`]).
    #[inline(always)]
    fn traverse<C: Counter, const NEAREST_FIRST: bool, const AVX: bool>(
        &self,
        start: u64,
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
        let mut current = start;
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
                let (mask, t0) = slabs::<AVX>(node, &rs, t_max);
                let mut mask = mask;
                if mask != 0 {
                    let entry = |lane: usize| node.child[lane] as u64 | (node.count[lane] as u64) << 32;
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        current = entry(first);
                        continue;
                    }
                    // A node's child lane asked of the caches: an interior child's node (a
                    // leaf's lane asks for the root's, which is in cache), by a select.
                    let ahead = |lane: usize| (node.count[lane] == 0) as usize * node.child[lane] as usize;
                    if NEAREST_FIRST && mask & (mask - 1) == 0 {
                        // Two children hit, the common case: the nearer becomes the current
                        // node and the farther is pushed, chosen by selects rather than a
                        // branch on the distances (of equal ones the higher lane is nearer,
                        // as in the sorted push below).
                        let second = mask.trailing_zeros() as usize;
                        let swap = t0[first] < t0[second];
                        let (near, far) = if swap { (first, second) } else { (second, first) };
                        prefetch(&self.nodes[ahead(far)]);
                        refs[top].write(entry(far));
                        dists[top].write(t0[far]);
                        top += 1;
                        current = entry(near);
                        continue;
                    }
                    // Push every hit child, keeping the pushed run sorted by decreasing
                    // distance; then the nearest, on top, becomes the current node.
                    let start = top;
                    let mut lane = first;
                    loop {
                        let (r, d) = (entry(lane), t0[lane]);
                        prefetch(&self.nodes[ahead(lane)]);
                        let mut k = top;
                        if NEAREST_FIRST {
                            // SAFETY: slots below `top` were written.
                            while k > start && unsafe { dists[k - 1].assume_init() } < d {
                                refs[k] = refs[k - 1];
                                dists[k] = dists[k - 1];
                                k -= 1;
                            }
                            dists[k].write(d);
                        }
                        refs[k].write(r);
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
                // SAFETY: slots below the old `top` were written (`dists` only when
                // `NEAREST_FIRST`, and only then read).
                if !NEAREST_FIRST || unsafe { dists[top].assume_init() } <= t_max {
                    current = unsafe { refs[top].assume_init() };
                    break;
                }
            }
        }
    }

    #[inline(always)]
    fn closest_hit<C: Counter, const AVX: bool>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        self.closest_from::<C, AVX>(ROOT, ray, &self.prims.prepare(ray), t_max, stats)
    }

    /// The closest hit below `start` (a pending entry of the traversal: a node, or a leaf
    /// with its count in the high half; [`ROOT`] for the whole tree), for `ray` with its
    /// prepared `data`.
    #[inline(always)]
    pub(super) fn closest_from<C: Counter, const AVX: bool>(
        &self,
        start: u64,
        ray: &Ray,
        data: &P::RayData,
        t_max: f32,
        stats: &mut C,
    ) -> Option<Hit> {
        let mut closest = None;
        self.traverse::<C, true, AVX>(
            start,
            ray,
            t_max,
            stats,
            #[inline(always)]
            |first, count, mut t_max, stats| {
                stats.prims(count as u64);
                if self.order.is_empty() {
                    if let Some(hit) = self.prims.intersect_run(first, count, ray, data, t_max) {
                        t_max = hit.t;
                        closest = Some(hit);
                    }
                    return (t_max, false);
                }
                for &prim in &self.order[first..first + count] {
                    if let Some(hit) = self.prims.intersect(prim, ray, data, t_max) {
                        t_max = hit.t;
                        closest = Some(hit);
                    }
                }
                (t_max, false)
            },
        );
        closest
    }

    #[inline(always)]
    fn any_hit_kernel<const AVX: bool>(&self, ray: &Ray, t_max: f32) -> bool {
        self.any_hit_from::<AVX>(ROOT, ray, &self.prims.prepare(ray), t_max)
    }

    /// Whether anything below `start` (as in [`Bvh::closest_from`]) blocks `ray`.
    #[inline(always)]
    pub(super) fn any_hit_from<const AVX: bool>(&self, start: u64, ray: &Ray, data: &P::RayData, t_max: f32) -> bool {
        let mut hit = false;
        self.traverse::<(), false, AVX>(
            start,
            ray,
            t_max,
            &mut (),
            #[inline(always)]
            |first, count, t_max, _| {
                hit = if self.order.is_empty() {
                    self.prims.occluded_run(first, count, ray, data, t_max)
                } else {
                    self.order[first..first + count]
                        .iter()
                        .any(|&prim| self.prims.occluded(prim, ray, data, t_max))
                };
                (t_max, hit)
            },
        );
        hit
    }
}

/// The traversals compiled for AVX2 and for AVX-512: the whole loop, with the eight-wide
/// slab test.
#[cfg(target_arch = "x86_64")]
impl<P: PrimitiveSet> Bvh<P> {
    penumbra_core::level_fns! {
        unsafe fn [closest_avx2, closest_avx512]<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
            self.closest_hit::<C, true>(ray, t_max, stats)
        }
    }

    penumbra_core::level_fns! {
        unsafe fn [any_hit_avx2, any_hit_avx512](&self, ray: &Ray, t_max: f32) -> bool {
            self.any_hit_kernel::<true>(ray, t_max)
        }
    }

    penumbra_core::level_fns! {
        unsafe fn [closest_batch_avx2, closest_batch_avx512](&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
            for ((ray, t_max), hit) in rays.iter().zip(hits) {
                *hit = self.closest_hit::<(), true>(ray, *t_max, &mut ());
            }
        }
    }

    penumbra_core::level_fns! {
        unsafe fn [coherent_batch_avx2, coherent_batch_avx512](&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
            self.closest_packets::<F8Avx, true>(rays, hits)
        }
    }

    penumbra_core::level_fns! {
        unsafe fn [any_hit_batch_avx2, any_hit_batch_avx512](&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
            for ((ray, t_max), b) in rays.iter().zip(blocked) {
                *b = self.any_hit_kernel::<true>(ray, *t_max);
            }
        }
    }
}

/// Asks the caches for a node about to be pushed: by the time it is popped its cache lines
/// are more likely there, which helps incoherent rays most.
#[inline(always)]
fn prefetch(node: &WideNode) {
    penumbra_core::simd::prefetch(node);
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
/// `AVX` picks [`slabs_avx`], else [`slabs_sse`].
#[inline(always)]
fn slabs<const AVX: bool>(node: &WideNode, r: &RaySlabs, t_max: f32) -> (u32, [f32; WIDTH]) {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: `AVX` is true only in functions compiled for AVX2, called when the CPU runs it.
        return unsafe { slabs_avx(node, r, t_max) };
    }
    slabs_sse(node, r, t_max)
}

/// [`slabs`] in AVX registers. Safety: the CPU must run AVX; inline it only into functions
/// compiled for AVX (the intrinsics are not inlined elsewhere).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn slabs_avx(node: &WideNode, r: &RaySlabs, t_max: f32) -> (u32, [f32; WIDTH]) {
    use std::arch::x86_64::*;
    // SAFETY: the caller's CPU has AVX, and every load reads a whole row of eight floats.
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
#[inline(always)]
fn slabs_sse(node: &WideNode, r: &RaySlabs, t_max: f32) -> (u32, [f32; WIDTH]) {
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
pub(super) const ROUNDING: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl<P: PrimitiveSet> Traverse for Bvh<P> {
    fn closest<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit> {
        penumbra_core::at_level!(
            avx512: self.closest_avx512(ray, t_max, stats),
            avx2: self.closest_avx2(ray, t_max, stats),
            portable: self.closest_hit::<C, false>(ray, t_max, stats),
        )
    }

    fn any_hit(&self, ray: &Ray, t_max: f32) -> bool {
        penumbra_core::at_level!(
            avx512: self.any_hit_avx512(ray, t_max),
            avx2: self.any_hit_avx2(ray, t_max),
            portable: self.any_hit_kernel::<false>(ray, t_max),
        )
    }

    /// The whole batch in one function compiled for the CPU's level, one ray at a time
    /// (scattered rays: packets did not pay for them, see `bvh_packet.rs`).
    fn closest_batch(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        penumbra_core::at_level!(
            avx512: self.closest_batch_avx512(rays, hits),
            avx2: self.closest_batch_avx2(rays, hits),
            portable: for ((ray, t_max), hit) in rays.iter().zip(hits) {
                *hit = self.closest_hit::<(), false>(ray, *t_max, &mut ());
            },
        )
    }

    /// Coherent rays in packets (`bvh_packet.rs`).
    fn closest_coherent(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        penumbra_core::at_level!(
            avx512: self.coherent_batch_avx512(rays, hits),
            avx2: self.coherent_batch_avx2(rays, hits),
            portable: self.closest_packets::<F8, false>(rays, hits),
        )
    }

    /// The whole batch in one function compiled for the CPU's level.
    fn any_hit_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
        penumbra_core::at_level!(
            avx512: self.any_hit_batch_avx512(rays, blocked),
            avx2: self.any_hit_batch_avx2(rays, blocked),
            portable: for ((ray, t_max), b) in rays.iter().zip(blocked) {
                *b = self.any_hit_kernel::<false>(ray, *t_max);
            },
        )
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
