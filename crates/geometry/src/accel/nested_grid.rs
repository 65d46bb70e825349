//! The nested (adaptive) grid, after Jevans and Wyvill, "Adaptive Voxel Subdivision for Ray
//! Tracing" (1989): a coarse regular grid whose crowded cells hold grids of their own, so
//! that a small dense object inside a large sparse scene (the "teapot in a stadium") gets
//! fine cells without the whole scene paying for them. The traversal is the regular grid's
//! 3D-DDA, descending into a cell's sub-grid over the part of the ray inside the cell.
//!
//! Parameters: top-level `lambda` 1 cell per primitive; a cell with more than 8 primitives
//! is subdivided (again with about `lambda` cells per primitive it holds), at most 2 levels
//! below the top.

use super::grid::{Grid, GridParams};
use super::PrimitiveSet;
use std::sync::Arc;

pub const PARAMS: GridParams = GridParams {
    lambda: 1.0,
    max_items: 8,
    max_depth: 2,
};

pub fn build<P: PrimitiveSet>(prims: Arc<P>) -> Grid<P> {
    Grid::with_params(prims, PARAMS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{Accel, TraversalStats};
    use crate::instance::MeshTriangles;
    use crate::TriangleMesh;
    use glam::Vec3;
    use penumbra_core::{Pcg32, Ray};

    /// A dense cluster of 4,000 tiny triangles near the centre of a sparse ring of 40 large
    /// ones: the teapot in a stadium.
    fn teapot_in_a_stadium() -> Arc<MeshTriangles> {
        let mut rng = Pcg32::new(4, 0);
        let mut m = TriangleMesh::default();
        let mut add = |c: Vec3, size: f32, rng: &mut Pcg32| {
            let mut p = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - Vec3::splat(0.5);
            let base = m.positions.len() as u32;
            m.positions.extend([c, c + p() * size, c + p() * size]);
            m.indices.push([base, base + 1, base + 2]);
        };
        for i in 0..40 {
            let a = i as f32 / 40.0 * std::f32::consts::TAU;
            add(Vec3::new(a.cos(), 0.0, a.sin()) * 100.0, 10.0, &mut rng);
        }
        for _ in 0..4000 {
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - Vec3::splat(0.5);
            add(c, 0.05, &mut rng);
        }
        Arc::new(MeshTriangles::new(Arc::new(m)))
    }

    #[test]
    fn crowded_cells_are_subdivided_and_cheaper_to_traverse() {
        let prims = teapot_in_a_stadium();
        let nested = build(prims.clone());
        let flat = Grid::new(prims, 1.0);
        assert!(nested.grid_count() > 1, "the dense cluster gets sub-grids");
        assert_eq!(flat.grid_count(), 1);
        // Rays into the cluster: the same hits, with far fewer primitive tests when nested.
        let (mut a, mut b) = (TraversalStats::default(), TraversalStats::default());
        for i in 0..200 {
            let y = (i as f32 / 200.0 - 0.5) * 0.8;
            let ray = Ray::new(Vec3::new(-50.0, y, 0.01 * i as f32 - 1.0), Vec3::X);
            let (h1, h2) = (
                nested.intersect_counted(&ray, f32::INFINITY, &mut a),
                flat.intersect_counted(&ray, f32::INFINITY, &mut b),
            );
            assert_eq!(h1.map(|h| h.t), h2.map(|h| h.t));
        }
        assert!(a.prims * 4 < b.prims, "nested {} vs flat {} tests", a.prims, b.prims);
    }
}
