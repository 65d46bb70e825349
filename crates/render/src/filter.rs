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

/// The pixel filter, tabulated once per render: sampled (narrow filters) or splatted.
pub struct Filters {
    pub(crate) sampler: FilterSampler,
    /// For filters wider than a pixel.
    pub(crate) splat: Option<FilterTable>,
    /// Pixels a splat reaches beyond a tile's edge (0 without splatting).
    pub(crate) margin: u32,
    /// The filter for the film's splat layer, whatever its width, and for each column and
    /// row of pixels the factor that makes it integrate to one over the image: a pixel's
    /// value is ∫ f(x - c) L(x) dx / ∫ f(x - c) dx over the image (what the weighted mean
    /// of its samples estimates, or filter importance sampling), so near the borders the
    /// factor is larger, and splats lose no light off the image's edge.
    pub(crate) layer: FilterTable,
    pub(crate) columns: Vec<f32>,
    pub(crate) rows: Vec<f32>,
}

impl Filters {
    pub(crate) fn new(scene: &crate::Scene) -> Self {
        let radius = scene.filter.radius();
        let splat = radius > 0.5;
        let table = FilterTable::new(&scene.filter);
        // ∫ f over [lo, hi] ∩ [-r, r], by the trapezoid rule on 1024 intervals.
        let integral = |lo: f64, hi: f64| -> f64 {
            let (lo, hi) = (lo.max(-radius as f64), hi.min(radius as f64));
            if hi <= lo {
                return 0.0;
            }
            let n = 1024;
            let step = (hi - lo) / n as f64;
            (0..=n)
                .map(|i| {
                    let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                    w * scene.filter.eval_1d((lo + i as f64 * step) as f32) as f64
                })
                .sum::<f64>()
                * step
        };
        // Pixel centre c = k + 1/2 of a side of n pixels: ∫ f(x - c) over x in [0, n]; the
        // whole filter's integral (the same sum) where the filter lies inside the image.
        let whole = integral(f64::NEG_INFINITY, f64::INFINITY);
        let r = radius as f64;
        let factors = |n: u32| -> Vec<f32> {
            (0..n)
                .map(|k| {
                    let c = k as f64 + 0.5;
                    let (lo, hi) = (-c, n as f64 - c);
                    let mass = if lo <= -r && hi >= r { whole } else { integral(lo, hi) };
                    if mass > 0.0 {
                        (1.0 / mass) as f32
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        Filters {
            sampler: FilterSampler::new(scene.filter),
            splat: splat.then(|| table.clone()),
            margin: if splat { (radius - 0.5).ceil() as u32 } else { 0 },
            layer: table,
            columns: factors(scene.width),
            rows: factors(scene.height),
        }
    }

    /// An offset from a pixel's centre drawn from the pixel filter, and its weight
    /// f / pdf (about 1): filter importance sampling (Ernst et al. 2006), for integrators
    /// that estimate each pixel by one point per pass.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        self.sampler.sample(u)
    }

    /// Adds `value`, landing at film position `film`, to every pixel of a `width` x
    /// `height` film within the filter's radius, with the normalised filter's weight.
    pub fn splat(
        &self,
        s: &crate::film::Splat,
        (width, height): (u32, u32),
        out: &mut Vec<(u32, u32, penumbra_core::Rgb)>,
    ) {
        let (film, value) = (s.film, s.value);
        let table = &self.layer;
        let r = table.radius();
        let lo = (film - Vec2::splat(r + 0.5)).ceil().max(Vec2::ZERO);
        let hi = (film + Vec2::splat(r - 0.5)).floor();
        if hi.x < 0.0 || hi.y < 0.0 {
            return;
        }
        let x1 = (hi.x as u32).min(width - 1);
        let y1 = (hi.y as u32).min(height - 1);
        for py in lo.y as u32..=y1 {
            let wy = table.eval(py as f32 + 0.5 - film.y) * self.rows[py as usize];
            for px in lo.x as u32..=x1 {
                let w = wy * table.eval(px as f32 + 0.5 - film.x) * self.columns[px as usize];
                if w != 0.0 {
                    out.push((s.layer, py * width + px, value * w));
                }
            }
        }
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
