//! Percolation chains of large particles: the graph of large bodies linked by
//! their contacts, whether it spans the bed wall to wall (or wraps around a
//! periodic box), the shortest chain, the number of vertex-disjoint chains and the
//! source study's count of unique chains.
//!
//! Nodes are bodies (a sphere is a body; a chain of beads is one node, large if any
//! bead is). A chain in direction `x` is a path from a body touching the wall
//! `x0` to one touching `x1` whose inner bodies touch neither: a path through a
//! wall-touching body already contains a shorter chain. In 3D both `x` and `y` are
//! directions.
//!
//! Periodic sides have no walls. A cluster percolates along an axis when it wraps
//! around: a breadth-first search gives each body the image offset it is reached
//! with, and an edge that reaches a body with a second, different offset closes a
//! loop around the box. The chain counts (shortest, disjoint, unique) then treat the
//! periodic seam `x = 0 ≡ W` as the pair of walls: a chain runs from a body with a
//! contact across the seam on its left to one with a contact across the seam on its
//! right, without crossing the seam itself (a path across the periodic cell).

//!
//! Modules: [`options`] (what is large, the caps), `graph` and
//! [`large_graph`] (the graph of large bodies, the terminals of a chain),
//! [`clusters`] (clusters and which span), `shortest`, `disjoint` (the exact
//! count of disjoint chains), `unique` (the enumeration of unique chains) and
//! [`report`] (the figures written to `summary.json`).

mod clusters;
mod disjoint;
mod graph;
mod large_graph;
pub mod options;
pub mod report;
mod shortest;
mod unique;

#[cfg(test)]
mod tests;

pub use clusters::{clusters, spanning};
pub use disjoint::disjoint_chains;
#[cfg(test)]
use graph::LinkGraph;
pub use graph::Terminals;
pub use large_graph::{large_graph, terminals};
#[cfg(test)]
use options::{default_large, volume_median};
pub use options::{LargeRule, LargeSource, PercolationOptions};
#[cfg(test)]
use report::LengthStats;
pub use report::{DirectionPercolation, Percolation};
pub use shortest::shortest_chain;
pub use unique::unique_chains;

use super::contacts::Contacts;
use super::StageTimes;
use crate::bed::Bed;
use rayon::prelude::*;
use report::length_stats;

/// The percolation analysis of `bed`.
pub fn percolation<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    opts: &PercolationOptions,
) -> Percolation {
    percolation_timed(bed, contacts, opts, &mut StageTimes::default())
}

/// The percolation analysis of `bed`, timing its stages into `times`.
pub fn percolation_timed<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    opts: &PercolationOptions,
    times: &mut StageTimes,
) -> Percolation {
    let lg = times.time("percolation/graph", || {
        large_graph(bed, contacts, opts.large)
    });
    let g = &lg.graph;
    let found = times.time("percolation/clusters", || clusters(g));
    let sizes = &found.sizes;
    let periodic = bed.container.periodic;
    let mut spanning_any = vec![false; sizes.len()];
    let mut all_chains: Vec<Vec<u32>> = Vec::new();
    let mut directions = Vec::new();
    let ends: Vec<Terminals> = times.time("percolation/graph", || {
        (0..D - 1)
            .map(|k| terminals(bed, contacts, &lg, k))
            .collect()
    });
    // The max flow dominates the whole analysis of a large bed, and the
    // directions are independent: one thread each.
    let disjoint: Vec<u64> = times.time("percolation/disjoint", || {
        ends.par_iter().map(|t| disjoint_chains(g, t)).collect()
    });
    let shortest: Vec<Option<u64>> = times.time("percolation/shortest", || {
        ends.par_iter().map(|t| shortest_chain(g, t)).collect()
    });
    for (k, t) in ends.iter().enumerate() {
        let spans = spanning(&found, t, periodic, k);
        for c in 0..sizes.len() {
            spanning_any[c] |= spans[c];
        }
        let en = times.time("percolation/enumeration", || {
            unique_chains(
                g,
                t,
                opts.max_chains,
                opts.max_chain_length,
                opts.max_search_steps,
            )
        });
        let spanning_clusters = spans.iter().filter(|&&s| s).count() as u64;
        directions.push(DirectionPercolation {
            axis: ["x", "y"][k].to_string(),
            spans: spanning_clusters > 0,
            spanning_clusters,
            shortest_chain: shortest[k],
            disjoint_chains: disjoint[k],
            unique_chains: en.chains.len() as u64,
            chain_cap_hit: en.chain_cap_hit,
            length_cap_hit: en.length_cap_hit,
            search_cap_hit: en.search_cap_hit,
            chain_length: length_stats(&en.chains),
        });
        all_chains.extend(en.chains);
    }
    Percolation {
        large_radius: lg.large_radius,
        large_rule: lg.large_source,
        large_bodies: g.len() as u64,
        clusters: sizes.len() as u64,
        largest_cluster: sizes.iter().copied().max().unwrap_or(0),
        criterion: if periodic { "wraps" } else { "walls" }.into(),
        spans: directions.iter().any(|d| d.spans),
        spanning_clusters: spanning_any.iter().filter(|&&s| s).count() as u64,
        shortest_chain: directions.iter().filter_map(|d| d.shortest_chain).min(),
        disjoint_chains: directions
            .iter()
            .map(|d| d.disjoint_chains)
            .max()
            .unwrap_or(0),
        disjoint_chains_sum: directions.iter().map(|d| d.disjoint_chains).sum(),
        unique_chains: directions.iter().map(|d| d.unique_chains).sum(),
        cap_hit: directions
            .iter()
            .any(|d| d.chain_cap_hit || d.length_cap_hit || d.search_cap_hit),
        chain_length: length_stats(&all_chains),
        directions,
    }
}

/// Where a particle stands in the percolation of large bodies.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Membership {
    /// Part of a large body in a cluster that spans (walls) or wraps (periodic)
    /// along some horizontal axis.
    Spanning,
    /// Part of a large body in a cluster that does not.
    Large,
    /// Not part of a large body.
    Small,
}

/// Per particle, its [`Membership`]: the large bodies and spanning clusters of
/// [`percolation`] itself (same threshold, same graph, same criterion), so that
/// a picture of the chains agrees with `summary.json`.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub fn membership<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    large: LargeRule,
) -> Vec<Membership> {
    let lg = large_graph(bed, contacts, large);
    let found = clusters(&lg.graph);
    let mut spans = vec![false; found.sizes.len()];
    for k in 0..D - 1 {
        let t = terminals(bed, contacts, &lg, k);
        for (any, s) in spans
            .iter_mut()
            .zip(spanning(&found, &t, bed.container.periodic, k))
        {
            *any |= s;
        }
    }
    lg.node_of
        .iter()
        .map(|&u| match u {
            u32::MAX => Membership::Small,
            u if spans[found.comp[u as usize] as usize] => Membership::Spanning,
            _ => Membership::Large,
        })
        .collect()
}
