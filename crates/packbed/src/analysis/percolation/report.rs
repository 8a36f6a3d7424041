//! The figures of the percolation analysis as `summary.json` holds them.

use super::options::LargeSource;
use crate::math::Real;
use serde::Serialize;

/// Min, mean and max of the enumerated chain lengths (particles).
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq)]
pub struct LengthStats {
    /// Shortest enumerated chain.
    pub min: u64,
    /// Mean length.
    pub mean: Real,
    /// Longest enumerated chain.
    pub max: u64,
}

/// Percolation along one horizontal axis.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct DirectionPercolation {
    /// `x` or `y`.
    pub axis: String,
    /// A chain exists (walls) or a cluster wraps around (periodic).
    pub spans: bool,
    /// Clusters that span (walls) or wrap (periodic) along this axis.
    pub spanning_clusters: u64,
    /// Particles in the shortest chain (`None`: no chain).
    pub shortest_chain: Option<u64>,
    /// Maximum number of chains sharing no particle.
    pub disjoint_chains: u64,
    /// Distinct particle sets forming a chain, as enumerated within the caps.
    pub unique_chains: u64,
    /// The enumeration stopped at `max_chains`.
    pub chain_cap_hit: bool,
    /// Some branch of the enumeration was cut because every chain through it
    /// would be longer than `max_chain_length`.
    pub length_cap_hit: bool,
    /// The enumeration stopped at `max_search_steps`.
    pub search_cap_hit: bool,
    /// Lengths of the enumerated chains (`None`: none enumerated).
    pub chain_length: Option<LengthStats>,
}

/// `percolation.*` of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Percolation {
    /// Particles with `r >=` this are large.
    pub large_radius: Real,
    /// Where `large_radius` came from: `given`, `largest size` (the radius
    /// of a species of one size) or `volume median` (of a species of several).
    pub large_rule: LargeSource,
    /// Large bodies (graph nodes).
    pub large_bodies: u64,
    /// Connected clusters of large bodies.
    pub clusters: u64,
    /// Bodies in the largest cluster.
    pub largest_cluster: u64,
    /// `walls` (wall-to-wall chains) or `wraps` (periodic sides).
    pub criterion: String,
    /// A chain exists in some direction.
    pub spans: bool,
    /// Clusters spanning in at least one direction.
    pub spanning_clusters: u64,
    /// Shortest chain over the directions.
    pub shortest_chain: Option<u64>,
    /// Vertex-disjoint chains in the direction with the most (2D: along x).
    pub disjoint_chains: u64,
    /// Vertex-disjoint chains summed over the directions (3D: x and y counted
    /// together, as the source study counted chains "in x or y"; 2D: along x).
    pub disjoint_chains_sum: u64,
    /// Unique chains summed over the directions (per direction in `directions`).
    pub unique_chains: u64,
    /// Some cap of the enumeration was hit in some direction.
    pub cap_hit: bool,
    /// Lengths over all enumerated chains.
    pub chain_length: Option<LengthStats>,
    /// Per direction: `x` (2D), `x` and `y` (3D).
    pub directions: Vec<DirectionPercolation>,
}

/// Min, mean and max length of `chains` (`None`: no chain).
pub(super) fn length_stats(chains: &[Vec<u32>]) -> Option<LengthStats> {
    if chains.is_empty() {
        return None;
    }
    let lens = chains.iter().map(|c| c.len() as u64);
    Some(LengthStats {
        min: lens.clone().min().unwrap_or(0),
        max: lens.clone().max().unwrap_or(0),
        mean: lens.sum::<u64>() as Real / chains.len() as Real,
    })
}
