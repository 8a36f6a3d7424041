//! The source study's count of unique chains: a capped depth-first enumeration
//! of the distinct body sets forming a chain.

use super::graph::{LinkGraph, Terminals};
use std::collections::{HashSet, VecDeque};

/// Outcome of the chain enumeration along one axis.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Enumeration {
    /// Each distinct chain as its sorted node set.
    pub chains: Vec<Vec<u32>>,
    /// Stopped at the chain cap.
    pub chain_cap_hit: bool,
    /// A branch was cut by the length cap.
    pub length_cap_hit: bool,
    /// Stopped at the step cap.
    pub search_cap_hit: bool,
}

/// Enumerates the distinct node sets of chains (simple paths from a start node to
/// an end node, inner nodes neither), depth first from the start nodes in order,
/// within the caps, nearest-to-the-end neighbours first. Branches that cannot reach an end node, or only in more than
/// `max_len` nodes, are cut using the breadth-first distance to the end nodes.
pub fn unique_chains(
    g: &LinkGraph,
    t: &Terminals,
    max_chains: usize,
    max_len: usize,
    max_steps: u64,
) -> Enumeration {
    let n = g.len();
    let mut out = Enumeration::default();
    if max_chains == 0 || max_len == 0 {
        return out;
    }
    // Distance (in edges) to the nearest end node through usable inner nodes.
    let mut to_end = vec![u32::MAX; n];
    let mut queue = VecDeque::new();
    for u in 0..n {
        if t.end[u] {
            to_end[u] = 0;
            queue.push_back(u);
        }
    }
    while let Some(u) = queue.pop_front() {
        if to_end[u] > 0 && t.start[u] {
            continue; // chains do not pass through a start node
        }
        for e in g.edges(u) {
            let v = g.adj[e] as usize;
            if to_end[v] == u32::MAX && t.usable(g, e) {
                to_end[v] = to_end[u] + 1;
                queue.push_back(v);
            }
        }
    }
    // Try the neighbours nearest to the end first, so that the enumeration meets
    // short chains early rather than wandering through the whole cluster.
    let mut order: Vec<usize> = (0..g.adj.len()).collect();
    for u in 0..n {
        order[g.row[u]..g.row[u + 1]].sort_by_key(|&e| (to_end[g.adj[e] as usize], e));
    }
    let mut seen: HashSet<Vec<u32>> = HashSet::new();
    let mut on_path = vec![false; n];
    let mut path: Vec<u32> = Vec::new();
    let mut cursor: Vec<usize> = Vec::new();
    let mut steps = 0u64;
    let mut seen_at = vec![0u32; n];
    let mut stamp = 0u32;
    let mut stack: Vec<u32> = Vec::new();
    let mut record = |path: &[u32], out: &mut Enumeration| -> bool {
        let mut set = path.to_vec();
        set.sort_unstable();
        if seen.insert(set.clone()) {
            out.chains.push(set);
        }
        out.chains.len() >= max_chains
    };
    // A shortest chain first: whatever the caps cut later, the enumerated
    // lengths then start at the breadth-first shortest chain and never
    // contradict it (a capped search from the first start nodes could miss it).
    if let Some(s) = (0..n)
        .filter(|&s| t.start[s] && to_end[s] != u32::MAX)
        .min_by_key(|&s| (to_end[s], s))
    {
        if (to_end[s] as usize) < max_len {
            let mut chain = vec![s as u32];
            let mut u = s;
            while to_end[u] > 0 {
                let next = order[g.row[u]..g.row[u + 1]].iter().find(|&&e| {
                    let v = g.adj[e] as usize;
                    t.usable(g, e) && !t.start[v] && to_end[v] + 1 == to_end[u]
                });
                let Some(&e) = next else {
                    chain.clear();
                    break;
                };
                u = g.adj[e] as usize;
                chain.push(u as u32);
            }
            if !chain.is_empty() && record(&chain, &mut out) {
                out.chain_cap_hit = true;
                return out;
            }
        }
    }
    for s in 0..n {
        if !t.start[s] || to_end[s] == u32::MAX {
            continue;
        }
        if t.end[s] {
            if record(&[s as u32], &mut out) {
                out.chain_cap_hit = true;
                return out;
            }
            continue;
        }
        if to_end[s] as usize + 1 > max_len {
            out.length_cap_hit = true;
            continue;
        }
        path.push(s as u32);
        cursor.push(g.row[s]);
        on_path[s] = true;
        while let Some(&u) = path.last() {
            let u = u as usize;
            let depth = path.len();
            let c = cursor.last_mut().expect("cursor follows path");
            if *c >= g.row[u + 1] {
                on_path[u] = false;
                path.pop();
                cursor.pop();
                continue;
            }
            let e = order[*c];
            *c += 1;
            steps += 1;
            if steps > max_steps {
                out.search_cap_hit = true;
                return out;
            }
            let v = g.adj[e] as usize;
            if on_path[v] || !t.usable(g, e) || t.start[v] || to_end[v] == u32::MAX {
                continue;
            }
            if depth + 1 + to_end[v] as usize > max_len {
                out.length_cap_hit = true;
                continue;
            }
            if t.end[v] {
                path.push(v as u32);
                let full = record(&path, &mut out);
                path.pop();
                if full {
                    out.chain_cap_hit = true;
                    return out;
                }
                continue;
            }
            // Enter `v` only if an end node is still reachable from it around the
            // path: every branch then ends in a chain, so the work per chain found
            // stays bounded instead of growing with the dead branches of the
            // cluster (which exhausted the step cap on most small beds).
            stamp += 1;
            match reaches_end(
                g,
                t,
                &order,
                &to_end,
                &on_path,
                v,
                &mut seen_at,
                stamp,
                &mut stack,
            ) {
                Some(work) => steps += work,
                None => {
                    steps += n as u64;
                    continue;
                }
            }
            path.push(v as u32);
            cursor.push(g.row[v]);
            on_path[v] = true;
        }
    }
    out
}

/// Whether an end node can be reached from `v` through nodes off the path that
/// are not start nodes; `Some(nodes visited)` if so. A depth-first search trying
/// the neighbours nearest the end first, so it usually walks straight there.
#[allow(clippy::too_many_arguments)]
fn reaches_end(
    g: &LinkGraph,
    t: &Terminals,
    order: &[usize],
    to_end: &[u32],
    on_path: &[bool],
    v: usize,
    seen_at: &mut [u32],
    stamp: u32,
    stack: &mut Vec<u32>,
) -> Option<u64> {
    stack.clear();
    stack.push(v as u32);
    seen_at[v] = stamp;
    let mut work = 0u64;
    while let Some(u) = stack.pop() {
        let u = u as usize;
        work += 1;
        if t.end[u] {
            return Some(work);
        }
        // Pushed in reverse so that the nearest neighbour is popped first.
        for &e in order[g.row[u]..g.row[u + 1]].iter().rev() {
            let w = g.adj[e] as usize;
            if seen_at[w] != stamp
                && !on_path[w]
                && !t.start[w]
                && to_end[w] != u32::MAX
                && t.usable(g, e)
            {
                seen_at[w] = stamp;
                stack.push(w as u32);
            }
        }
    }
    None
}
