//! What counts as a large particle, and the caps of the chain enumeration.

use crate::bed::Bed;
use crate::math::Real;

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
    /// Particles with `r >=` the [`default_large_radius`] of the bed: the
    /// largest of the species' median drawn radii (the default).
    Median,
    /// Particles with `r >= R` (relative slack 1e-9 for radii read from text).
    Radius(Real),
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

/// Which particles are large, and the radius threshold that means.
pub(super) fn large_particles<const D: usize>(bed: &Bed<D>, rule: LargeRule) -> (Vec<bool>, Real) {
    let r = match rule {
        LargeRule::Radius(r) => r,
        LargeRule::Median => default_large_radius(bed),
    };
    // Radii read back from text differ from the threshold in the last digits.
    let cut = r * (1.0 - 1e-9);
    (bed.radii.iter().map(|&x| x >= cut).collect(), r)
}

/// The default threshold of "large": the largest, over the species present,
/// of the median radius drawn in that species (0 for an empty bed).
///
/// A species of one size gives its radius, so radii 10 and 20 make the 20s
/// large and equal radii make every particle large, whatever the species. A
/// size distribution gives its median as drawn, not the truncation bound of
/// its tail, which for a lognormal is far out and held by almost nothing.
pub fn default_large_radius<const D: usize>(bed: &Bed<D>) -> Real {
    let mut by_species: Vec<(u32, Real)> = bed
        .species
        .iter()
        .zip(&bed.radii)
        .map(|(&s, &r)| (s, r))
        .collect();
    by_species.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut best: Real = 0.0;
    for group in by_species.chunk_by(|a, b| a.0 == b.0) {
        let m = group.len();
        let median = if m % 2 == 1 {
            group[m / 2].1
        } else {
            0.5 * (group[m / 2 - 1].1 + group[m / 2].1)
        };
        best = best.max(median);
    }
    best
}
