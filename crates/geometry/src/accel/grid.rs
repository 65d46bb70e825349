//! The regular grid (Fujimoto et al. 1986): voxels of equal size over the scene's bounds,
//! each listing the primitives that really overlap it (exact triangle-box tests for
//! triangles), traversed cell by cell along the ray with the 3D-DDA of Amanatides and Woo,
//! "A Fast Voxel Traversal Algorithm for Ray Tracing" (1987). With mailboxing a primitive
//! spanning many cells is tested once per ray, and the walk stops at the first cell whose
//! exit lies beyond the closest hit found so far.
//!
//! Resolution: about `lambda * N` cells in all, shaped like the bounds (cell side
//! `(V / (lambda N))^(1/3)`), at most 512 per axis; `lambda` defaults to 4.

use super::mailbox::{CellVisitor, CellWalk};
use super::{Counter, PrimitiveSet};
use glam::{UVec3, Vec3};
use penumbra_core::{Aabb, Ray};
use rayon::prelude::*;
use std::sync::Arc;

/// Cells per primitive the grid aims for.
pub const DEFAULT_LAMBDA: f32 = 4.0;
const MAX_RESOLUTION: u32 = 512;

pub struct Grid<P> {
    prims: Arc<P>,
    root: Level,
}

/// One level of a (possibly nested) grid.
struct Level {
    bounds: Aabb,
    res: UVec3,
    cell_size: Vec3,
    /// `starts[c]..starts[c + 1]` indexes the primitives of cell `c` in `items`.
    starts: Vec<u32>,
    items: Vec<u32>,
    /// For a nested grid: per cell, the index of its sub-grid in `children` or `NO_CHILD`.
    child: Vec<u32>,
    children: Vec<Level>,
}

const NO_CHILD: u32 = u32::MAX;

/// How a grid subdivides.
#[derive(Clone, Copy, Debug)]
pub struct GridParams {
    pub lambda: f32,
    /// Cells holding more primitives than this get a sub-grid...
    pub max_items: usize,
    /// ...down to this many levels below the top (0: a regular grid).
    pub max_depth: u32,
}

/// The grid shape for `n` primitives in `bounds`: resolution and padded bounds.
pub(crate) fn grid_shape(bounds: Aabb, n: usize, lambda: f32) -> (UVec3, Aabb) {
    // Give flat axes some thickness so every cell has volume.
    let pad = (bounds.extent().max_element() * 1e-3).max(1e-3);
    let grow = Vec3::select(bounds.extent().cmple(Vec3::splat(pad)), Vec3::splat(pad), Vec3::ZERO);
    let bounds = Aabb {
        min: bounds.min - grow,
        max: bounds.max + grow,
    };
    let e = bounds.extent();
    let side = (e.x * e.y * e.z / (lambda * n.max(1) as f32)).cbrt();
    let res = (e / side)
        .ceil()
        .clamp(Vec3::ONE, Vec3::splat(MAX_RESOLUTION as f32))
        .as_uvec3();
    (res, bounds)
}

impl<P: PrimitiveSet> Grid<P> {
    /// A regular grid.
    pub fn new(prims: Arc<P>, lambda: f32) -> Self {
        Self::with_params(
            prims,
            GridParams {
                lambda,
                max_items: usize::MAX,
                max_depth: 0,
            },
        )
    }

    pub fn with_params(prims: Arc<P>, params: GridParams) -> Self {
        let n = prims.len();
        let scene = (0..n as u32).fold(Aabb::EMPTY, |b, i| b.union(prims.bounds(i)));
        if n == 0 || scene.is_empty() {
            let root = Level {
                bounds: Aabb::EMPTY,
                res: UVec3::ONE,
                cell_size: Vec3::ONE,
                starts: vec![0, 0],
                items: Vec::new(),
                child: Vec::new(),
                children: Vec::new(),
            };
            return Grid { prims, root };
        }
        let (res, bounds) = grid_shape(scene, n, params.lambda);
        let ids: Vec<u32> = (0..n as u32).collect();
        let root = Level::build(prims.as_ref(), &ids, bounds, res, params, 0);
        Grid { prims, root }
    }

    /// Number of grids, the top one and every sub-grid.
    pub fn grid_count(&self) -> usize {
        fn count(l: &Level) -> usize {
            1 + l.children.iter().map(count).sum::<usize>()
        }
        count(&self.root)
    }
}

impl Level {
    /// Buckets primitives `ids` into a `res` grid over `bounds`, giving crowded cells
    /// sub-grids while `depth < params.max_depth`.
    fn build<P: PrimitiveSet>(
        prims: &P,
        ids: &[u32],
        bounds: Aabb,
        res: UVec3,
        params: GridParams,
        depth: u32,
    ) -> Level {
        let cell_size = bounds.extent() / res.as_vec3();
        let mut level = Level {
            bounds,
            res,
            cell_size,
            starts: Vec::new(),
            items: Vec::new(),
            child: Vec::new(),
            children: Vec::new(),
        };
        // Every (cell, primitive) pair that overlaps, found in parallel, then bucketed by cell.
        let pairs: Vec<(u32, u32)> = ids
            .par_iter()
            .flat_map_iter(|&i| {
                let b = prims.bounds(i);
                let (lo, hi) = (level.cell_of(b.min), level.cell_of(b.max));
                let mut out = Vec::new();
                for z in lo.z..=hi.z {
                    for y in lo.y..=hi.y {
                        for x in lo.x..=hi.x {
                            let cell = UVec3::new(x, y, z);
                            if prims.overlaps(i, &level.cell_bounds(cell)) {
                                out.push((level.index(cell), i));
                            }
                        }
                    }
                }
                out
            })
            .collect();
        let cells = (res.x * res.y * res.z) as usize;
        let mut counts = vec![0u32; cells];
        pairs.iter().for_each(|&(c, _)| counts[c as usize] += 1);
        let mut bucket: Vec<Vec<u32>> = vec![Vec::new(); cells];
        for &(c, i) in &pairs {
            bucket[c as usize].push(i);
        }
        // Crowded cells become sub-grids; the rest keep their primitives.
        let nest = depth < params.max_depth;
        if nest {
            level.child = vec![NO_CHILD; cells];
        }
        let mut starts = vec![0u32; cells + 1];
        let mut items = Vec::with_capacity(pairs.len());
        for (c, ids) in bucket.iter().enumerate() {
            if nest && ids.len() > params.max_items {
                let cell = UVec3::new(c as u32 % res.x, (c as u32 / res.x) % res.y, c as u32 / (res.x * res.y));
                let cb = level.cell_bounds(cell);
                let sub_res = grid_shape(cb, ids.len(), params.lambda).0;
                level.child[c] = level.children.len() as u32;
                level
                    .children
                    .push(Level::build(prims, ids, cb, sub_res, params, depth + 1));
            } else {
                items.extend_from_slice(ids);
            }
            starts[c + 1] = items.len() as u32;
        }
        level.starts = starts;
        level.items = items;
        level
    }

    fn cell_of(&self, p: Vec3) -> UVec3 {
        let rel = ((p - self.bounds.min) / self.cell_size).floor();
        rel.clamp(Vec3::ZERO, (self.res - UVec3::ONE).as_vec3()).as_uvec3()
    }

    fn cell_bounds(&self, c: UVec3) -> Aabb {
        let min = self.bounds.min + c.as_vec3() * self.cell_size;
        Aabb {
            min,
            max: min + self.cell_size,
        }
    }

    fn index(&self, c: UVec3) -> u32 {
        (c.z * self.res.y + c.y) * self.res.x + c.x
    }

    /// Walks the cells along `ray` in order, descending into sub-grids; returns whether the
    /// visitor ended the walk.
    fn walk<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>) -> bool {
        if self.starts.len() < 2 || self.bounds.is_empty() {
            return false;
        }
        let inv = ray.dir.recip();
        let Some(t_enter) = self.bounds.hit(ray, inv, t_max) else {
            return false;
        };
        let mut cell = self.cell_of(ray.at(t_enter));
        let step = ray.dir.signum().as_ivec3();
        // Distance to the next cell boundary along each axis, and between boundaries.
        let mut t_next = Vec3::ZERO;
        let mut t_delta = Vec3::ZERO;
        for a in 0..3 {
            if ray.dir[a] == 0.0 {
                t_next[a] = f32::INFINITY;
                t_delta[a] = f32::INFINITY;
            } else {
                let boundary = cell[a] + (ray.dir[a] > 0.0) as u32;
                let plane = self.bounds.min[a] + boundary as f32 * self.cell_size[a];
                t_next[a] = (plane - ray.origin[a]) * inv[a];
                t_delta[a] = self.cell_size[a] * inv[a].abs();
            }
        }
        loop {
            stats.node();
            let axis = t_next.min_position();
            let t_exit = t_next[axis];
            let c = self.index(cell) as usize;
            let sub = self.child.get(c).copied().unwrap_or(NO_CHILD);
            let stop = if sub == NO_CHILD {
                visit(
                    &self.items[self.starts[c] as usize..self.starts[c + 1] as usize],
                    t_exit,
                    stats,
                ) <= t_exit
            } else {
                self.children[sub as usize].walk(ray, t_max, stats, visit)
            };
            if stop || t_exit > t_max {
                return stop;
            }
            let next = cell[axis] as i32 + step[axis];
            if next < 0 || next >= self.res[axis] as i32 {
                return false;
            }
            cell[axis] = next as u32;
            t_next[axis] += t_delta[axis];
        }
    }

    fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + 4 * (self.starts.capacity() + self.items.capacity() + self.child.capacity())
            + self.children.iter().map(Level::memory_bytes).sum::<usize>()
    }
}

impl<P: PrimitiveSet> CellWalk for Grid<P> {
    type Prims = P;
    fn prims(&self) -> &P {
        &self.prims
    }
    fn walk<C: Counter>(&self, ray: &Ray, t_max: f32, stats: &mut C, visit: &mut CellVisitor<'_, C>) {
        self.root.walk(ray, t_max, stats, visit);
    }
    fn extent(&self) -> Aabb {
        self.root.bounds
    }
    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.root.memory_bytes()
    }
}
