//! The k-d tree, the axis-aligned BSP tree: space split by planes chosen with the surface
//! area heuristic and the cost model of Wald and Havran, "On building fast kd-Trees for Ray
//! Tracing, and on doing that in O(N log N)" (2006): C = C_t + C_i (P_L N_L + P_R N_R),
//! with P the area ratio of each side and a 20% bonus for cutting off empty space; a node
//! becomes a leaf when no plane beats testing its primitives. Candidate planes are the
//! primitives' bounds clipped to the node, swept per axis after sorting (O(N log^2 N)
//! rather than the paper's single presort). Traversal is the stack-based front-to-back
//! walk: the near child first, the far one later, stopping once a hit lies inside the
//! current node's interval; mailboxing skips primitives met in earlier leaves.

use super::mailbox::{CellVisitor, CellWalk};
use super::{Counter, PrimitiveSet};
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

const TRAVERSAL_COST: f32 = 1.0;
const INTERSECT_COST: f32 = 1.5;
const EMPTY_BONUS: f32 = 0.8;
/// Depth limit of the tree, and so of the traversal stack (the usual 8 + 1.3 log2 N stays
/// below it up to about 2^43 primitives).
const MAX_STACK: usize = 64;

/// Interior: `axis` 0-2, split plane, second child at `index` (the first follows the
/// node). Leaf (`axis` 3): primitives `items[index..index + count]`.
#[derive(Clone, Copy)]
struct Node {
    split: f32,
    axis: u8,
    index: u32,
    count: u32,
}

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
            let max_depth = ((8.0 + 1.3 * (n as f32).log2()) as u32).min(MAX_STACK as u32);
            tree.build(&boxes, (0..n).collect(), bounds, max_depth);
        }
        tree
    }

    fn leaf(&mut self, ids: &[u32]) {
        self.nodes.push(Node {
            split: 0.0,
            axis: 3,
            index: self.items.len() as u32,
            count: ids.len() as u32,
        });
        self.items.extend_from_slice(ids);
    }

    fn build(&mut self, boxes: &[Aabb], ids: Vec<u32>, bounds: Aabb, depth_left: u32) {
        let n = ids.len();
        let leaf_cost = INTERSECT_COST * n as f32;
        if n <= 1 || depth_left == 0 {
            return self.leaf(&ids);
        }
        let area = bounds.surface_area();
        let mut best: Option<(f32, usize, f32)> = None;
        for axis in 0..3 {
            // Start and end events of the clipped bounds, sorted; ends before starts at ties.
            let mut events: Vec<(f32, u8)> = Vec::with_capacity(2 * n);
            for &i in &ids {
                let b = boxes[i as usize];
                events.push((b.min[axis].max(bounds.min[axis]), 1));
                events.push((b.max[axis].min(bounds.max[axis]), 0));
            }
            events.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let (mut left, mut right) = (0usize, n);
            let mut k = 0;
            while k < events.len() {
                let plane = events[k].0;
                let (mut ends, mut starts) = (0, 0);
                while k < events.len() && events[k].0 == plane {
                    if events[k].1 == 0 {
                        ends += 1
                    } else {
                        starts += 1
                    }
                    k += 1;
                }
                right -= ends;
                if plane > bounds.min[axis] && plane < bounds.max[axis] {
                    let (mut lb, mut rb) = (bounds, bounds);
                    lb.max[axis] = plane;
                    rb.min[axis] = plane;
                    let bonus = if left == 0 || right == 0 { EMPTY_BONUS } else { 1.0 };
                    let cost = TRAVERSAL_COST
                        + bonus * INTERSECT_COST * (lb.surface_area() * left as f32 + rb.surface_area() * right as f32)
                            / area;
                    if best.is_none_or(|b| cost < b.0) {
                        best = Some((cost, axis, plane));
                    }
                }
                left += starts;
            }
        }
        let Some((_, axis, split)) = best.filter(|b| b.0 < leaf_cost) else {
            return self.leaf(&ids);
        };
        // Primitives touching each side (those spanning the plane go to both).
        let below: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| boxes[i as usize].min[axis] < split)
            .collect();
        let above: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| boxes[i as usize].max[axis] > split || boxes[i as usize].min[axis] >= split)
            .collect();

        let (mut lb, mut rb) = (bounds, bounds);
        lb.max[axis] = split;
        rb.min[axis] = split;
        let me = self.nodes.len();
        self.nodes.push(Node {
            split,
            axis: axis as u8,
            index: 0,
            count: 0,
        });
        self.build(boxes, below, lb, depth_left - 1);
        self.nodes[me].index = self.nodes.len() as u32;
        self.build(boxes, above, rb, depth_left - 1);
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
        // One pending far child per level of a tree at most `self.max_depth` deep.
        let mut stack = [(0u32, 0f32, 0f32); MAX_STACK];
        let mut top = 0;
        let (mut node, mut t0, mut t1) = (0u32, t_enter, t_exit);
        loop {
            stats.node();
            let n = self.nodes[node as usize];
            if n.axis == 3 {
                if visit(&self.items[n.index as usize..(n.index + n.count) as usize], t1, stats) <= t1 {
                    return;
                }
                if top == 0 {
                    return;
                }
                top -= 1;
                (node, t0, t1) = stack[top];
                continue;
            }
            let a = n.axis as usize;
            let t_plane = (n.split - ray.origin[a]) * inv[a];
            let below_first = ray.origin[a] < n.split || (ray.origin[a] == n.split && ray.dir[a] <= 0.0);
            let (near, far) = if below_first {
                (node + 1, n.index)
            } else {
                (n.index, node + 1)
            };
            if t_plane > t1 || t_plane <= 0.0 || t_plane.is_nan() {
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
