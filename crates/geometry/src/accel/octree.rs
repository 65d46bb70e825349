//! The octree (Glassner, "Space Subdivision for Fast Ray Tracing", 1984): a cube split at
//! its centre into eight, recursively, where more than `MAX_ITEMS` primitives crowd a node,
//! down to `MAX_DEPTH`. Two insertion policies:
//! - `Policy::Lowest` (`octree`): a primitive goes down into every child it overlaps (exact
//!   for triangles), so it is listed in all the leaves it touches; mailboxing keeps each
//!   (ray, primitive) test to one.
//! - `Policy::Keep` (`octree-keep`): a primitive goes down only into a child that contains
//!   it whole; one that straddles a split stays at the intermediate node. Nothing is
//!   duplicated, but large primitives are tested by every ray that enters their node.
//!
//! Traversal visits a node's own primitives, then its children front to back by the
//! distance at which the ray enters them, skipping those beyond the closest hit.

use super::mailbox::{CellVisitor, CellWalk};
use super::{Counter, PrimitiveSet};
use glam::Vec3;
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

const MAX_ITEMS: usize = 8;
const MAX_DEPTH: u32 = 10;
/// A split whose children list more than this many times the node's primitives mostly
/// copies large primitives around: the node stays a leaf.
const MAX_DUPLICATION: usize = 3;
const NO_CHILDREN: u32 = u32::MAX;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Policy {
    Lowest,
    Keep,
}

struct Node {
    bounds: Aabb,
    /// Index of the first of eight consecutive children, or `NO_CHILDREN`.
    children: u32,
    /// This node's primitives: `items[first..first + count]`.
    first: u32,
    count: u32,
}

pub struct Octree<P> {
    prims: Arc<P>,
    nodes: Vec<Node>,
    items: Vec<u32>,
}

impl<P: PrimitiveSet> Octree<P> {
    pub fn new(prims: Arc<P>, policy: Policy) -> Self {
        let n = prims.len() as u32;
        let bounds = (0..n).fold(Aabb::EMPTY, |b, i| b.union(prims.bounds(i)));
        let mut tree = Octree {
            prims,
            nodes: Vec::new(),
            items: Vec::new(),
        };
        if n == 0 || bounds.is_empty() {
            return tree;
        }
        // A cube around the bounds, so children stay cubes.
        let half = 0.5 * bounds.extent().max_element().max(1e-6) * 1.0001;
        let c = bounds.centroid();
        let cube = Aabb {
            min: c - Vec3::splat(half),
            max: c + Vec3::splat(half),
        };
        tree.nodes.push(Node {
            bounds: cube,
            children: NO_CHILDREN,
            first: 0,
            count: 0,
        });
        let ids: Vec<u32> = (0..n).collect();
        tree.insert(0, ids, policy, 0);
        tree
    }

    /// Fills node `node` with `ids`, splitting it when crowded.
    fn insert(&mut self, node: usize, ids: Vec<u32>, policy: Policy, depth: u32) {
        if ids.len() <= MAX_ITEMS || depth >= MAX_DEPTH {
            self.set_items(node, &ids);
            return;
        }
        let b = self.nodes[node].bounds;
        let c = b.centroid();
        let octants: Vec<Aabb> = (0..8)
            .map(|k| {
                let pick = |bit: u32, axis: usize| {
                    if k & bit == 0 {
                        (b.min[axis], c[axis])
                    } else {
                        (c[axis], b.max[axis])
                    }
                };
                let (x, y, z) = (pick(1, 0), pick(2, 1), pick(4, 2));
                Aabb {
                    min: Vec3::new(x.0, y.0, z.0),
                    max: Vec3::new(x.1, y.1, z.1),
                }
            })
            .collect();
        let mut kept = Vec::new();
        let mut per_child: Vec<Vec<u32>> = vec![Vec::new(); 8];
        for &i in &ids {
            match policy {
                Policy::Lowest => {
                    for (k, o) in octants.iter().enumerate() {
                        if self.prims.overlaps(i, o) {
                            per_child[k].push(i);
                        }
                    }
                }
                Policy::Keep => {
                    let pb = self.prims.bounds(i);
                    match octants
                        .iter()
                        .position(|o| pb.min.cmpge(o.min).all() && pb.max.cmple(o.max).all())
                    {
                        Some(k) => per_child[k].push(i),
                        None => kept.push(i),
                    }
                }
            }
        }
        // A split that mostly copies primitives into several children gains little.
        let refs: usize = per_child.iter().map(Vec::len).sum();
        if policy == Policy::Lowest && refs > MAX_DUPLICATION * ids.len() {
            self.set_items(node, &ids);
            return;
        }
        self.set_items(node, &kept);
        let first_child = self.nodes.len() as u32;
        self.nodes[node].children = first_child;
        for o in &octants {
            self.nodes.push(Node {
                bounds: *o,
                children: NO_CHILDREN,
                first: 0,
                count: 0,
            });
        }
        for (k, child_ids) in per_child.into_iter().enumerate() {
            self.insert(first_child as usize + k, child_ids, policy, depth + 1);
        }
    }

    fn set_items(&mut self, node: usize, ids: &[u32]) {
        self.nodes[node].first = self.items.len() as u32;
        self.nodes[node].count = ids.len() as u32;
        self.items.extend_from_slice(ids);
    }

    /// Visits nodes front to back, culling those beyond the closest distance the visitor
    /// reports.
    fn walk_nodes<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = ray.dir.recip();
        let mut t_max = t_max;
        // At most 8 entries per level of a tree at most MAX_DEPTH deep: no allocation per ray.
        let mut stack = [(0u32, 0f32); 8 * (MAX_DEPTH as usize + 1)];
        let mut top = 0;
        if let Some(t) = self.nodes[0].bounds.hit(ray, inv, t_max) {
            stack[0] = (0, t);
            top = 1;
        }
        while top > 0 {
            top -= 1;
            let (index, t_near) = stack[top];
            if t_near > t_max {
                continue;
            }
            stats.node();
            let node = &self.nodes[index as usize];
            let closest = visit(
                &self.items[node.first as usize..(node.first + node.count) as usize],
                t_max,
                stats,
            );
            if closest == f32::NEG_INFINITY {
                return;
            }
            t_max = t_max.min(closest);
            if node.children == NO_CHILDREN {
                continue;
            }
            // Push the children the ray enters, farthest first, so the nearest is popped next.
            let start = top;
            for c in node.children..node.children + 8 {
                let n = &self.nodes[c as usize];
                if n.count == 0 && n.children == NO_CHILDREN {
                    continue;
                }
                if let Some(t) = n.bounds.hit(ray, inv, t_max) {
                    stack[top] = (c, t);
                    top += 1;
                }
            }
            stack[start..top].sort_unstable_by(|a, b| b.1.total_cmp(&a.1));
        }
    }
}

impl<P: PrimitiveSet> CellWalk for Octree<P> {
    type Prims = P;
    fn prims(&self) -> &P {
        &self.prims
    }
    fn walk<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>) {
        self.walk_nodes(ray, t_max, stats, visit);
    }
    fn extent(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }
    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.items.capacity() * std::mem::size_of::<u32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instance::MeshTriangles;
    use crate::TriangleMesh;
    use penumbra_core::Pcg32;

    #[test]
    fn policies_duplicate_or_keep() {
        // 300 small triangles plus one large triangle across the centre of the cube.
        let mut rng = Pcg32::new(8, 0);
        let mut m = TriangleMesh::default();
        for i in 0..300u32 {
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 10.0;
            m.positions.extend([c, c + Vec3::X * 0.1, c + Vec3::Y * 0.1]);
            m.indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        m.positions.extend([
            Vec3::new(1.0, 5.0, 1.0),
            Vec3::new(9.0, 5.0, 1.0),
            Vec3::new(5.0, 5.0, 9.0),
        ]);
        m.indices.push([900, 901, 902]);
        let prims = Arc::new(MeshTriangles::new(Arc::new(m)));
        let keep = Octree::new(prims.clone(), Policy::Keep);
        let lowest = Octree::new(prims, Policy::Lowest);
        assert_eq!(keep.items.len(), 301, "keep lists every primitive exactly once");
        assert!(keep.nodes[0].count >= 1, "the large triangle stays at the root");
        assert!(
            lowest.items.len() > 301,
            "lowest copies the large triangle into many leaves"
        );
        assert_eq!(lowest.nodes[0].count, 0, "lowest keeps nothing at the root");
    }
}
