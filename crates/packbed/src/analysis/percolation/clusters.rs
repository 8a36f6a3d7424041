//! Connected clusters of large bodies and which of them span the bed (walls)
//! or wrap around it (periodic sides).

use super::graph::{LinkGraph, Terminals};

/// Components, their sizes and their wrapping, from one breadth-first pass.
pub struct Clusters {
    /// Component of each node, numbered by lowest node.
    pub comp: Vec<u32>,
    /// Nodes per component.
    pub sizes: Vec<u64>,
    /// Per component, wraps around the box along x and y.
    pub wraps: Vec<[bool; 2]>,
}

/// Connected components of `g` and whether each wraps around the periodic box:
/// the search gives every node the image offset it is first reached with, and an
/// edge that reaches a node with a different offset closes a loop around the box.
pub fn clusters(g: &LinkGraph) -> Clusters {
    const UNSEEN: u32 = u32::MAX;
    let n = g.len();
    let mut comp = vec![UNSEEN; n];
    // Offsets of a few cells at most in any real bed; i64 arithmetic below
    // keeps even absurd inputs from overflowing.
    let mut at = vec![[0i64; 2]; n];
    let mut sizes = Vec::new();
    let mut wraps = Vec::new();
    let mut queue: Vec<u32> = Vec::with_capacity(n);
    for s in 0..n {
        if comp[s] != UNSEEN {
            continue;
        }
        let id = sizes.len() as u32;
        let mut wrap = [false; 2];
        queue.clear();
        comp[s] = id;
        queue.push(s as u32);
        let mut head = 0;
        while head < queue.len() {
            let u = queue[head] as usize;
            head += 1;
            let pu = at[u];
            for e in g.edges(u) {
                let v = g.adj[e] as usize;
                let o = g.offset[e];
                let pv = [pu[0] + i64::from(o[0]), pu[1] + i64::from(o[1])];
                if comp[v] == UNSEEN {
                    comp[v] = id;
                    at[v] = pv;
                    queue.push(v as u32);
                } else {
                    wrap[0] |= at[v][0] != pv[0];
                    wrap[1] |= at[v][1] != pv[1];
                }
            }
        }
        sizes.push(queue.len() as u64);
        wraps.push(wrap);
    }
    Clusters { comp, sizes, wraps }
}

/// Per cluster, whether it spans along horizontal axis `k`: it wraps around the
/// box (periodic), or holds both a start and an end body of `t` (walls).
pub fn spanning(found: &Clusters, t: &Terminals, periodic: bool, k: usize) -> Vec<bool> {
    if periodic {
        return found.wraps.iter().map(|w| w[k]).collect();
    }
    let mut has = vec![[false; 2]; found.sizes.len()];
    for (u, &c) in found.comp.iter().enumerate() {
        has[c as usize][0] |= t.start[u];
        has[c as usize][1] |= t.end[u];
    }
    has.iter().map(|h| h[0] && h[1]).collect()
}
