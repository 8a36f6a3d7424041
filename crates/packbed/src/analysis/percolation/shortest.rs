//! The shortest chain, by breadth-first search.

use super::graph::{LinkGraph, Terminals};
use std::collections::VecDeque;

/// Nodes in the shortest chain (breadth-first search from every start node), or
/// `None` when no chain exists.
pub fn shortest_chain(g: &LinkGraph, t: &Terminals) -> Option<u64> {
    let n = g.len();
    let mut dist = vec![u32::MAX; n];
    let mut queue = VecDeque::new();
    for u in 0..n {
        if t.start[u] {
            if t.end[u] {
                return Some(1);
            }
            dist[u] = 1;
            queue.push_back(u);
        }
    }
    while let Some(u) = queue.pop_front() {
        for e in g.edges(u) {
            if !t.usable(g, e) {
                continue;
            }
            let v = g.adj[e] as usize;
            if dist[v] == u32::MAX {
                dist[v] = dist[u] + 1;
                if t.end[v] {
                    return Some(u64::from(dist[v]));
                }
                queue.push_back(v);
            }
        }
    }
    None
}
