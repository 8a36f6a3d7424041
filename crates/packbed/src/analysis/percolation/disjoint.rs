//! The exact number of chains sharing no body: a maximum flow.

use super::graph::{LinkGraph, Terminals};
use crate::analysis::disjoint_paths::{max_disjoint_paths, PathProblem};

/// Maximum number of chains with no node in common: the maximum flow from the
/// start nodes to the end nodes with unit node capacities (each node split into an
/// inlet and an outlet joined by an arc of capacity 1), by push–relabel.
pub fn disjoint_chains(g: &LinkGraph, t: &Terminals) -> u64 {
    let n = g.len();
    // Only nodes that can lie on a chain matter: reachable from a start node and
    // reaching an end node through usable edges.
    let from_start = reach(g, t, &t.start);
    let to_end = reach(g, t, &t.end);
    let keep: Vec<bool> = (0..n).map(|u| from_start[u] && to_end[u]).collect();
    // Number the nodes in breadth-first order from the start nodes: neighbours
    // in the bed then sit close together in memory. The flow's phases are sweeps
    // of the whole network, and with the bed's own (deposition) order nearly
    // every step was a cache miss: on a 2·10^5-sphere bed this is most of the
    // analysis time.
    let mut id = vec![u32::MAX; n];
    let mut order: Vec<usize> = Vec::new();
    for u in 0..n {
        if keep[u] && t.start[u] {
            id[u] = order.len() as u32;
            order.push(u);
        }
    }
    let mut head = 0;
    while head < order.len() {
        let u = order[head];
        head += 1;
        for e in g.edges(u) {
            let v = g.adj[e] as usize;
            if keep[v] && id[v] == u32::MAX && t.usable(g, e) {
                id[v] = order.len() as u32;
                order.push(v);
            }
        }
    }
    let mut row = Vec::with_capacity(order.len() + 1);
    let mut adj = Vec::new();
    row.push(0u32);
    for &u in &order {
        for e in g.edges(u) {
            let v = g.adj[e] as usize;
            if keep[v] && v != u && t.usable(g, e) {
                adj.push(id[v]);
            }
        }
        row.push(adj.len() as u32);
    }
    let start: Vec<bool> = order.iter().map(|&u| t.start[u]).collect();
    let end: Vec<bool> = order.iter().map(|&u| t.end[u]).collect();
    max_disjoint_paths(&PathProblem {
        row: &row,
        adj: &adj,
        start: &start,
        end: &end,
    })
}

/// Nodes reachable from `seeds` through usable edges.
fn reach(g: &LinkGraph, t: &Terminals, seeds: &[bool]) -> Vec<bool> {
    let mut seen = seeds.to_vec();
    let mut stack: Vec<usize> = (0..g.len()).filter(|&u| seeds[u]).collect();
    while let Some(u) = stack.pop() {
        for e in g.edges(u) {
            let v = g.adj[e] as usize;
            if !seen[v] && t.usable(g, e) {
                seen[v] = true;
                stack.push(v);
            }
        }
    }
    seen
}
