//! Particle species: shape, size distribution and number ratio.

use crate::error::{Error, Result};
use crate::math::Real;
use rand::RngExt;
use rand_distr::{Distribution, LogNormal, Normal};
use std::path::{Path, PathBuf};

/// Unbounded size distributions are truncated to their central part, so that every
/// species has a finite largest radius (the neighbour grid is sized by it). The tail
/// beyond this many standard deviations (of the radius, or of its logarithm for
/// lognormal) has probability 5.7e-7 and is redrawn.
pub const TRUNCATION_SIGMAS: Real = 5.0;

/// How the radius of a new particle is chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum SizeDist {
    /// Every particle has this radius.
    Fixed(Real),
    /// Normal distribution, truncated to `(0, ∞)` and to ±5 sd.
    Normal {
        /// Mean radius.
        mean: Real,
        /// Standard deviation.
        sd: Real,
    },
    /// Lognormal distribution by median and geometric standard deviation,
    /// truncated to `median · gsd^±5`.
    Lognormal {
        /// Median radius.
        median: Real,
        /// Geometric standard deviation (> 1; 1 means a fixed size).
        gsd: Real,
    },
    /// Uniform on `[min, max]`.
    Uniform {
        /// Smallest radius.
        min: Real,
        /// Largest radius.
        max: Real,
    },
    /// A measured particle size distribution: radii with number weights.
    Table {
        /// The radii.
        radii: Vec<Real>,
        /// Cumulative weights, normalised so that the last is 1.
        cumulative: Vec<Real>,
        /// Where the table came from, for the summary.
        source: PathBuf,
    },
}

impl SizeDist {
    /// The smallest and largest radius this distribution can produce.
    pub fn bounds(&self) -> (Real, Real) {
        match self {
            SizeDist::Fixed(r) => (*r, *r),
            SizeDist::Normal { mean, sd } => {
                let lo = mean - TRUNCATION_SIGMAS * sd;
                (
                    if lo > 0.0 { lo } else { mean * 1e-3 },
                    mean + TRUNCATION_SIGMAS * sd,
                )
            }
            SizeDist::Lognormal { median, gsd } => {
                let f = gsd.powf(TRUNCATION_SIGMAS);
                (median / f, median * f)
            }
            SizeDist::Uniform { min, max } => (*min, *max),
            SizeDist::Table { radii, .. } => radii
                .iter()
                .fold((Real::INFINITY, 0.0), |(lo, hi), &r| (lo.min(r), hi.max(r))),
        }
    }

    /// The median radius: the typical size of the species, used to name species
    /// "large" and "small" (the truncation bounds of a tail say little of it).
    pub fn median(&self) -> Real {
        match self {
            SizeDist::Fixed(r) => *r,
            // Truncation at ±k sd on both sides (or at 0 and +k sd) keeps the
            // mean as the centre of a symmetric normal; near-0 cuts shift it a little.
            SizeDist::Normal { mean, .. } => *mean,
            SizeDist::Lognormal { median, .. } => *median,
            SizeDist::Uniform { min, max } => 0.5 * (min + max),
            SizeDist::Table {
                radii, cumulative, ..
            } => {
                // Rows may come in any order: weigh them in order of radius.
                let mut rows: Vec<(Real, Real)> = radii
                    .iter()
                    .zip(cumulative)
                    .scan(0.0, |prev, (&r, &c)| {
                        let w = c - *prev;
                        *prev = c;
                        Some((r, w))
                    })
                    .collect();
                rows.sort_by(|a, b| a.0.total_cmp(&b.0));
                let mut acc = 0.0;
                for &(r, w) in &rows {
                    acc += w;
                    if acc >= 0.5 {
                        return r;
                    }
                }
                rows.last().map_or(0.0, |x| x.0)
            }
        }
    }

    /// Draws one radius.
    pub fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> Real {
        let (lo, hi) = self.bounds();
        match self {
            SizeDist::Fixed(r) => *r,
            SizeDist::Normal { mean, sd } => {
                if *sd == 0.0 {
                    return *mean;
                }
                let n = Normal::new(*mean, *sd).expect("validated");
                loop {
                    let r = n.sample(rng);
                    if r >= lo && r <= hi {
                        return r;
                    }
                }
            }
            SizeDist::Lognormal { median, gsd } => {
                if *gsd == 1.0 {
                    return *median;
                }
                let n = LogNormal::new(median.ln(), gsd.ln()).expect("validated");
                loop {
                    let r = n.sample(rng);
                    if r >= lo && r <= hi {
                        return r;
                    }
                }
            }
            SizeDist::Uniform { min, max } => {
                if min == max {
                    *min
                } else {
                    rng.random_range(*min..=*max)
                }
            }
            SizeDist::Table {
                radii, cumulative, ..
            } => {
                let u: Real = rng.random();
                let i = cumulative.partition_point(|&c| c <= u);
                radii[i.min(radii.len() - 1)]
            }
        }
    }

    /// Mean radius (of the truncated distribution where it matters little).
    pub fn describe(&self) -> String {
        match self {
            SizeDist::Fixed(r) => format!("r = {r}"),
            SizeDist::Normal { mean, sd } => format!("r ~ normal(mean {mean}, sd {sd})"),
            SizeDist::Lognormal { median, gsd } => {
                format!("r ~ lognormal(median {median}, gsd {gsd})")
            }
            SizeDist::Uniform { min, max } => format!("r ~ uniform({min}, {max})"),
            SizeDist::Table { source, radii, .. } => {
                format!("r from {} ({} sizes)", source.display(), radii.len())
            }
        }
    }

    /// Reads a PSD table: CSV (or whitespace) rows `radius,weight`, optional header.
    pub fn read_table(path: &Path) -> Result<SizeDist> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let data_err = |line: usize, message: String| Error::Data {
            path: path.to_path_buf(),
            line,
            message,
        };
        let mut radii = Vec::new();
        let mut weights = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line
                .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
                .filter(|f| !f.is_empty())
                .collect();
            let parsed: Vec<Option<Real>> = fields.iter().map(|f| f.parse().ok()).collect();
            if radii.is_empty() && weights.is_empty() && parsed.iter().any(|p| p.is_none()) {
                continue; // a header line
            }
            if fields.len() != 2 {
                return Err(data_err(
                    i + 1,
                    format!(
                        "expected two columns `radius,weight`, found {}",
                        fields.len()
                    ),
                ));
            }
            let (Some(r), Some(w)) = (parsed[0], parsed[1]) else {
                return Err(data_err(i + 1, format!("not a number in `{line}`")));
            };
            if !(r.is_finite() && r > 0.0) {
                return Err(data_err(i + 1, format!("radius must be positive, got {r}")));
            }
            if !(w.is_finite() && w >= 0.0) {
                return Err(data_err(i + 1, format!("weight must be >= 0, got {w}")));
            }
            radii.push(r);
            weights.push(w);
        }
        let total: Real = weights.iter().sum();
        if radii.is_empty() || total <= 0.0 {
            return Err(data_err(
                text.lines().count().max(1),
                "the table has no radius with a positive weight".into(),
            ));
        }
        let mut acc = 0.0;
        let cumulative = weights
            .iter()
            .map(|w| {
                acc += w / total;
                acc
            })
            .collect();
        Ok(SizeDist::Table {
            radii,
            cumulative,
            source: path.to_path_buf(),
        })
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
        orientation: Orientation,
    },
}

/// Orientation of a chain's axis when it enters the box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Orientation {
    /// Upright (the source study's choice); the first tilt goes to a random side.
    #[default]
    Vertical,
    /// Uniformly random direction.
    Random,
    /// Horizontal, with a uniformly random azimuth.
    Horizontal,
}

impl Orientation {
    /// The config name: `vertical`, `random` or `horizontal`.
    pub fn name(&self) -> &'static str {
        match self {
            Orientation::Vertical => "vertical",
            Orientation::Random => "random",
            Orientation::Horizontal => "horizontal",
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
}

/// Draws species indices with probability proportional to their ratios.
#[derive(Clone, Debug)]
pub struct SpeciesPicker {
    cumulative: Vec<Real>,
}

impl SpeciesPicker {
    /// A picker for these species (ratios validated to be >= 0 with a positive sum).
    pub fn new(species: &[Species]) -> Self {
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
    pub fn pick<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> usize {
        if self.cumulative.len() == 1 {
            return 0;
        }
        let u: Real = rng.random();
        self.cumulative
            .partition_point(|&c| c <= u)
            .min(self.cumulative.len() - 1)
    }
}
