//! Acceleration structures: given a set of primitives, find the closest hit along a ray
//! (`intersect`) or whether anything blocks it (`occluded`, for shadow rays).
//!
//! Every accelerator is built over a [`PrimitiveSet`] and answers through the [`Accel`]
//! trait, so they can be swapped per scene (`accel = "..."` in the native format, `--accel`
//! on the command line) and checked against each other. Primitives with unbounded extent
//! (infinite planes) are kept out of the accelerator and tested on every ray.
//!
//! Adding an accelerator: a new file with a `build(prims: Arc<P>) -> impl Accel`, one
//! variant in [`AccelKind`] and one arm in [`build_accel`].

mod bvh;
mod bvh_build;
mod bvh_packet;
mod grid;
mod kdtree;
mod list;
mod mailbox;
mod nested_grid;
mod octree;
mod packet;

pub use bvh::Bvh;
pub use grid::{Grid, GridParams};
pub use kdtree::KdTree;
pub use list::{closest_of, List};
pub use octree::{Octree, Policy as OctreePolicy};
pub use packet::{RayPacket, PACKET};

use crate::Hit;
use penumbra_core::lanes::Lane8;
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

/// A closest-hit and any-hit query over a set of primitives.
pub trait Accel: Send + Sync {
    /// The closest hit in `(0, t_max)`.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit>;
    /// Whether anything is hit in `(0, t_max)`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;
    fn bounds(&self) -> Aabb;
    /// [`Accel::intersect`], also counting the nodes (or cells) visited and the primitives
    /// tested, for benchmarks and cost images.
    fn intersect_counted(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit>;
    /// Bytes of memory the structure holds, not counting the primitives themselves.
    fn memory_bytes(&self) -> usize;
    /// Bytes of the primitive data the structure reads (for a mesh, its packed vertices):
    /// its own leaf-ordered copy, or the set it was built over.
    fn primitive_bytes(&self) -> usize;
    /// [`Accel::intersect`] for each `(ray, t_max)` of `rays`, into `hits`: one call (and
    /// one choice of SIMD level) for a whole batch of a wavefront's rays.
    fn intersect_batch(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]);
    /// [`Accel::occluded`] for each `(ray, t_max)` of `rays`, into `blocked`.
    fn occluded_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]);
    /// [`Accel::intersect_batch`] for rays that run nearly parallel from nearby origins
    /// in runs of eight (a tile's camera rays), which a structure may trace in packets.
    fn intersect_coherent(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        self.intersect_batch(rays, hits)
    }
}

/// What an accelerator implements; [`Accel`] follows from it, with the closest-hit query
/// generic over a [`Counter`] so that counting costs nothing when it is not asked for.
pub trait Traverse: Send + Sync {
    fn closest<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C) -> Option<Hit>;
    fn any_hit(&self, ray: &Ray, t_max: f32) -> bool;
    fn extent(&self) -> Aabb;
    fn bytes(&self) -> usize;
    fn prim_bytes(&self) -> usize;
    /// [`Accel::intersect_batch`], one ray after another.
    fn closest_batch(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        for ((ray, t_max), hit) in rays.iter().zip(hits) {
            *hit = self.closest(ray, *t_max, &mut ());
        }
    }
    /// [`Accel::intersect_coherent`]: [`Traverse::closest_batch`] unless the structure
    /// has packets.
    fn closest_coherent(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        self.closest_batch(rays, hits)
    }
    /// [`Accel::occluded_batch`], one ray after another.
    fn any_hit_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
        for ((ray, t_max), b) in rays.iter().zip(blocked) {
            *b = self.any_hit(ray, *t_max);
        }
    }
}

impl<T: Traverse> Accel for T {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.closest(ray, t_max, &mut ())
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.any_hit(ray, t_max)
    }
    fn bounds(&self) -> Aabb {
        self.extent()
    }
    fn intersect_counted(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        self.closest(ray, t_max, stats)
    }
    fn memory_bytes(&self) -> usize {
        self.bytes()
    }
    fn primitive_bytes(&self) -> usize {
        self.prim_bytes()
    }
    fn intersect_batch(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        self.closest_batch(rays, hits)
    }
    fn occluded_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
        self.any_hit_batch(rays, blocked)
    }
    fn intersect_coherent(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        self.closest_coherent(rays, hits)
    }
}

/// What one or more traversals cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Nodes or cells visited.
    pub nodes: u64,
    /// Primitive intersection tests.
    pub prims: u64,
}

/// Counts traversal work; the no-op implementation for `()` compiles away.
pub trait Counter {
    fn node(&mut self);
    fn prims(&mut self, n: u64);
}

impl Counter for () {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn prims(&mut self, _: u64) {}
}

impl Counter for TraversalStats {
    #[inline(always)]
    fn node(&mut self) {
        self.nodes += 1;
    }
    #[inline(always)]
    fn prims(&mut self, n: u64) {
        self.prims += n;
    }
}

/// An empty slot in a [`PrimitiveSet::reordered`] order.
pub const PAD: u32 = u32::MAX;

/// What an accelerator is built over: indexable primitives with bounds and a ray test.
pub trait PrimitiveSet: Send + Sync + 'static {
    /// What the primitives' tests need of a ray, computed once per query.
    type RayData;
    /// What the packet tests ([`PrimitiveSet::intersect_run_packet`]) need of a packet's
    /// rays, made once per packet (`()` for a set without packet tests).
    type PacketData;
    fn prepare(&self, ray: &Ray) -> Self::RayData;
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    fn bounds(&self, i: u32) -> Aabb;
    /// The hit of primitive `i` in `(0, t_max)`, with `Hit::prim == i` (for a set made by
    /// [`PrimitiveSet::reordered`], the number `i` had in the original set).
    fn intersect(&self, i: u32, ray: &Ray, data: &Self::RayData, t_max: f32) -> Option<Hit>;
    fn occluded(&self, i: u32, ray: &Ray, data: &Self::RayData, t_max: f32) -> bool {
        self.intersect(i, ray, data, t_max).is_some()
    }
    /// A copy whose primitive `k` is primitive `order[k]` of this set (nothing when
    /// `order[k]` is [`PAD`]), answering hits with the original numbers, when the set can be
    /// reordered. An accelerator whose leaves hold runs of primitives stores them in leaf
    /// order, so a leaf's primitives are adjacent in memory and need no index array.
    fn reordered(&self, _order: &[u32]) -> Option<Self>
    where
        Self: Sized,
    {
        None
    }
    /// How many primitives the set tests at once (its SIMD width). A set with a group above
    /// one can be [reordered](PrimitiveSet::reordered), and runs that start at multiples of
    /// the group are tested fastest.
    fn group(&self) -> usize {
        1
    }
    /// The closest hit among primitives `first..first + count`.
    #[inline]
    fn intersect_run(&self, first: usize, count: usize, ray: &Ray, data: &Self::RayData, t_max: f32) -> Option<Hit> {
        let mut t_max = t_max;
        let mut closest = None;
        for i in first..first + count {
            if let Some(hit) = self.intersect(i as u32, ray, data, t_max) {
                t_max = hit.t;
                closest = Some(hit);
            }
        }
        closest
    }
    /// Whether any of primitives `first..first + count` is hit.
    #[inline]
    fn occluded_run(&self, first: usize, count: usize, ray: &Ray, data: &Self::RayData, t_max: f32) -> bool {
        (first..first + count).any(|i| self.occluded(i as u32, ray, data, t_max))
    }
    /// Rays of one class can share a packet ([`PrimitiveSet::prepare_packet`] accepts
    /// them): the dominant axis of the direction for triangles' watertight test, whose
    /// frame depends on it. At most three classes (`packet::CLASSES`).
    fn packet_class(&self, _ray: &Ray) -> usize {
        0
    }
    /// The packet tests' data for the rays of `p` (lanes `p.mask`), if the set has packet
    /// tests and those rays can share them; `None`: the leaves test the rays one by one.
    fn prepare_packet(&self, _p: &RayPacket<Self::RayData>) -> Option<Self::PacketData> {
        None
    }
    /// [`PrimitiveSet::intersect_run`] for the rays of `p` in `lanes`, at once: each lane's
    /// `t_max` and hit are updated as the one-ray run would update them, to the bit.
    #[inline(always)]
    fn intersect_run_packet<L: Lane8>(
        &self,
        first: usize,
        count: usize,
        p: &RayPacket<Self::RayData>,
        _data: &Self::PacketData,
        lanes: u32,
        (t_max, hits): (&mut [f32; PACKET], &mut [Option<Hit>; PACKET]),
    ) {
        for j in (0..PACKET).filter(|j| lanes >> j & 1 != 0) {
            if let Some(hit) = self.intersect_run(first, count, &p.rays[j], &p.data[j], t_max[j]) {
                (t_max[j], hits[j]) = (hit.t, Some(hit));
            }
        }
    }
    /// Bytes of memory the set holds for its primitives' data.
    fn memory_bytes(&self) -> usize {
        0
    }
    /// Whether primitive `i` may overlap box `b`: exact for triangles, by bounding box for
    /// the rest (spatial subdivisions store a primitive in each cell it overlaps).
    fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        self.bounds(i).overlaps(b)
    }
    /// Bounds of the part of primitive `i` inside box `b`, or a box containing it (the
    /// k-d tree's "perfect splits"); empty if the primitive misses `b`. Triangles are
    /// clipped; the rest take their bounding box cut to `b`.
    fn clip_bounds(&self, i: u32, b: &Aabb) -> Aabb {
        self.bounds(i).intersection(*b)
    }
}

/// For a set stored in packets of four slots (slot `i` is lane `i % 4` of packet `i / 4`):
/// the packets holding slots `first..first + count`, each with the mask of those slots'
/// lanes.
#[inline(always)]
pub(crate) fn packets_of(first: usize, count: usize) -> impl Iterator<Item = (usize, u32)> {
    let end = first + count;
    (first / 4..end.div_ceil(4)).map(move |packet| {
        let lo = first.max(packet * 4) - packet * 4;
        let hi = end.min(packet * 4 + 4) - packet * 4;
        (packet, (0b1111u32 >> (4 - hi)) & !((1u32 << lo) - 1))
    })
}

/// The accelerators a scene can choose.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AccelKind {
    /// Every primitive tested against every ray: the reference.
    List,
    /// Bounding volume hierarchy, binned SAH build.
    #[default]
    Bvh,
    /// Regular grid with 3D-DDA traversal and mailboxing.
    Grid,
    /// Adaptive grid: crowded cells hold sub-grids.
    NestedGrid,
    /// Octree, primitives pushed down to every leaf they overlap.
    Octree,
    /// Octree, primitives that straddle a split kept at the intermediate node.
    OctreeKeep,
    /// SAH k-d tree.
    KdTree,
}

impl AccelKind {
    pub const NAMES: [&'static str; 7] = ["list", "bvh", "grid", "nested-grid", "octree", "octree-keep", "kdtree"];
    /// Every accelerator, in the order of [`AccelKind::NAMES`].
    pub const ALL: [AccelKind; 7] = [
        AccelKind::List,
        AccelKind::Bvh,
        AccelKind::Grid,
        AccelKind::NestedGrid,
        AccelKind::Octree,
        AccelKind::OctreeKeep,
        AccelKind::KdTree,
    ];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "list" => Some(AccelKind::List),
            "bvh" => Some(AccelKind::Bvh),
            "grid" => Some(AccelKind::Grid),
            "nested-grid" => Some(AccelKind::NestedGrid),
            "octree" => Some(AccelKind::Octree),
            "octree-keep" => Some(AccelKind::OctreeKeep),
            "kdtree" => Some(AccelKind::KdTree),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            AccelKind::List => "list",
            AccelKind::Bvh => "bvh",
            AccelKind::Grid => "grid",
            AccelKind::NestedGrid => "nested-grid",
            AccelKind::Octree => "octree",
            AccelKind::OctreeKeep => "octree-keep",
            AccelKind::KdTree => "kdtree",
        }
    }
}

/// Builds the accelerator `kind` over `prims`.
pub fn build_accel<P: PrimitiveSet>(kind: AccelKind, prims: Arc<P>) -> Box<dyn Accel> {
    let (bounded, unbounded): (Vec<u32>, Vec<u32>) =
        (0..prims.len() as u32).partition(|&i| prims.bounds(i).is_finite());
    if unbounded.is_empty() {
        return build_bounded(kind, prims);
    }
    let inner = build_bounded(
        kind,
        Arc::new(Subset {
            prims: prims.clone(),
            ids: bounded,
        }),
    );
    Box::new(WithUnbounded {
        inner,
        unbounded: List::new(Arc::new(Subset { prims, ids: unbounded })),
    })
}

fn build_bounded<P: PrimitiveSet>(kind: AccelKind, prims: Arc<P>) -> Box<dyn Accel> {
    match kind {
        AccelKind::List => Box::new(List::new(prims)),
        AccelKind::Bvh => Box::new(Bvh::new(prims)),
        AccelKind::Grid => Box::new(Grid::new(prims, grid::DEFAULT_LAMBDA)),
        AccelKind::NestedGrid => Box::new(nested_grid::build(prims)),
        AccelKind::Octree => Box::new(Octree::new(prims, octree::Policy::Lowest)),
        AccelKind::OctreeKeep => Box::new(Octree::new(prims, octree::Policy::Keep)),
        AccelKind::KdTree => Box::new(KdTree::new(prims)),
    }
}

/// Some primitives of a set, renumbered `0..ids.len()`; hits keep the original numbers.
struct Subset<P> {
    prims: Arc<P>,
    ids: Vec<u32>,
}

impl<P: PrimitiveSet> PrimitiveSet for Subset<P> {
    type RayData = P::RayData;
    type PacketData = ();
    fn prepare(&self, ray: &Ray) -> P::RayData {
        self.prims.prepare(ray)
    }
    fn len(&self) -> usize {
        self.ids.len()
    }
    fn bounds(&self, i: u32) -> Aabb {
        self.prims.bounds(self.ids[i as usize])
    }
    fn intersect(&self, i: u32, ray: &Ray, data: &P::RayData, t_max: f32) -> Option<Hit> {
        self.prims.intersect(self.ids[i as usize], ray, data, t_max)
    }
    fn occluded(&self, i: u32, ray: &Ray, data: &P::RayData, t_max: f32) -> bool {
        self.prims.occluded(self.ids[i as usize], ray, data, t_max)
    }
    fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        self.prims.overlaps(self.ids[i as usize], b)
    }
    fn clip_bounds(&self, i: u32, b: &Aabb) -> Aabb {
        self.prims.clip_bounds(self.ids[i as usize], b)
    }
}

/// An accelerator over the bounded primitives, plus a list of unbounded ones.
struct WithUnbounded<P> {
    inner: Box<dyn Accel>,
    unbounded: List<Subset<P>>,
}

impl<P: PrimitiveSet> Accel for WithUnbounded<P> {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let near = self.unbounded.intersect(ray, t_max);
        let t = near.map_or(t_max, |h| h.t);
        self.inner.intersect(ray, t).or(near)
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.unbounded.occluded(ray, t_max) || self.inner.occluded(ray, t_max)
    }
    fn bounds(&self) -> Aabb {
        Aabb::INFINITE
    }
    fn intersect_counted(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        let near = self.unbounded.intersect_counted(ray, t_max, stats);
        let t = near.map_or(t_max, |h| h.t);
        self.inner.intersect_counted(ray, t, stats).or(near)
    }
    fn memory_bytes(&self) -> usize {
        self.inner.memory_bytes() + self.unbounded.memory_bytes() + std::mem::size_of::<Self>()
    }
    fn primitive_bytes(&self) -> usize {
        self.inner.primitive_bytes()
    }
    fn intersect_batch(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        closest_of_two(&self.unbounded, &*self.inner, |h| h, (rays, false), hits);
    }
    fn intersect_coherent(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        closest_of_two(&self.unbounded, &*self.inner, |h| h, (rays, true), hits);
    }
    fn occluded_batch(&self, rays: &[(Ray, f32)], blocked: &mut [bool]) {
        occluded_by_either(&self.unbounded, &*self.inner, rays, blocked);
    }
}

/// Rays a batch over two structures handles at a time (room on the stack).
const CHUNK: usize = 64;

/// [`Accel::intersect_batch`] (or, for `coherent` rays, [`Accel::intersect_coherent`]) over
/// two structures: `first`'s hits (renumbered by `map`), then `second`'s, each ray limited
/// to its hit in `first`, as `second.intersect(ray, t).or(near)` answers one ray.
pub(crate) fn closest_of_two(
    first: &dyn Accel,
    second: &dyn Accel,
    map: impl Fn(Hit) -> Hit,
    (rays, coherent): (&[(Ray, f32)], bool),
    hits: &mut [Option<Hit>],
) {
    let trace = |accel: &dyn Accel, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]| {
        if coherent {
            accel.intersect_coherent(rays, hits)
        } else {
            accel.intersect_batch(rays, hits)
        }
    };
    for (rays, hits) in rays.chunks(CHUNK).zip(hits.chunks_mut(CHUNK)) {
        trace(first, rays, hits);
        let mut limited = [(Ray::new(glam::Vec3::ZERO, glam::Vec3::Z), 0.0); CHUNK];
        for ((l, (ray, t_max)), hit) in limited.iter_mut().zip(rays).zip(hits.iter_mut()) {
            *hit = hit.map(&map);
            *l = (*ray, hit.map_or(*t_max, |h| h.t));
        }
        let mut closer = [None; CHUNK];
        trace(second, &limited[..rays.len()], &mut closer[..rays.len()]);
        for (hit, c) in hits.iter_mut().zip(closer) {
            if c.is_some() {
                *hit = c;
            }
        }
    }
}

/// [`Accel::occluded_batch`] over two structures: `second` asked only about the rays
/// `first` left unblocked.
pub(crate) fn occluded_by_either(first: &dyn Accel, second: &dyn Accel, rays: &[(Ray, f32)], blocked: &mut [bool]) {
    for (rays, blocked) in rays.chunks(CHUNK).zip(blocked.chunks_mut(CHUNK)) {
        first.occluded_batch(rays, blocked);
        let mut open = [(Ray::new(glam::Vec3::ZERO, glam::Vec3::Z), 0.0); CHUNK];
        let mut which = [0; CHUNK];
        let mut n = 0;
        for (k, (ray, b)) in rays.iter().zip(blocked.iter()).enumerate() {
            if !b {
                (open[n], which[n]) = (*ray, k);
                n += 1;
            }
        }
        let mut second_blocked = [false; CHUNK];
        second.occluded_batch(&open[..n], &mut second_blocked[..n]);
        for (&k, &b) in which[..n].iter().zip(&second_blocked) {
            blocked[k] = b;
        }
    }
}

#[cfg(test)]
mod agreement_tests;
