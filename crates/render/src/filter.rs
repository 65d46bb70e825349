//! Pixel reconstruction filters. Filters wider than a pixel are splatted by the driver (see
//! [`crate::driver`]); narrower ones are applied by filter importance sampling (Ernst et
//! al., "Filter Importance Sampling", 2006; as in pbrt-v4) with [`FilterSampler`]: each
//! sample's position is drawn from the filter around the pixel centre, and the pixel is the
//! weighted mean of its own samples.
//!
//! Native format (`[render] filter = { type = "gaussian", radius = 1.5, sigma = 0.5 }`):
//! `box` (radius 0.5), `tent` (radius 1), `gaussian` (radius 1.5, sigma 0.5; the
//! Gaussian minus its value at the radius, as in pbrt).

use glam::Vec2;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    Box { radius: f32 },
    Tent { radius: f32 },
    Gaussian { radius: f32, sigma: f32 },
}

impl Default for Filter {
    fn default() -> Self {
        Filter::Gaussian {
            radius: 1.5,
            sigma: 0.5,
        }
    }
}

impl Filter {
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box { radius } | Filter::Tent { radius } | Filter::Gaussian { radius, .. } => radius,
        }
    }

    /// The separable filter's value along one axis at offset `x`.
    pub fn eval_1d(&self, x: f32) -> f32 {
        let r = self.radius();
        if x.abs() > r {
            return 0.0;
        }
        match *self {
            Filter::Box { .. } => 1.0,
            Filter::Tent { .. } => r - x.abs(),
            Filter::Gaussian { sigma, .. } => {
                let g = |x: f32| (-x * x / (2.0 * sigma * sigma)).exp();
                (g(x) - g(r)).max(0.0)
            }
        }
    }
}

/// A filter's 1D profile tabulated on [0, radius] and interpolated linearly, for splatting
/// (each sample reaches (2 radius)^2 pixels; Mitsuba 3 likewise splats from a discretized
/// filter). With [`SPLAT_TABLE`] entries the Gaussian is matched to within 1e-5.
#[derive(Clone, Debug)]
pub struct FilterTable {
    values: Box<[f32; SPLAT_TABLE + 1]>,
    /// Table entries per unit of distance.
    scale: f32,
    radius: f32,
}

/// Entries of a [`FilterTable`].
pub const SPLAT_TABLE: usize = 1025;

impl FilterTable {
    pub fn new(filter: &Filter) -> Self {
        let r = filter.radius();
        let step = r / (SPLAT_TABLE - 1) as f32;
        // One zero past the end, so that interpolation needs no bounds check below the radius.
        let mut values = Box::new([0.0; SPLAT_TABLE + 1]);
        for (i, v) in values[..SPLAT_TABLE].iter_mut().enumerate() {
            *v = filter.eval_1d(i as f32 * step);
        }
        FilterTable {
            values,
            scale: if r > 0.0 { 1.0 / step } else { 0.0 },
            radius: r,
        }
    }

    /// The filter's radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// The filter's value at offset `x` (zero beyond the radius).
    #[inline]
    pub fn eval(&self, x: f32) -> f32 {
        let t = x.abs() * self.scale;
        let last = (SPLAT_TABLE - 1) as f32;
        if t >= last || t.is_nan() {
            return if t == last { self.values[SPLAT_TABLE - 1] } else { 0.0 };
        }
        // SAFETY: `t` is finite and in `[0, SPLAT_TABLE - 1)` here, so the conversion is
        // exact truncation (a checked `as` costs a dozen instructions on every splat).
        let i = unsafe { t.to_int_unchecked::<u32>() } as usize;
        let f = t - i as f32;
        // `min` (never taken) proves both reads in bounds of the fixed-size table.
        let i = i.min(SPLAT_TABLE - 2);
        self.values[i] * (1.0 - f) + self.values[i + 1] * f
    }
}

/// Draws offsets from a filter: a tabulated piecewise-constant density per axis, with the
/// weight `f / pdf` that makes the estimate exact in expectation.
#[derive(Clone, Debug)]
pub struct FilterSampler {
    filter: Filter,
    cdf: Vec<f32>,
    integral: f32,
}

const TABLE_SIZE: usize = 64;

impl FilterSampler {
    pub fn new(filter: Filter) -> Self {
        let r = filter.radius();
        let dx = 2.0 * r / TABLE_SIZE as f32;
        let mut cdf = vec![0.0; TABLE_SIZE + 1];
        for i in 0..TABLE_SIZE {
            let x = -r + (i as f32 + 0.5) * dx;
            cdf[i + 1] = cdf[i] + filter.eval_1d(x).abs() * dx;
        }
        let integral = cdf[TABLE_SIZE];
        if integral > 0.0 {
            cdf.iter_mut().for_each(|c| *c /= integral);
        }
        FilterSampler { filter, cdf, integral }
    }

    fn sample_1d(&self, u: f32) -> (f32, f32) {
        let r = self.filter.radius();
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, TABLE_SIZE) - 1;
        let width = self.cdf[i + 1] - self.cdf[i];
        let frac = if width > 0.0 { (u - self.cdf[i]) / width } else { 0.5 };
        let dx = 2.0 * r / TABLE_SIZE as f32;
        let x = -r + (i as f32 + frac) * dx;
        let pdf = width / dx;
        (x, pdf)
    }

    /// An offset from the pixel centre and its weight f(x, y) / pdf(x, y), normalised so
    /// that its expectation is 1.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (x, px) = self.sample_1d(u.x);
        let (y, py) = self.sample_1d(u.y);
        if self.integral.is_nan() || self.integral <= 0.0 {
            // A filter narrower than the table's cells: the limit is a delta at the centre.
            return (Vec2::ZERO, 1.0);
        }
        let f = self.filter.eval_1d(x) * self.filter.eval_1d(y) / (self.integral * self.integral);
        (Vec2::new(x, y), if px * py > 0.0 { f / (px * py) } else { 0.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_splat_table_matches_the_filter() {
        for filter in [
            Filter::default(),
            Filter::Gaussian {
                radius: 2.0,
                sigma: 0.5,
            },
            Filter::Tent { radius: 1.0 },
            Filter::Box { radius: 1.5 },
        ] {
            let table = FilterTable::new(&filter);
            let r = filter.radius();
            for i in -400..=400 {
                let x = i as f32 * r / 333.0;
                let (want, got) = (filter.eval_1d(x), table.eval(x));
                assert!((want - got).abs() < 2e-5, "{filter:?} at {x}: {want} vs {got}");
            }
        }
    }
    use penumbra_core::Pcg32;

    #[test]
    fn a_filter_narrower_than_the_table_is_a_delta() {
        let s = FilterSampler::new(Filter::Gaussian {
            radius: 1.5,
            sigma: 1e-4,
        });
        assert_eq!(s.sample(Vec2::new(0.3, 0.9)), (Vec2::ZERO, 1.0));
    }

    #[test]
    fn offsets_follow_the_filter_and_weights_average_one() {
        for filter in [
            Filter::Box { radius: 0.5 },
            Filter::Tent { radius: 1.0 },
            Filter::default(),
        ] {
            let s = FilterSampler::new(filter);
            let mut rng = Pcg32::new(3, 0);
            let n = 100_000;
            let (mut sum_w, mut sum_x2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let (o, w) = s.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
                assert!(o.x.abs() <= filter.radius() && o.y.abs() <= filter.radius());
                sum_w += w as f64;
                sum_x2 += (o.x * o.x) as f64 * w as f64;
            }
            // Weights are f/pdf for a piecewise-constant pdf close to f: mean 1, tiny spread.
            assert!(
                (sum_w / n as f64 - 1.0).abs() < 0.01,
                "{filter:?}: {}",
                sum_w / n as f64
            );
            // Variance of the box filter of radius 0.5 is 1/12, of the tent of radius 1 is 1/6.
            let var = sum_x2 / n as f64;
            match filter {
                Filter::Box { .. } => assert!((var - 1.0 / 12.0).abs() < 0.003, "{var}"),
                Filter::Tent { .. } => assert!((var - 1.0 / 6.0).abs() < 0.005, "{var}"),
                _ => assert!(var > 0.1 && var < 0.3),
            }
        }
    }
}
