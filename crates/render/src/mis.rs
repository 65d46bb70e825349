//! Multiple importance sampling's weights (Veach and Guibas, "Optimally Combining
//! Sampling Techniques for Monte Carlo Rendering", SIGGRAPH 1995), for every integrator and
//! for the layered BSDF's walks, in one lane or many.

use penumbra_core::lanes::Real;

/// The weighting of multiple importance sampling.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MisHeuristic {
    Balance,
    #[default]
    Power,
}

impl MisHeuristic {
    pub const NAMES: [&'static str; 2] = ["power", "balance"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "balance" => Some(MisHeuristic::Balance),
            "power" => Some(MisHeuristic::Power),
            _ => None,
        }
    }

    /// Weight of a sample of strategy f, given `f` = n_f p_f and `g` = n_g p_g for the
    /// other strategy (Veach and Guibas 1995: balance f/(f+g), power f²/(f²+g²)).
    pub fn weight(self, f: f32, g: f32) -> f32 {
        self.weight_lanes(f, g)
    }

    /// [`MisHeuristic::weight`] for lanes of any [`Real`] type.
    #[inline(always)]
    pub fn weight_lanes<R: Real>(self, f: R, g: R) -> R {
        let (f, g) = match self {
            MisHeuristic::Balance => (f, g),
            MisHeuristic::Power => (f * f, g * g),
        };
        let (zero, one) = (R::splat(0.0), R::splat(1.0));
        let sum = f + g;
        let finite = R::select(sum.cmp_gt(zero), f / sum, zero);
        R::select(f.abs().cmp_eq(R::splat(f32::INFINITY)), one, finite)
    }
}

#[cfg(test)]
mod tests {
    use super::MisHeuristic;
    use penumbra_core::lanes::F8;

    /// Veach and Guibas's weights as first written: infinite densities win, a zero pair
    /// weighs nothing.
    fn by_definition(h: MisHeuristic, f: f32, g: f32) -> f32 {
        let (f, g) = match h {
            MisHeuristic::Balance => (f, g),
            MisHeuristic::Power => (f * f, g * g),
        };
        if f.is_infinite() {
            1.0
        } else if f + g > 0.0 {
            f / (f + g)
        } else {
            0.0
        }
    }

    #[test]
    fn weights_equal_the_definition_in_one_lane_and_in_eight() {
        let values = [0.0, 1e-30, 0.3, 1.0, 7.5, 1e30, f32::MAX, f32::INFINITY, f32::NAN];
        // Every pair of values, eight pairs to a lane group.
        let pairs: Vec<(f32, f32)> = values
            .iter()
            .flat_map(|&f| values.iter().map(move |&g| (f, g)))
            .collect();
        for h in [MisHeuristic::Balance, MisHeuristic::Power] {
            for group in pairs.chunks(8) {
                let lane = |k: usize| group[k.min(group.len() - 1)];
                let (f, g): ([f32; 8], [f32; 8]) =
                    (std::array::from_fn(|k| lane(k).0), std::array::from_fn(|k| lane(k).1));
                let lanes = h.weight_lanes(F8::from(f), F8::from(g)).to_array();
                for k in 0..8 {
                    let expected = by_definition(h, f[k], g[k]);
                    assert_eq!(
                        h.weight(f[k], g[k]).to_bits(),
                        expected.to_bits(),
                        "{h:?} {} {}",
                        f[k],
                        g[k]
                    );
                    assert_eq!(lanes[k].to_bits(), expected.to_bits(), "{h:?} lanes {} {}", f[k], g[k]);
                }
            }
        }
    }
}
