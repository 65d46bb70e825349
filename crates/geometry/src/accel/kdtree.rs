//! The k-d tree, the axis-aligned BSP tree, built as in Wald and Havran, "On building fast
//! kd-Trees for Ray Tracing, and on doing that in O(N log N)" (2006). Cost model (their
//! eq. 2): C = C_t + lambda C_i (P_L N_L + P_R N_R), P the area ratio of each side, lambda
//! = 0.8 when a side is empty; primitives lying in the plane go to whichever side is
//! cheaper; a node becomes a leaf when no plane beats testing its primitives. Candidate
//! planes come from "perfect splits": each primitive's bounds clipped to the node
//! ([`PrimitiveSet::clip_bounds`]). The events are sorted once; each split classifies the
//! primitives with one sweep, keeps the sorted order of those that fall on one side and
//! sorts and merges only the new events of those clipped by the plane, so the whole build
//! is O(N log N) (their section 4.3). Traversal is the stack-based front-to-back walk: the
//! near child first, the far one later, stopping once a hit lies inside the current
//! node's interval; mailboxing skips primitives met in earlier leaves.

use super::mailbox::{CellVisitor, CellWalk};
use super::{Counter, PrimitiveSet};
use penumbra_core::{Aabb, Ray};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

const TRAVERSAL_COST: f32 = 1.0;
const INTERSECT_COST: f32 = 1.5;
const EMPTY_BONUS: f32 = 0.8;
/// Depth limit of the tree, and so of the traversal stack.
const MAX_STACK: usize = 64;
/// Node indices and leaf sizes share 30 bits with the axis.
const MAX_INDEX: usize = (1 << 30) - 1;

/// Eight bytes, as in pbrt: `word` is the split plane's bits (interior) or the first item
/// (leaf); `bits` holds the axis in its low two bits (3 for a leaf) and above them the
/// second child's index (interior; the first child follows the node) or the item count.
#[derive(Clone, Copy)]
struct Node {
    word: u32,
    bits: u32,
}

impl Node {
    fn leaf(first: usize, count: usize) -> Self {
        Node {
            word: first as u32,
            bits: (count as u32) << 2 | 3,
        }
    }
    fn axis(self) -> usize {
        (self.bits & 3) as usize
    }
    fn split(self) -> f32 {
        f32::from_bits(self.word)
    }
    /// Second child (interior) or item count (leaf).
    fn upper(self) -> u32 {
        self.bits >> 2
    }
}

/// Where a primitive's box starts or ends along one axis, or lies flat (`PLANAR`).
#[derive(Clone, Copy)]
struct Event {
    pos: f32,
    kind: u8,
    prim: u32,
}

const END: u8 = 0;
const PLANAR: u8 = 1;
const START: u8 = 2;

/// Events per axis, each list sorted by position, ends before flat boxes before starts.
type Events = [Vec<Event>; 3];

fn push_events(b: &Aabb, prim: u32, ev: &mut Events) {
    for (k, list) in ev.iter_mut().enumerate() {
        if b.min[k] == b.max[k] {
            list.push(Event {
                pos: b.min[k],
                kind: PLANAR,
                prim,
            });
        } else {
            list.push(Event {
                pos: b.min[k],
                kind: START,
                prim,
            });
            list.push(Event {
                pos: b.max[k],
                kind: END,
                prim,
            });
        }
    }
}

fn before(a: &Event, b: &Event) -> bool {
    a.pos.total_cmp(&b.pos).then(a.kind.cmp(&b.kind)).is_lt()
}

fn sort_events(ev: &mut Events) {
    for list in ev {
        list.sort_unstable_by(|a, b| a.pos.total_cmp(&b.pos).then(a.kind.cmp(&b.kind)));
    }
}

/// Merges two sorted event lists.
fn merge(a: impl Iterator<Item = Event>, b: &[Event], capacity: usize) -> Vec<Event> {
    let mut out = Vec::with_capacity(capacity);
    let mut b = b.iter().peekable();
    for e in a {
        while let Some(&&f) = b.peek() {
            if !before(&f, &e) {
                break;
            }
            out.push(f);
            b.next();
        }
        out.push(e);
    }
    out.extend(b);
    out
}

/// The chosen plane: axis, position, and the side its flat primitives go to.
struct Split {
    cost: f32,
    axis: usize,
    pos: f32,
    planar_left: bool,
}

/// The cheapest plane by one sweep over each axis's events (Wald and Havran, algorithm 4).
fn find_split(ev: &Events, n: usize, bounds: &Aabb) -> Option<Split> {
    let area = bounds.surface_area();
    if area.is_nan() || area <= 0.0 {
        return None;
    }
    let mut best: Option<Split> = None;
    for (axis, list) in ev.iter().enumerate() {
        let (mut left, mut right) = (0usize, n);
        let mut i = 0;
        while i < list.len() {
            let pos = list[i].pos;
            let mut count = [0usize; 3];
            while i < list.len() && list[i].pos == pos {
                count[list[i].kind as usize] += 1;
                i += 1;
            }
            right -= count[END as usize] + count[PLANAR as usize];
            if pos > bounds.min[axis] && pos < bounds.max[axis] {
                let (mut lb, mut rb) = (*bounds, *bounds);
                lb.max[axis] = pos;
                rb.min[axis] = pos;
                let (pl, pr) = (lb.surface_area() / area, rb.surface_area() / area);
                let flat = count[PLANAR as usize];
                for (planar_left, nl, nr) in [(true, left + flat, right), (false, left, right + flat)] {
                    let bonus = if nl == 0 || nr == 0 { EMPTY_BONUS } else { 1.0 };
                    let cost = TRAVERSAL_COST + bonus * INTERSECT_COST * (pl * nl as f32 + pr * nr as f32);
                    if best.as_ref().is_none_or(|b| cost < b.cost) {
                        best = Some(Split {
                            cost,
                            axis,
                            pos,
                            planar_left,
                        });
                    }
                }
            }
            left += count[START as usize] + count[PLANAR as usize];
        }
    }
    best
}

const BOTH: u8 = 0;
const LEFT: u8 = 1;
const RIGHT: u8 = 2;

/// Nodes and items of a tree or subtree.
#[derive(Default)]
struct Tree {
    nodes: Vec<Node>,
    items: Vec<u32>,
}

impl Tree {
    fn leaf(&mut self, ev: &Events) {
        let first = self.items.len();
        let prims = ev[0].iter().filter(|e| e.kind != END).map(|e| e.prim);
        self.items.extend(prims);
        self.nodes.push(Node::leaf(first, self.items.len() - first));
    }

    /// Appends a subtree built on its own, moving its indices past ours.
    fn append(&mut self, sub: Tree) {
        let (nodes, items) = (self.nodes.len() as u32, self.items.len() as u32);
        self.nodes.extend(sub.nodes.into_iter().map(|mut n| {
            if n.axis() == 3 {
                n.word += items;
            } else {
                n.bits += nodes << 2;
            }
            n
        }));
        self.items.extend(sub.items);
    }
}

/// The build's shared state: the primitives, and the nodes plus leaf items made so far
/// over all threads (node and item indices must fit in 30 bits).
struct Build<'a, P> {
    prims: &'a P,
    size: AtomicUsize,
}

impl<P: PrimitiveSet> Build<'_, P> {
    /// Builds the subtree of a node with `n` primitives and events `ev` into `out`;
    /// `forks` more levels split their children between threads, each with its own copy
    /// of the per-primitive `side` marks.
    #[allow(clippy::too_many_arguments)]
    fn node(&self, ev: Events, n: usize, bounds: Aabb, depth: Depth, forks: u32, side: &mut [u8], out: &mut Tree) {
        let leaf_cost = INTERSECT_COST * n as f32;
        // Close to the limit every node becomes a leaf (its n items plus a margin for
        // the subtrees other threads are building).
        let full = self.size.fetch_add(1, Ordering::Relaxed) + 2 * n + 2 >= MAX_INDEX;
        let split = if n <= 1 || depth.splits == 0 || depth.levels == 0 || full {
            None
        } else {
            find_split(&ev, n, &bounds).filter(|s| s.cost < leaf_cost)
        };
        let Some(Split {
            axis, pos, planar_left, ..
        }) = split
        else {
            self.size.fetch_add(n, Ordering::Relaxed);
            return out.leaf(&ev);
        };
        // Classify by one pass over the split axis's events (their algorithm 5).
        for e in &ev[axis] {
            side[e.prim as usize] = BOTH;
        }
        for e in &ev[axis] {
            let s = &mut side[e.prim as usize];
            match e.kind {
                END if e.pos <= pos => *s = LEFT,
                START if e.pos >= pos => *s = RIGHT,
                PLANAR => {
                    *s = if e.pos < pos || (e.pos == pos && planar_left) {
                        LEFT
                    } else {
                        RIGHT
                    }
                }
                _ => {}
            }
        }
        // Primitives cut by the plane get new events from their parts on each side.
        let (mut lb, mut rb) = (bounds, bounds);
        lb.max[axis] = pos;
        rb.min[axis] = pos;
        let (mut new_l, mut new_r): (Events, Events) = Default::default();
        let (mut nl, mut nr) = (0, 0);
        for e in &ev[axis] {
            match (e.kind, side[e.prim as usize]) {
                (START, BOTH) => {
                    for (b, new, count) in [(&lb, &mut new_l, &mut nl), (&rb, &mut new_r, &mut nr)] {
                        let clipped = self.prims.clip_bounds(e.prim, b);
                        if !clipped.is_empty() {
                            push_events(&clipped, e.prim, new);
                            *count += 1;
                        }
                    }
                }
                (END, _) | (_, BOTH) => {}
                (_, LEFT) => nl += 1,
                _ => nr += 1,
            }
        }
        sort_events(&mut new_l);
        sort_events(&mut new_r);
        let mut left: Events = Default::default();
        let mut right: Events = Default::default();
        let sides: &[u8] = side;
        for k in 0..3 {
            let list = &ev[k];
            let only = |s: u8| list.iter().copied().filter(move |e| sides[e.prim as usize] == s);
            left[k] = merge(only(LEFT), &new_l[k], 2 * nl);
            right[k] = merge(only(RIGHT), &new_r[k], 2 * nr);
        }
        drop(ev);
        let me = out.nodes.len();
        out.nodes.push(Node {
            word: pos.to_bits(),
            bits: axis as u32,
        });
        // A cut that leaves one side empty duplicates nothing, so only the depth limit
        // bounds it: a small object in a huge scene may need many such cuts.
        let depth = Depth {
            splits: depth.splits - (nl > 0 && nr > 0) as u32,
            levels: depth.levels - 1,
        };
        if forks > 0 && nl.min(nr) > PARALLEL_MIN {
            let mut side_r = side.to_vec();
            let mut out_r = Tree::default();
            rayon::join(
                || self.node(left, nl, lb, depth, forks - 1, side, out),
                || self.node(right, nr, rb, depth, forks - 1, &mut side_r, &mut out_r),
            );
            out.nodes[me].bits |= (out.nodes.len() as u32) << 2;
            out.append(out_r);
        } else {
            self.node(left, nl, lb, depth, forks, side, out);
            out.nodes[me].bits |= (out.nodes.len() as u32) << 2;
            self.node(right, nr, rb, depth, forks, side, out);
        }
    }
}

/// How much deeper a subtree may grow: splits that put primitives on both sides (the
/// usual 8 + 1.3 log2 N of them, which bounds duplication), and levels of any kind (the
/// traversal stack's size).
#[derive(Clone, Copy)]
struct Depth {
    splits: u32,
    levels: u32,
}

/// Subtrees with fewer primitives than this are built on the thread that splits them.
const PARALLEL_MIN: usize = 4096;

pub struct KdTree<P> {
    prims: Arc<P>,
    nodes: Vec<Node>,
    items: Vec<u32>,
    bounds: Aabb,
}

impl<P: PrimitiveSet> KdTree<P> {
    pub fn new(prims: Arc<P>) -> Self {
        let n = prims.len() as u32;
        let boxes: Vec<Aabb> = (0..n).map(|i| prims.bounds(i)).collect();
        let bounds = boxes.iter().fold(Aabb::EMPTY, |b, p| b.union(*p));
        let mut tree = KdTree {
            prims,
            nodes: Vec::new(),
            items: Vec::new(),
            bounds,
        };
        if n > 0 && !bounds.is_empty() {
            let mut ev: Events = Default::default();
            let mut count = 0;
            for (i, b) in boxes.iter().enumerate() {
                if !b.is_empty() {
                    push_events(b, i as u32, &mut ev);
                    count += 1;
                }
            }
            drop(boxes);
            sort_events(&mut ev);
            let depth = Depth {
                splits: (8.0 + 1.3 * (n as f32).log2()) as u32,
                levels: MAX_STACK as u32,
            };
            let mut side = vec![BOTH; n as usize];
            let build = Build {
                prims: &*tree.prims,
                size: AtomicUsize::new(0),
            };
            let forks = rayon::current_num_threads().next_power_of_two().trailing_zeros() + 3;
            let mut out = Tree::default();
            build.node(ev, count, bounds, depth, forks, &mut side, &mut out);
            (tree.nodes, tree.items) = (out.nodes, out.items);
        }
        tree
    }

    fn walk_cells<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = ray.dir.recip();
        let Some(t_enter) = self.bounds.hit(ray, inv, t_max) else {
            return;
        };
        let t_exit = {
            let t0 = (self.bounds.min - ray.origin) * inv;
            let t1 = (self.bounds.max - ray.origin) * inv;
            t0.max(t1).min_element().min(t_max)
        };
        // One pending far child per level of a tree at most `MAX_STACK` deep.
        let mut stack = [(0u32, 0f32, 0f32); MAX_STACK];
        let mut top = 0;
        let (mut node, mut t0, mut t1) = (0u32, t_enter, t_exit);
        loop {
            stats.node();
            let n = self.nodes[node as usize];
            let a = n.axis();
            if a == 3 {
                let first = n.word as usize;
                if visit(&self.items[first..first + n.upper() as usize], t1, stats) <= t1 {
                    return;
                }
                if top == 0 {
                    return;
                }
                top -= 1;
                (node, t0, t1) = stack[top];
                continue;
            }
            let split = n.split();
            let t_plane = (split - ray.origin[a]) * inv[a];
            let below_first = ray.origin[a] < split || (ray.origin[a] == split && ray.dir[a] <= 0.0);
            let (near, far) = if below_first {
                (node + 1, n.upper())
            } else {
                (n.upper(), node + 1)
            };
            if t_plane.is_nan() {
                // The ray runs inside the plane, where primitives of both sides may touch it.
                stack[top] = (far, t0, t1);
                top += 1;
                node = near;
            } else if t_plane > t1 || t_plane <= 0.0 {
                node = near;
            } else if t_plane < t0 {
                node = far;
            } else {
                stack[top] = (far, t_plane, t1);
                top += 1;
                node = near;
                t1 = t_plane;
            }
        }
    }
}

impl<P: PrimitiveSet> CellWalk for KdTree<P> {
    type Prims = P;
    fn prims(&self) -> &P {
        &self.prims
    }
    fn walk<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>) {
        self.walk_cells(ray, t_max, stats, visit);
    }
    fn extent(&self) -> Aabb {
        self.bounds
    }
    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.items.capacity() * std::mem::size_of::<u32>()
    }
}
