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
use crate::lanes::Real;
use crate::Distribution1D;

/// Where [`Distribution2D::sample_lanes`] lands in each lane: the cell's column and row
/// (as floats, exact below 2^24) and the point of the unit square within the cell.
#[derive(Clone, Copy, Debug)]
pub struct CellLanes<R> {
    pub x: R,
    pub y: R,
    pub point: [R; 2],
}

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

    /// [`Distribution2D::sample`] with the payload of the cell the point lies in: the
    /// one-lane instance of [`Distribution2D::sample_lanes`] and [`Distribution2D::cell`].
    pub fn sample_item(&self, u: [f32; 2]) -> ([f32; 2], f32, P) {
        let c = self.sample_lanes((u[0], u[1]));
        let (density, item) = self.cell(c.x as usize, c.y as usize);
        (c.point, density, item)
    }

    /// The cells `u` draws in the lanes of `R` (`u.1` the row, `u.0` the cell within it)
    /// and the points within them: the same floats in every lane as in one. Each step's
    /// reads are made for every lane after all of its lanes' reads were asked of the
    /// caches (a large map's tables are not in them, and each step's reads depend on the
    /// step before): the alias draw's arithmetic in SIMD, its slots read lane by lane; the
    /// inverted draw's searches lane by lane. The caller reads the cells' densities and
    /// payloads the same way ([`Distribution2D::prefetch_cell`], [`Distribution2D::cell`]).
    #[inline(always)]
    pub fn sample_lanes<R: Real>(&self, u: (R, R)) -> CellLanes<R> {
        let (x, rest_x, y, rest_y) = match &self.tables {
            Tables::Inverted { marginal, rows } => {
                let [y, rest_y] = R::map_lanes([u.0, u.1], |_, [u0, u1]| {
                    let (y, _, rest) = marginal.sample(u1);
                    if let Some(row) = &rows[y] {
                        row.prefetch_guide(u0);
                    }
                    [y as f32, rest]
                });
                let [] = R::map_lanes([u.0, y], |_, [u0, y]| {
                    if let Some(row) = &rows[y as usize] {
                        row.prefetch_sample(u0);
                    }
                    []
                });
                let [x, rest_x] = R::map_lanes([u.0, y], |_, [u0, y]| {
                    let row = rows[y as usize].as_ref().expect("rows of zero weight are never chosen");
                    let (x, _, rest) = row.sample(u0);
                    [x as f32, rest]
                });
                (x, rest_x, y, rest_y)
            }
            Tables::Alias { rows, columns } => {
                // The rows' table is small (one slot per row): no prefetch.
                let (y, rest_y) = alias::sample_lanes(self.height, u.1, R::splat(0.0), |_, _| {}, |_, i| rows[i]);
                let w = self.width;
                let (x, rest_x) = alias::sample_lanes(
                    w,
                    u.0,
                    y,
                    |y, i| crate::simd::prefetch(&columns[y as usize * w + i]),
                    |y, i| columns[y as usize * w + i],
                );
                (x, rest_x, y, rest_y)
            }
        };
        // Kept inside the chosen cell (i + rest can round up to the next one).
        let (nx, ny) = (R::splat(self.width as f32), R::splat(self.height as f32));
        let one = R::splat(1.0);
        let [last_x, last_y] = R::map_lanes([(x + one) / nx, (y + one) / ny], |_, [a, b]| {
            [a.next_down(), b.next_down()]
        });
        // A function, not a closure: a closure making lane values may be compiled apart
        // from its caller's SIMD level.
        #[inline(always)]
        fn within<R: Real>(i: R, rest: R, n: R, last: R) -> R {
            let p = (i + rest) / n;
            R::select(p.cmp_lt(last), p, last)
        }
        CellLanes {
            x,
            y,
            point: [within(x, rest_x, nx, last_x), within(y, rest_y, ny, last_y)],
        }
    }

    /// Asks the caches for cell (`x`, `y`), which [`Distribution2D::cell`] reads.
    #[inline(always)]
    pub fn prefetch_cell(&self, x: usize, y: usize) {
        crate::simd::prefetch(&self.cells[y * self.width + x]);
    }

    /// The density and payload of cell (`x`, `y`).
    #[inline(always)]
    pub fn cell(&self, x: usize, y: usize) -> (f32, P) {
        self.cells[y * self.width + x]
    }

    /// The cell holding point `p` of the unit square, as its index.
    fn cell_index(&self, p: [f32; 2]) -> usize {
        let x = ((p[0] * self.width as f32) as usize).min(self.width - 1);
        let y = ((p[1] * self.height as f32) as usize).min(self.height - 1);
        y * self.width + x
    }

    /// The density at point `p` of the unit square.
    pub fn pdf(&self, p: [f32; 2]) -> f32 {
        self.cells[self.cell_index(p)].0
    }

    /// Asks the caches for the cell [`Distribution2D::item_at`] reads for `p`.
    #[inline]
    pub fn prefetch_at(&self, p: [f32; 2]) {
        crate::simd::prefetch(&self.cells[self.cell_index(p)]);
    }

    /// The density and payload of the cell holding point `p`.
    pub fn item_at(&self, p: [f32; 2]) -> (f32, P) {
        self.cells[self.cell_index(p)]
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

    /// Eight lanes draw the cells and points that one lane draws, bit for bit, by either
    /// draw (numbers at the ends of [0, 1) included; `F8Avx` gives `F8`'s bits, its own
    /// test).
    #[test]
    fn lanes_draw_what_one_lane_draws() {
        use crate::lanes::{Lane8, F8};
        let (w, h) = (37, 11);
        let weights: Vec<f32> = (0..w * h).map(|i| ((i * 7919) % 13) as f32 * (i % 5) as f32).collect();
        let mut rng = crate::Pcg32::new(3, 7);
        let ends = [0.0, crate::samplers::ONE_MINUS_EPSILON, 0.5];
        for draw in [Draw::Inverted, Draw::Alias] {
            let d = Distribution2D::with_items(&weights, |i| i as u32, w, h, draw).unwrap();
            for round in 0..2_000 {
                let u: [[f32; 2]; 8] = std::array::from_fn(|k| match (round * 8 + k) % 11 {
                    0 => [ends[k % 3], rng.next_f32()],
                    1 => [rng.next_f32(), ends[k % 3]],
                    _ => [rng.next_f32(), rng.next_f32()],
                });
                let c = d.sample_lanes((F8::from_array(u.map(|u| u[0])), F8::from_array(u.map(|u| u[1]))));
                let (x, y) = (c.x.to_array(), c.y.to_array());
                let point = c.point.map(F8::to_array);
                for k in 0..8 {
                    let (p, density, item) = d.sample_item(u[k]);
                    let lane = [point[0][k], point[1][k]];
                    assert_eq!(lane.map(f32::to_bits), p.map(f32::to_bits), "{draw:?} u {:?}", u[k]);
                    assert_eq!(
                        d.cell(x[k] as usize, y[k] as usize),
                        (density, item),
                        "{draw:?} u {:?}",
                        u[k]
                    );
                    assert!(density > 0.0, "{draw:?}: a cell of zero weight drawn");
                }
            }
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
