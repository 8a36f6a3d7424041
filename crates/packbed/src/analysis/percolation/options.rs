//! What counts as a large particle, and the caps of the chain enumeration.

use crate::bed::Bed;
use crate::math::Real;
use serde::Serialize;

/// Default cap on the number of unique chains enumerated per direction.
pub const MAX_CHAINS: usize = 400;
/// Default cap on the length (in particles) of an enumerated chain.
pub const MAX_CHAIN_LENGTH: usize = 250;
/// Default cap on the edges the chain enumeration follows per direction, so that
/// a dense graph without chains cannot keep it busy for ever.
pub const MAX_SEARCH_STEPS: u64 = 5_000_000;

/// Which particles are large.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LargeRule {
    /// Particles with `r >=` the default large radius of the bed (the
    /// default): the largest over the species of the volume-median radius
    /// drawn in that species, which for a species of one size is its radius.
    Median,
    /// Particles with `r >=` a given `R` (relative slack 1e-9 for radii read
    /// from text).
    Radius(Real),
}

/// Where the threshold of "large" came from (`percolation.large_rule`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum LargeSource {
    /// Given by the user (`--large`, `analysis.large_radius`).
    #[serde(rename = "given")]
    Given,
    /// The default, decided by a species of one size: its radius.
    #[default]
    #[serde(rename = "largest size")]
    LargestSize,
    /// The default, decided by a species of several sizes: its volume-median
    /// radius.
    #[serde(rename = "volume median")]
    VolumeMedian,
}

/// Settings of the percolation analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PercolationOptions {
    /// Which particles are large.
    pub large: LargeRule,
    /// Stop enumerating unique chains after this many (per direction).
    pub max_chains: usize,
    /// Do not enumerate chains longer than this many particles.
    pub max_chain_length: usize,
    /// Stop the enumeration after following this many edges (per direction).
    pub max_search_steps: u64,
}

impl Default for PercolationOptions {
    fn default() -> Self {
        PercolationOptions {
            large: LargeRule::Median,
            max_chains: MAX_CHAINS,
            max_chain_length: MAX_CHAIN_LENGTH,
            max_search_steps: MAX_SEARCH_STEPS,
        }
    }
}

/// Which particles are large, the radius threshold that means, and where the
/// threshold came from.
pub(super) fn large_particles<const D: usize>(
    bed: &Bed<D>,
    rule: LargeRule,
) -> (Vec<bool>, Real, LargeSource) {
    let (r, source) = match rule {
        LargeRule::Radius(r) => (r, LargeSource::Given),
        LargeRule::Median => default_large(bed),
    };
    // Radii read back from text differ from the threshold in the last digits.
    let cut = r * (1.0 - 1e-9);
    (bed.radii.iter().map(|&x| x >= cut).collect(), r, source)
}

/// The default threshold of "large": the largest, over the species present,
/// of the volume-median radius drawn in that species (0 for an empty bed),
/// and whether a species of one size or of several decided it.
///
/// A species of one size gives its radius, so radii 10 and 20 make the 20s
/// large and equal radii make every particle large, whatever the species. A
/// size distribution gives the radius below which half of its drawn volume
/// lies: the coarse half of the solid, as a sieve analysis by mass sees it.
/// The number median it replaced made a measured table, where fines are most
/// of the count, call nearly every particle large; the truncation bound of the
/// tail would call almost nothing large.
pub fn default_large<const D: usize>(bed: &Bed<D>) -> (Real, LargeSource) {
    let mut by_species: Vec<(u32, Real)> = bed
        .species
        .iter()
        .zip(&bed.radii)
        .map(|(&s, &r)| (s, r))
        .collect();
    by_species.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut best: (Real, LargeSource) = (0.0, LargeSource::LargestSize);
    for group in by_species.chunk_by(|a, b| a.0 == b.0) {
        let radii: Vec<Real> = group.iter().map(|&(_, r)| r).collect();
        let one_size = radii.first() == radii.last();
        let r = volume_median::<D>(&radii);
        // On a tie the species of one size names the threshold: its radius is
        // the plainer reason.
        if r > best.0 || (r == best.0 && one_size) {
            let source = if one_size {
                LargeSource::LargestSize
            } else {
                LargeSource::VolumeMedian
            };
            best = (r, source);
        }
    }
    best
}

/// The smallest of `sorted` (ascending radii) at which the particles up to and
/// including it hold at least half of the volume (`r^D`: area in 2D); 0 for
/// none.
pub fn volume_median<const D: usize>(sorted: &[Real]) -> Real {
    let volume = |r: Real| r.powi(D as i32);
    // Summed in the same order as the running sum below, so that the last
    // radius always reaches the half.
    let total: Real = sorted.iter().map(|&r| volume(r)).sum();
    let mut below = 0.0;
    for &r in sorted {
        below += volume(r);
        if below >= 0.5 * total {
            return r;
        }
    }
    sorted.last().copied().unwrap_or(0.0)
}
