//! A piecewise-constant density over the unit square from a `width` x `height` grid of
//! non-negative weights (row-major, row 0 at v = 0): an environment map's sampling
//! density. A point is drawn as pbrt-v4's "PiecewiseConstant2D" draws it (section A.5: a
//! row by the marginal over rows, a cell by the conditional within that row, the point
//! uniform within the cell), each discrete draw taken one of two ways ([`Draw`]):
//! - by inverting the CDFs (the row's and the cell's found by guide-table searches,
//!   [`Distribution1D`]): monotone in each number, so stratified and low-discrepancy
//!   numbers stay stratified over the map;
//! - by Walker's alias method ([`crate::alias`]): one table slot and one comparison, no
//!   search and no branch that waits on a random number, but the map is visited out of
//!   order, so it suits independent numbers only (with a Sobol sampler a glossy
//!   environment-lit scene's error grew by 70% at equal samples).
//!
//! Each cell carries its density and a payload `P` side by side (an environment map's
//! pixel radiance), so that a sample's answer is one read.

use crate::alias::{self, AliasEntry};
use crate::Distribution1D;

/// How a [`Distribution2D`] draws its rows and cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Draw {
    /// Inverting the CDFs: for stratified or low-discrepancy numbers.
    Inverted,
    /// Walker's alias method: faster, for independent numbers.
    Alias,
}

#[derive(Clone, Debug, PartialEq)]
enum Tables {
    Inverted {
        marginal: Distribution1D,
        /// Each row's conditional distribution; `None` for a row of zero weight.
        rows: Vec<Option<Distribution1D>>,
    },
    Alias {
        /// The rows' slots, by each row's total weight.
        rows: Vec<AliasEntry>,
        /// Each row's slots over its cells, row `y`'s at `y * width` (a row of zero
        /// weight, never drawn, holds empty slots).
        columns: Vec<AliasEntry>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D<P = ()> {
    tables: Tables,
    /// Each cell's density over the unit square (the probability the draw gives it,
    /// times the number of cells) and payload, row-major.
    cells: Vec<(f32, P)>,
    width: usize,
    height: usize,
}

impl Distribution2D {
    /// `None` when the weights are all zero, or one is negative or not finite.
    pub fn new(weights: &[f32], width: usize, height: usize, draw: Draw) -> Option<Self> {
        Distribution2D::with_items(weights, |_| (), width, height, draw)
    }
}

impl<P: Copy> Distribution2D<P> {
    /// The weights as for [`Distribution2D::new`], cell `i` (row-major) carrying
    /// `item(i)` beside its density.
    pub fn with_items(
        weights: &[f32],
        item: impl Fn(usize) -> P,
        width: usize,
        height: usize,
        draw: Draw,
    ) -> Option<Self> {
        if width == 0 || height == 0 || weights.len() != width * height {
            return None;
        }
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return None;
        }
        let count = (width * height) as f32;
        let (tables, densities): (Tables, Vec<f32>) = match draw {
            Draw::Inverted => {
                let rows: Vec<Option<Distribution1D>> = weights
                    .chunks(width)
                    .map(|row| Distribution1D::new(row.iter().copied()))
                    .collect();
                let marginal = Distribution1D::new(rows.iter().map(|r| r.as_ref().map_or(0.0, |d| d.total() as f32)))?;
                // The density the inversion gives: the product of the two tables' pmfs.
                let densities = (0..width * height)
                    .map(|i| {
                        let (x, y) = (i % width, i / width);
                        rows[y].as_ref().map_or(0.0, |row| marginal.pmf(y) * row.pmf(x) * count)
                    })
                    .collect();
                (Tables::Inverted { marginal, rows }, densities)
            }
            Draw::Alias => {
                let weights: Vec<f64> = weights.iter().map(|&w| w as f64).collect();
                let totals: Vec<f64> = weights.chunks(width).map(|row| row.iter().sum()).collect();
                let total: f64 = totals.iter().sum();
                let rows = alias::build(&totals)?;
                let mut columns = Vec::with_capacity(width * height);
                for row in weights.chunks(width) {
                    match alias::build(row) {
                        Some(slots) => columns.extend(slots),
                        None => columns.extend(std::iter::repeat_n(AliasEntry::default(), width)),
                    }
                }
                let densities = weights.iter().map(|&w| (w / total * count as f64) as f32).collect();
                (Tables::Alias { rows, columns }, densities)
            }
        };
        let cells = densities
            .into_iter()
            .enumerate()
            .map(|(i, density)| (density, item(i)))
            .collect();
        Some(Distribution2D {
            tables,
            cells,
            width,
            height,
        })
    }

    /// A point of the unit square and its density there.
    pub fn sample(&self, u: [f32; 2]) -> ([f32; 2], f32) {
        let (point, density, _) = self.sample_item(u);
        (point, density)
    }

    /// [`Distribution2D::sample`] with the payload of the cell the point lies in (one
    /// sample alone: the steps' prefetches serve only lanes that interleave them).
    pub fn sample_item(&self, u: [f32; 2]) -> ([f32; 2], f32, P) {
        self.sample_in_row(u[0], self.sample_row(u))
    }

    /// The first step of [`Distribution2D::sample_item`]: the row `u[1]` draws and `u[1]`
    /// rescaled within its share, having asked the caches for what
    /// [`Distribution2D::prefetch_in_row`] with `u[0]` reads in that row. Lanes that take
    /// every step for all lanes before the next wait on their memory together: a large
    /// map's tables are not in the caches, and each step's reads depend on the step before.
    #[inline]
    pub fn sample_row(&self, u: [f32; 2]) -> (usize, f32) {
        match &self.tables {
            Tables::Inverted { marginal, rows } => {
                let (y, _, rest) = marginal.sample(u[1]);
                if let Some(row) = &rows[y] {
                    row.prefetch_guide(u[0]);
                }
                (y, rest)
            }
            Tables::Alias { rows, columns } => {
                let (y, rest) = alias::sample(rows, u[1]);
                let row = self.row_slots(columns, y);
                crate::simd::prefetch(&row[alias::slot(row, u[0]).0]);
                (y, rest)
            }
        }
    }

    /// The second step of [`Distribution2D::sample_item`] taken in lanes (a sample alone
    /// skips it): asks the caches for what [`Distribution2D::sample_in_row`] with `u0`
    /// reads in row `y` (the ends of its guide bucket, or the drawn cell).
    #[inline]
    pub fn prefetch_in_row(&self, u0: f32, y: usize) {
        match &self.tables {
            Tables::Inverted { rows, .. } => {
                if let Some(row) = &rows[y] {
                    row.prefetch_sample(u0);
                }
            }
            Tables::Alias { columns, .. } => {
                let (x, _) = alias::sample(self.row_slots(columns, y), u0);
                crate::simd::prefetch(&self.cells[y * self.width + x]);
            }
        }
    }

    /// The last step of [`Distribution2D::sample_item`]: the point in the row `picked`
    /// ([`Distribution2D::sample_row`]'s answer) that `u0` draws, its density and payload.
    #[inline]
    pub fn sample_in_row(&self, u0: f32, picked: (usize, f32)) -> ([f32; 2], f32, P) {
        let (y, rest_y) = picked;
        let (x, rest_x) = match &self.tables {
            Tables::Inverted { rows, .. } => {
                let row = rows[y].as_ref().expect("rows of zero weight are never chosen");
                let (x, _, rest) = row.sample(u0);
                (x, rest)
            }
            Tables::Alias { columns, .. } => alias::sample(self.row_slots(columns, y), u0),
        };
        // Kept inside the chosen cell (x + rest can round up to the next one).
        let within =
            |i: usize, rest: f32, n: usize| ((i as f32 + rest) / n as f32).min(((i + 1) as f32 / n as f32).next_down());
        let point = [within(x, rest_x, self.width), within(y, rest_y, self.height)];
        let (density, item) = self.cells[y * self.width + x];
        (point, density, item)
    }

    /// Row `y`'s alias slots among `columns`.
    #[inline(always)]
    fn row_slots<'t>(&self, columns: &'t [AliasEntry], y: usize) -> &'t [AliasEntry] {
        &columns[y * self.width..(y + 1) * self.width]
    }

    /// The cell holding point `p` of the unit square, as its index.
    fn cell(&self, p: [f32; 2]) -> usize {
        let x = ((p[0] * self.width as f32) as usize).min(self.width - 1);
        let y = ((p[1] * self.height as f32) as usize).min(self.height - 1);
        y * self.width + x
    }

    /// The density at point `p` of the unit square.
    pub fn pdf(&self, p: [f32; 2]) -> f32 {
        self.cells[self.cell(p)].0
    }

    /// Asks the caches for the cell [`Distribution2D::item_at`] reads for `p`.
    #[inline]
    pub fn prefetch_at(&self, p: [f32; 2]) {
        crate::simd::prefetch(&self.cells[self.cell(p)]);
    }

    /// The density and payload of the cell holding point `p`.
    pub fn item_at(&self, p: [f32; 2]) -> (f32, P) {
        self.cells[self.cell(p)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_dimensional_density_matches_its_weights() {
        // 3 x 2 weights; the density of each cell is weight / mean weight.
        let w = [1.0, 0.0, 2.0, 3.0, 0.0, 0.0];
        for draw in [Draw::Inverted, Draw::Alias] {
            drawn_in_proportion(&w, Distribution2D::new(&w, 3, 2, draw).unwrap());
            assert!(Distribution2D::new(&[0.0; 4], 2, 2, draw).is_none());
        }
    }

    #[test]
    fn the_inverted_draw_keeps_the_numbers_in_order() {
        // Monotone in each number (what keeps stratified samples stratified over the map):
        // increasing u[1] never goes back a row, increasing u[0] never back a column.
        let w: Vec<f32> = (0..64).map(|i| ((i * 37) % 11) as f32).collect();
        let d = Distribution2D::new(&w, 8, 8, Draw::Inverted).unwrap();
        let mut last = [0.0f32; 2];
        for k in 0..4_000 {
            let u = (k as f32 + 0.5) / 4_000.0;
            let (by_row, _) = d.sample([0.3, u]);
            let (by_column, _) = d.sample([u, 0.6]);
            assert!(
                by_row[1] >= last[1] && by_column[0] >= last[0],
                "u {u}: {by_row:?} {by_column:?}"
            );
            last = [by_column[0], by_row[1]];
        }
    }

    fn drawn_in_proportion(w: &[f32; 6], d: Distribution2D) {
        let mean = 1.0;
        for (i, &wi) in w.iter().enumerate() {
            let p = [((i % 3) as f32 + 0.5) / 3.0, ((i / 3) as f32 + 0.5) / 2.0];
            assert!((d.pdf(p) - wi / mean).abs() < 1e-5, "cell {i}: {}", d.pdf(p));
        }
        // Samples land in cells in proportion to the weights, with the density of their
        // cell, uniformly within it (each cell's quarters get a quarter of its samples, to
        // 1%: the numbers are a stratified sweep, not random).
        let n = 60_000;
        let mut counts = [[0usize; 4]; 6];
        for k in 0..n {
            let u = [((k * 7919) % n) as f32 / n as f32, (k as f32 + 0.5) / n as f32];
            let (p, pdf) = d.sample(u);
            let (cx, cy) = (p[0] * 3.0, p[1] * 2.0);
            let cell = (cx as usize).min(2) + 3 * (cy as usize).min(1);
            assert_eq!(pdf, d.pdf(p), "{p:?}");
            let quarter = (cx.fract() * 2.0) as usize + 2 * (cy.fract() * 2.0) as usize;
            counts[cell][quarter] += 1;
        }
        for (i, c) in counts.iter().enumerate() {
            let want = w[i] / 6.0;
            let got: usize = c.iter().sum();
            assert!((got as f32 / n as f32 - want).abs() < 0.01, "cell {i}: {c:?}");
            for &q in c {
                assert!(
                    (q as f32 - got as f32 / 4.0).abs() <= 0.01 * got as f32,
                    "cell {i}: {c:?}"
                );
            }
        }
    }
}
