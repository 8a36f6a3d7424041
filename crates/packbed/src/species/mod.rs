//! Particle species: shape, size distribution and number ratio.

use crate::math::{display_length as length, normal, Real};
use rand::RngExt;

mod passing;
mod table;

pub use passing::passing_quantile;
pub use table::{SizeTable, TableOptions, Within};

/// Unbounded size distributions are truncated to their central part unless the
/// config bounds them, so that every species has a finite largest radius (the
/// neighbour grid is sized by it). The window is this many standard deviations
/// either side (of the radius, or of its logarithm for lognormal): ±3 sd holds
/// 99.73 % of the distribution, and the largest radius, which sets the grid and
/// the thesis box, stays near the sizes actually drawn.
pub const TRUNCATION_SIGMAS: Real = 3.0;

/// A bounded window must hold at least this fraction of its distribution: one
/// that holds less is far in a tail, which is a mistake far more often than a
/// wish (the radii would all sit at its near end).
pub const MIN_WINDOW_MASS: Real = 1e-6;

/// How the radius of a new particle is chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum SizeDist {
    /// Every particle has this radius.
    Fixed(Real),
    /// Normal distribution truncated to `[lo, hi]`: the config's `min`/`max`, or
    /// by default `mean ± 3 sd` (`SizeDist::normal_window`).
    Normal {
        /// Mean radius (of the distribution before truncation).
        mean: Real,
        /// Standard deviation (before truncation).
        sd: Real,
        /// Smallest radius drawn (> 0).
        lo: Real,
        /// Largest radius drawn.
        hi: Real,
    },
    /// Lognormal distribution by median and geometric standard deviation,
    /// truncated to `[lo, hi]`: the config's `min`/`max`, or by default
    /// `median · gsd^±3` (`SizeDist::lognormal_window`).
    Lognormal {
        /// Median radius (of the distribution before truncation).
        median: Real,
        /// Geometric standard deviation (> 1; 1 means a fixed size).
        gsd: Real,
        /// Smallest radius drawn.
        lo: Real,
        /// Largest radius drawn.
        hi: Real,
    },
    /// Uniform on `[min, max]`.
    Uniform {
        /// Smallest radius.
        min: Real,
        /// Largest radius.
        max: Real,
    },
    /// A measured particle size distribution ([`SizeTable`]).
    Table(SizeTable),
}

impl SizeDist {
    /// The default window of a normal distribution: `mean ± 3 sd`, with a lower
    /// end at or below 0 replaced by `mean / 1000` (radii must be positive).
    pub(crate) fn normal_window(mean: Real, sd: Real) -> (Real, Real) {
        let lo = mean - TRUNCATION_SIGMAS * sd;
        (
            if lo > 0.0 { lo } else { mean * 1e-3 },
            mean + TRUNCATION_SIGMAS * sd,
        )
    }

    /// The default window of a lognormal distribution: `median · gsd^±3`.
    pub(crate) fn lognormal_window(median: Real, gsd: Real) -> (Real, Real) {
        let f = gsd.powf(TRUNCATION_SIGMAS);
        (median / f, median * f)
    }

    /// The window of a normal or lognormal distribution in standard deviations
    /// from its centre (of `ln r` for lognormal); `None` for the other kinds
    /// and for a spread of 0.
    fn standard_window(&self) -> Option<(Real, Real)> {
        match *self {
            SizeDist::Normal { mean, sd, lo, hi } if sd > 0.0 => {
                Some(((lo - mean) / sd, (hi - mean) / sd))
            }
            SizeDist::Lognormal {
                median,
                gsd,
                lo,
                hi,
            } if gsd > 1.0 => {
                let s = gsd.ln();
                Some(((lo / median).ln() / s, (hi / median).ln() / s))
            }
            _ => None,
        }
    }

    /// The probability the untruncated distribution gives to the radii this one
    /// draws: 1 without truncation, 0 for a window of one radius under a
    /// continuous distribution, or one that misses a spread of 0.
    pub fn window_mass(&self) -> Real {
        if let Some((a, b)) = self.standard_window() {
            return normal::mass(a, b);
        }
        match *self {
            SizeDist::Normal { mean, lo, hi, .. } => Real::from(u8::from(lo <= mean && mean <= hi)),
            SizeDist::Lognormal { median, lo, hi, .. } => {
                Real::from(u8::from(lo <= median && median <= hi))
            }
            _ => 1.0,
        }
    }

    /// The `u`-quantile (`u` in `[0, 1]`) of a truncated normal or lognormal,
    /// within its window; inversion, so that a draw costs one uniform number
    /// however little of the distribution the window holds.
    fn truncated_quantile(&self, u: Real) -> Real {
        let (lo, hi) = self.bounds();
        if lo == hi {
            return lo;
        }
        let r = match (self, self.standard_window()) {
            (&SizeDist::Normal { mean, sd, .. }, Some((a, b))) => {
                mean + sd * normal::truncated_quantile(a, b, u)
            }
            (&SizeDist::Lognormal { median, gsd, .. }, Some((a, b))) => {
                median * (gsd.ln() * normal::truncated_quantile(a, b, u)).exp()
            }
            (&SizeDist::Normal { mean, .. }, None) => mean,
            (&SizeDist::Lognormal { median, .. }, None) => median,
            _ => lo,
        };
        // The way back from standard units may round a last bit past an end.
        r.clamp(lo, hi)
    }

    /// The smallest and largest radius this distribution can produce.
    pub fn bounds(&self) -> (Real, Real) {
        match self {
            SizeDist::Fixed(r) => (*r, *r),
            SizeDist::Normal { lo, hi, .. } | SizeDist::Lognormal { lo, hi, .. } => (*lo, *hi),
            SizeDist::Uniform { min, max } => (*min, *max),
            SizeDist::Table(t) => t.bounds(),
        }
    }

    /// The median radius: the typical size of the species, used to name species
    /// "large" and "small" (the truncation bounds of a tail say little of it).
    pub fn median(&self) -> Real {
        match self {
            SizeDist::Fixed(r) => *r,
            // The median of the truncated distribution, which is the centre for
            // the default symmetric window and moves with one-sided bounds.
            SizeDist::Normal { .. } | SizeDist::Lognormal { .. } => self.truncated_quantile(0.5),
            SizeDist::Uniform { min, max } => 0.5 * (min + max),
            SizeDist::Table(t) => t.median(),
        }
    }

    /// Draws one radius.
    pub fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> Real {
        match self {
            SizeDist::Fixed(r) => *r,
            SizeDist::Normal { .. } | SizeDist::Lognormal { .. } => {
                self.truncated_quantile(rng.random())
            }
            SizeDist::Uniform { min, max } => {
                if min == max {
                    *min
                } else {
                    rng.random_range(*min..=*max)
                }
            }
            SizeDist::Table(t) => t.sample(rng),
        }
    }

    /// The distribution for a person, with the window it is truncated to:
    /// `r ~ lognormal(median 10, gsd 2) in [1.25, 80] (±3 sd)`, or
    /// `... in [2, 100]` for bounds from the config (a default end is named).
    pub fn describe(&self) -> String {
        let window = |lo: Real, hi: Real, default: (Real, Real), clipped: bool| {
            let k = TRUNCATION_SIGMAS;
            let mut notes = Vec::new();
            if lo == default.0 {
                notes.push(if clipped {
                    "min just above 0".to_string()
                } else {
                    format!("min at -{k} sd")
                });
            }
            if hi == default.1 {
                notes.push(format!("max at +{k} sd"));
            }
            let notes = if notes.len() == 2 && !clipped {
                format!(" (±{k} sd)")
            } else if notes.is_empty() {
                String::new()
            } else {
                format!(" ({})", notes.join(", "))
            };
            format!(" in [{}, {}]{notes}", length(lo), length(hi))
        };
        match self {
            &SizeDist::Fixed(r) => format!("r = {r}"),
            &SizeDist::Normal { mean, sd, lo, hi } => format!(
                "r ~ normal(mean {mean}, sd {sd}){}",
                window(
                    lo,
                    hi,
                    SizeDist::normal_window(mean, sd),
                    mean - TRUNCATION_SIGMAS * sd <= 0.0
                )
            ),
            &SizeDist::Lognormal {
                median,
                gsd,
                lo,
                hi,
            } => format!(
                "r ~ lognormal(median {median}, gsd {gsd}){}",
                window(lo, hi, SizeDist::lognormal_window(median, gsd), false)
            ),
            SizeDist::Uniform { min, max } => format!("r ~ uniform({min}, {max})"),
            SizeDist::Table(t) => t.describe(),
        }
    }
}

/// Shape of a particle of a species.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A sphere (disc in 2D).
    Sphere,
    /// A rigid straight chain of `beads` equal spheres, centres `spacing × r` apart.
    Chain {
        /// Number of beads.
        beads: u32,
        /// Centre distance in bead radii.
        spacing: Real,
        /// Orientation of the axis on entry.
        orientation: EntryOrientation,
    },
}

impl Shape {
    /// Particles (beads) per body: 1 for a sphere.
    pub(crate) fn beads(&self) -> u32 {
        match self {
            Shape::Sphere => 1,
            Shape::Chain { beads, .. } => *beads,
        }
    }
}

/// Orientation of a chain's axis when it enters the box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EntryOrientation {
    /// Upright (the source study's choice); the first tilt goes to a random side.
    #[default]
    Vertical,
    /// Uniformly random direction.
    Random,
    /// Horizontal, with a uniformly random azimuth.
    Horizontal,
}

impl EntryOrientation {
    /// The config name: `vertical`, `random` or `horizontal`.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            EntryOrientation::Vertical => "vertical",
            EntryOrientation::Random => "random",
            EntryOrientation::Horizontal => "horizontal",
        }
    }
}

/// One species of a bed.
#[derive(Clone, Debug, PartialEq)]
pub struct Species {
    /// Human name ("large", "small", or from the config).
    pub name: String,
    /// Sphere or chain.
    pub shape: Shape,
    /// Radius of the sphere (or of each bead).
    pub size: SizeDist,
    /// Number ratio (relative probability of being drawn).
    pub ratio: Real,
    /// The `[[feeds]]` entry that feeds it (`None`: the bed has one feed).
    pub feed: Option<u32>,
}

/// Draws species indices with probability proportional to their ratios.
#[derive(Clone, Debug)]
pub struct SpeciesPicker {
    cumulative: Vec<Real>,
}

impl SpeciesPicker {
    /// A picker for these species (ratios validated to be >= 0 with a positive sum).
    pub(crate) fn new(species: &[Species]) -> Self {
        let total: Real = species.iter().map(|s| s.ratio).sum();
        let mut acc = 0.0;
        let cumulative = species
            .iter()
            .map(|s| {
                acc += s.ratio / total;
                acc
            })
            .collect();
        SpeciesPicker { cumulative }
    }

    /// Index of the next species.
    pub(crate) fn pick<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> usize {
        if self.cumulative.len() == 1 {
            return 0;
        }
        let u: Real = rng.random();
        self.cumulative
            .partition_point(|&c| c <= u)
            .min(self.cumulative.len() - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    fn lognormal(median: Real, gsd: Real, lo: Real, hi: Real) -> SizeDist {
        SizeDist::Lognormal {
            median,
            gsd,
            lo,
            hi,
        }
    }

    fn normal(mean: Real, sd: Real, lo: Real, hi: Real) -> SizeDist {
        SizeDist::Normal { mean, sd, lo, hi }
    }

    #[test]
    fn the_default_window_is_three_sd() {
        assert_eq!(SizeDist::lognormal_window(10.0, 2.0), (1.25, 80.0));
        assert_eq!(SizeDist::normal_window(10.0, 2.0), (4.0, 16.0));
        // 10 − 3·5 < 0: the lower end is cut just above 0, as before.
        assert_eq!(SizeDist::normal_window(10.0, 5.0), (0.01, 25.0));
        let (lo, hi) = SizeDist::lognormal_window(10.0, 1.3);
        assert!((lo.ln() - (10.0f64.ln() - 3.0 * 1.3f64.ln())).abs() < 1e-14);
        assert!((hi.ln() - (10.0f64.ln() + 3.0 * 1.3f64.ln())).abs() < 1e-14);
    }

    #[test]
    fn symmetric_windows_keep_the_centre_as_median() {
        let (lo, hi) = SizeDist::lognormal_window(10.0, 1.3);
        assert_eq!(lognormal(10.0, 1.3, lo, hi).median(), 10.0);
        assert_eq!(normal(10.0, 2.0, 4.0, 16.0).median(), 10.0);
    }

    #[test]
    fn describe_names_the_window() {
        let dists = [
            lognormal(10.0, 2.0, 1.25, 80.0),
            lognormal(10.0, 2.0, 2.0, 100.0),
            lognormal(10.0, 2.0, 2.0, 80.0),
            lognormal(10.0, 1.3, 10.0 / 1.3f64.powf(3.0), 40.0),
            normal(10.0, 2.0, 4.0, 16.0),
            normal(10.0, 5.0, 0.01, 25.0),
            normal(10.0, 5.0, 0.01, 20.0),
        ];
        let described = [
            "r ~ lognormal(median 10, gsd 2) in [1.25, 80] (±3 sd)",
            "r ~ lognormal(median 10, gsd 2) in [2, 100]",
            "r ~ lognormal(median 10, gsd 2) in [2, 80] (max at +3 sd)",
            "r ~ lognormal(median 10, gsd 1.3) in [4.55166, 40] (min at -3 sd)",
            "r ~ normal(mean 10, sd 2) in [4, 16] (±3 sd)",
            "r ~ normal(mean 10, sd 5) in [0.01, 25] (min just above 0, max at +3 sd)",
            "r ~ normal(mean 10, sd 5) in [0.01, 20] (min just above 0)",
        ];
        assert_eq!(dists.map(|d| d.describe()), described);
    }

    #[test]
    fn a_window_far_in_a_tail_draws_at_once() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
        // 17, 48 and 200 sd above the median: tiny, subnormal and no
        // representable probability at all.
        for (lo, hi) in [(50.0, 60.0), (1e3, 2e3), (1e10, 1e11)] {
            let d = lognormal(10.0, 1.1, lo, hi);
            for _ in 0..1000 {
                let r = d.sample(&mut rng);
                assert!((lo..=hi).contains(&r), "[{lo}, {hi}]: {r}");
            }
            // Far out, the density falls so fast that the median hugs `lo`.
            assert!(d.median() < lo * 1.01, "[{lo}, {hi}]: {}", d.median());
        }
        let below = normal(100.0, 1.0, 1.0, 2.0);
        for _ in 0..1000 {
            let r = below.sample(&mut rng);
            assert!((1.0..=2.0).contains(&r), "{r}");
        }
        assert!(below.median() > 1.99);
    }

    proptest! {
        #[test]
        fn samples_stay_in_the_window(
            median in 1e-3f64..1e3,
            gsd in 1.0f64..5.0,
            lo_sd in -12.0f64..12.0,
            width_sd in 0.0f64..12.0,
            seed in any::<u64>(),
        ) {
            // Windows anywhere, in the body or far in a tail, of any width.
            let s = gsd.ln();
            let lo = median * (lo_sd * s).exp();
            let hi = median * ((lo_sd + width_sd) * s).exp();
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            for d in [
                lognormal(median, gsd, lo, hi),
                normal(median, median * (gsd - 1.0), lo, hi),
            ] {
                prop_assert_eq!(d.bounds(), (lo, hi));
                for _ in 0..200 {
                    let r = d.sample(&mut rng);
                    prop_assert!(lo <= r && r <= hi, "{:?}: {}", d, r);
                }
                let m = d.median();
                prop_assert!(lo <= m && m <= hi, "{:?}: median {}", d, m);
            }
        }
    }
}
