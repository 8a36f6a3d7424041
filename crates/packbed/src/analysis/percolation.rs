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

use super::contacts::Contacts;
use super::disjoint_paths::{max_disjoint_paths, PathProblem};
use super::StageTimes;
use crate::bed::Bed;
use crate::container::Wall;
use crate::math::Real;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{HashSet, VecDeque};

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

/// An undirected graph in compressed rows, each edge stored both ways with the
/// periodic image offset of the far node (`[0, 0]` with walls).
#[derive(Clone, Debug, Default)]
pub struct LinkGraph {
    /// `adj[row[u]..row[u + 1]]` are the neighbours of `u`.
    pub row: Vec<usize>,
    /// Neighbour node of each edge.
    pub adj: Vec<u32>,
    /// Image offset of the neighbour along the horizontal axes.
    pub offset: Vec<[i32; 2]>,
}

impl LinkGraph {
    /// A graph of `n` nodes from undirected edges `(u, v, offset of v seen from u)`.
    /// Each row is sorted by neighbour and offset, without repeats.
    pub fn from_edges(n: usize, edges: &[(u32, u32, [i32; 2])]) -> Self {
        // Bucketed by node (a counting sort), then each short row sorted on its
        // own: a sort of all 2m directed edges was most of the graph's cost on a
        // bed of 10^6 spheres.
        let looped = |&(u, v, o): &(u32, u32, [i32; 2])| u == v && o == [0, 0];
        let mut fill = vec![0usize; n + 1];
        for e in edges.iter().filter(|e| !looped(e)) {
            fill[e.0 as usize + 1] += 1;
            fill[e.1 as usize + 1] += 1;
        }
        for i in 0..n {
            fill[i + 1] += fill[i];
        }
        let bucket = fill.clone();
        let mut slots = vec![(0u32, [0i32; 2]); fill[n]];
        for &(u, v, o) in edges.iter().filter(|e| !looped(e)) {
            slots[fill[u as usize]] = (v, o);
            fill[u as usize] += 1;
            slots[fill[v as usize]] = (u, [-o[0], -o[1]]);
            fill[v as usize] += 1;
        }
        let mut row = Vec::with_capacity(n + 1);
        row.push(0usize);
        let mut adj = Vec::with_capacity(slots.len());
        let mut offset = Vec::with_capacity(slots.len());
        for u in 0..n {
            let list = &mut slots[bucket[u]..bucket[u + 1]];
            list.sort_unstable();
            let mut last = None;
            for &(v, o) in list.iter() {
                if last != Some((v, o)) {
                    adj.push(v);
                    offset.push(o);
                    last = Some((v, o));
                }
            }
            row.push(adj.len());
        }
        LinkGraph { row, adj, offset }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.row.len().saturating_sub(1)
    }

    /// True when the graph has no node.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Edge indices of node `u`.
    #[inline]
    fn edges(&self, u: usize) -> std::ops::Range<usize> {
        self.row[u]..self.row[u + 1]
    }
}

/// The chain problem along one axis: which nodes may start and end a chain, and
/// which edges a chain may use.
#[derive(Clone, Debug)]
pub struct Terminals {
    /// Nodes touching the low wall (or the seam from the right).
    pub start: Vec<bool>,
    /// Nodes touching the high wall (or the seam from the left).
    pub end: Vec<bool>,
    /// Axis whose seam edges are cut (periodic), `None` with walls.
    pub seam: Option<usize>,
}

impl Terminals {
    #[inline]
    fn usable(&self, g: &LinkGraph, e: usize) -> bool {
        self.seam.is_none_or(|k| g.offset[e][k] == 0)
    }
}

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

/// The graph of large bodies of `bed` and, per node, its particles' body id.
pub struct LargeGraph {
    /// The contact graph of large bodies.
    pub graph: LinkGraph,
    /// For each particle, its node (`u32::MAX`: not large).
    pub node_of: Vec<u32>,
    /// Radius threshold in use.
    pub large_radius: Real,
}

/// Builds the graph of large bodies from the contacts of `bed`.
pub fn large_graph<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    large: LargeRule,
) -> LargeGraph {
    let n = bed.len();
    let (is_large, large_radius) = large_particles(bed, large);
    // Dense node ids for large bodies, in order of first appearance.
    let max_body = bed.bodies.iter().max().map_or(0, |&b| b as usize);
    let dense = max_body <= 4 * n + 1024;
    let mut body_node: Vec<u32> = if dense {
        vec![u32::MAX; max_body + 1]
    } else {
        Vec::new()
    };
    let mut sorted: Vec<u32> = Vec::new();
    if !dense {
        sorted = (0..n)
            .filter(|&i| is_large[i])
            .map(|i| bed.bodies[i])
            .collect();
        sorted.sort_unstable();
        sorted.dedup();
    }
    // A body is large when any of its beads is.
    let mut large_body = vec![false; if dense { max_body + 1 } else { 0 }];
    if dense {
        for i in 0..n {
            if is_large[i] {
                large_body[bed.bodies[i] as usize] = true;
            }
        }
    }
    let mut nodes = 0u32;
    let mut node_of = vec![u32::MAX; n];
    let mut first_bead: Vec<u32> = Vec::new();
    for i in 0..n {
        let b = bed.bodies[i];
        let id = if dense {
            if !large_body[b as usize] {
                continue;
            }
            let slot = &mut body_node[b as usize];
            if *slot == u32::MAX {
                *slot = nodes;
                nodes += 1;
                first_bead.push(i as u32);
            }
            *slot
        } else {
            match sorted.binary_search(&b) {
                Ok(k) => k as u32,
                Err(_) => continue,
            }
        };
        node_of[i] = id;
    }
    if !dense {
        nodes = sorted.len() as u32;
        first_bead = vec![u32::MAX; sorted.len()];
        for i in 0..n {
            let u = node_of[i];
            if u != u32::MAX && first_bead[u as usize] == u32::MAX {
                first_bead[u as usize] = i as u32;
            }
        }
    }
    spatial_order(bed, &mut node_of, &mut first_bead);
    // Offset of each bead's image that lies next to its body's first bead, so that
    // a body stored wrapped across the seam still has one frame.
    let periodic = bed.container.periodic;
    let size = bed.container.size;
    let image = |from: usize, to: usize| -> [i32; 2] {
        let mut o = [0i32; 2];
        if periodic {
            let d = bed
                .container
                .displacement(&bed.centres[from], &bed.centres[to]);
            for k in 0..D - 1 {
                let shift = bed.centres[from][k] + d[k] - bed.centres[to][k];
                o[k] = (shift / size[k]).round() as i32;
            }
        }
        o
    };
    let bead_offset: Vec<[i32; 2]> = (0..n)
        .into_par_iter()
        .map(|i| {
            let u = node_of[i];
            if !periodic || u == u32::MAX {
                [0, 0]
            } else {
                image(first_bead[u as usize] as usize, i)
            }
        })
        .collect();
    let edges: Vec<(u32, u32, [i32; 2])> = contacts
        .pairs
        .par_iter()
        .filter_map(|c| {
            let (i, j) = (c.i as usize, c.j as usize);
            if i >= n || j >= n {
                return None;
            }
            let (u, v) = (node_of[i], node_of[j]);
            if u == u32::MAX || v == u32::MAX || u == v {
                return None;
            }
            let k = image(i, j);
            let (oi, oj) = (bead_offset[i], bead_offset[j]);
            Some((u, v, [k[0] + oi[0] - oj[0], k[1] + oi[1] - oj[1]]))
        })
        .collect();
    LargeGraph {
        graph: LinkGraph::from_edges(nodes as usize, &edges),
        node_of,
        large_radius,
    }
}

/// Renumbers the nodes in the order of the cells (two large radii wide, rows
/// along x, then y, then height) holding their first beads. Graph searches then
/// walk memory nearly in sequence instead of jumping across the whole bed with
/// every step, which on a bed of 10^6 particles is most of their time.
fn spatial_order<const D: usize>(bed: &Bed<D>, node_of: &mut [u32], first_bead: &mut [u32]) {
    let nodes = first_bead.len();
    let cell = first_bead
        .iter()
        .map(|&i| bed.radii[i as usize])
        .fold(0.0, Real::max)
        * 2.0;
    if nodes < 2 || cell.is_nan() || cell <= 0.0 || !cell.is_finite() {
        return;
    }
    let lo: [Real; D] = std::array::from_fn(|k| {
        first_bead
            .iter()
            .map(|&i| bed.centres[i as usize][k])
            .fold(Real::INFINITY, Real::min)
    });
    let key = |i: u32| -> u64 {
        let c = &bed.centres[i as usize];
        (0..D).rev().fold(0u64, |acc, k| {
            // 2^20 cells per axis at most; beyond that order is only coarser.
            let x = ((c[k] - lo[k]) / cell).clamp(0.0, (1 << 20) as Real - 1.0) as u64;
            (acc << 21) | x
        })
    };
    let mut order: Vec<(u64, u32)> = (0..nodes as u32)
        .map(|u| (key(first_bead[u as usize]), u))
        .collect();
    order.par_sort_unstable();
    let mut rank = vec![0u32; nodes];
    let old = first_bead.to_vec();
    for (k, &(_, u)) in order.iter().enumerate() {
        rank[u as usize] = k as u32;
        first_bead[k] = old[u as usize];
    }
    for u in node_of.iter_mut() {
        if *u != u32::MAX {
            *u = rank[*u as usize];
        }
    }
}

/// Which particles are large, and the radius threshold that means.
fn large_particles<const D: usize>(bed: &Bed<D>, rule: LargeRule) -> (Vec<bool>, Real) {
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

/// The chain problem along horizontal axis `k`.
pub fn terminals<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    lg: &LargeGraph,
    k: usize,
) -> Terminals {
    let n = lg.graph.len();
    let mut t = Terminals {
        start: vec![false; n],
        end: vec![false; n],
        seam: None,
    };
    if bed.container.periodic {
        t.seam = Some(k);
        let g = &lg.graph;
        for u in 0..n {
            for e in g.edges(u) {
                let o = g.offset[e][k];
                if o > 0 {
                    t.end[u] = true;
                } else if o < 0 {
                    t.start[u] = true;
                }
            }
        }
    } else {
        for w in &contacts.walls {
            let Some(&u) = lg.node_of.get(w.i as usize) else {
                continue;
            };
            if u == u32::MAX {
                continue;
            }
            match w.wall {
                Wall::Low(a) if a == k => t.start[u as usize] = true,
                Wall::High(a) if a == k => t.end[u as usize] = true,
                _ => {}
            }
        }
    }
    t
}

fn length_stats(chains: &[Vec<u32>]) -> Option<LengthStats> {
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
    let Clusters { comp, sizes, wraps } = times.time("percolation/clusters", || clusters(g));
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
        let mut spanning = vec![false; sizes.len()];
        if periodic {
            for (c, w) in wraps.iter().enumerate() {
                spanning[c] = w[k];
            }
        } else {
            // A cluster spans when it holds both a start and an end node.
            let mut has = vec![[false; 2]; sizes.len()];
            for u in 0..g.len() {
                let c = comp[u] as usize;
                has[c][0] |= t.start[u];
                has[c][1] |= t.end[u];
            }
            for c in 0..sizes.len() {
                spanning[c] = has[c][0] && has[c][1];
            }
        }
        for c in 0..sizes.len() {
            spanning_any[c] |= spanning[c];
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
        let spanning_clusters = spanning.iter().filter(|&&s| s).count() as u64;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::find_contacts;
    use crate::container::Container;
    use crate::math::Vector;
    use proptest::prelude::*;

    fn bed2(size: [Real; 2], periodic: bool, discs: &[(Real, Real, Real, u32)]) -> Bed<2> {
        let mut bed = Bed::new(
            Container {
                size: Vector(size),
                periodic,
            },
            Vec::new(),
        );
        for &(x, y, r, s) in discs {
            bed.push(Vector([x, y]), r, s);
        }
        bed
    }

    fn run<const D: usize>(bed: &Bed<D>) -> Percolation {
        let c = find_contacts(bed, 1e-9);
        percolation(bed, &c, &PercolationOptions::default())
    }

    #[test]
    fn row_of_large_discs_from_wall_to_wall() {
        // Four large discs spanning x, a small disc on top (species 1, not large).
        let bed = bed2(
            [8.0, 10.0],
            false,
            &[
                (1.0, 1.0, 1.0, 0),
                (3.0, 1.0, 1.0, 0),
                (5.0, 1.0, 1.0, 0),
                (7.0, 1.0, 1.0, 0),
                (4.0, 1.0 + (1.5f64 * 1.5 - 1.0).sqrt(), 0.5, 1),
            ],
        );
        let p = run(&bed);
        assert_eq!(p.large_bodies, 4);
        assert_eq!(p.large_radius, 1.0);
        assert_eq!(p.criterion, "walls");
        assert!(p.spans);
        assert_eq!(p.spanning_clusters, 1);
        assert_eq!(p.shortest_chain, Some(4));
        assert_eq!(p.disjoint_chains, 1);
        assert_eq!(p.unique_chains, 1);
        assert_eq!(
            p.chain_length,
            Some(LengthStats {
                min: 4,
                mean: 4.0,
                max: 4
            })
        );
        assert!(!p.cap_hit);
        // A gap breaks it.
        let mut broken = bed.clone();
        broken.centres[3][0] = 6.9;
        broken.container.size[0] = 7.9;
        broken.centres[2][0] = 4.8;
        let q = run(&broken);
        assert!(!q.spans);
        assert_eq!(q.spanning_clusters, 0);
        assert_eq!(q.shortest_chain, None);
        assert_eq!(q.unique_chains, 0);
        assert_eq!(q.clusters, 2);
        // A radius threshold that makes the small disc large too: it bridges
        // discs 1 and 2, giving a second chain through the same end discs.
        let c = find_contacts(&bed, 1e-9);
        let opts = PercolationOptions {
            large: LargeRule::Radius(0.5),
            ..Default::default()
        };
        let r = percolation(&bed, &c, &opts);
        assert_eq!(r.large_bodies, 5);
        assert_eq!(r.unique_chains, 2);
        assert_eq!(r.shortest_chain, Some(4));
        assert_eq!(r.disjoint_chains, 1);
        assert_eq!(r.chain_length.unwrap().max, 5);
    }

    #[test]
    fn two_chains_sharing_particles() {
        // A diamond A–B–D, A–C–D: A touches x0, D touches x1; B and C do not touch.
        let s = 2f64.sqrt();
        let w = 2.0 + 2.0 * s;
        let bed = bed2(
            [w, 10.0],
            false,
            &[
                (1.0, 3.0, 1.0, 0),
                (1.0 + s, 3.0 + s, 1.0, 0),
                (1.0 + s, 3.0 - s, 1.0, 0),
                (1.0 + 2.0 * s, 3.0, 1.0, 0),
            ],
        );
        let p = run(&bed);
        assert_eq!(p.unique_chains, 2);
        assert_eq!(p.disjoint_chains, 1);
        assert_eq!(p.shortest_chain, Some(3));
        assert_eq!(p.spanning_clusters, 1);
        let c = find_contacts(&bed, 1e-9);
        let lg = large_graph(&bed, &c, LargeRule::Median);
        let t = terminals(&bed, &c, &lg, 0);
        let e = unique_chains(&lg.graph, &t, 400, 250, u64::MAX);
        // As particle sets (node ids follow the cells, not the input order).
        let particle = |u: u32| lg.node_of.iter().position(|&x| x == u).unwrap();
        let mut sets: Vec<Vec<usize>> = e
            .chains
            .iter()
            .map(|c| {
                let mut v: Vec<usize> = c.iter().map(|&u| particle(u)).collect();
                v.sort_unstable();
                v
            })
            .collect();
        sets.sort();
        assert_eq!(sets, vec![vec![0, 1, 3], vec![0, 2, 3]]);
        // Caps: one chain only, or chains of at most 2 particles.
        let e = unique_chains(&lg.graph, &t, 1, 250, u64::MAX);
        assert_eq!(e.chains.len(), 1);
        assert!(e.chain_cap_hit);
        let e = unique_chains(&lg.graph, &t, 400, 2, u64::MAX);
        assert!(e.chains.is_empty() && e.length_cap_hit);
        let e = unique_chains(&lg.graph, &t, 400, 250, 2);
        assert!(e.search_cap_hit);
    }

    #[test]
    fn periodic_cluster_that_wraps() {
        // Four discs in a row round a periodic box of width 8: the last touches the
        // first across the seam.
        let row = [
            (1.0, 1.0, 1.0, 0),
            (3.0, 1.0, 1.0, 0),
            (5.0, 1.0, 1.0, 0),
            (7.0, 1.0, 1.0, 0),
        ];
        let p = run(&bed2([8.0, 10.0], true, &row));
        assert_eq!(p.criterion, "wraps");
        assert!(p.spans);
        assert_eq!(p.spanning_clusters, 1);
        // Across the cell from the seam to the seam: the whole row.
        assert_eq!(p.shortest_chain, Some(4));
        assert_eq!(p.unique_chains, 1);
        assert_eq!(p.disjoint_chains, 1);
        // Three of them cross the seam but do not wrap.
        let p = run(&bed2([8.0, 10.0], true, &[row[0], row[2], row[3]]));
        assert!(!p.spans);
        assert_eq!(p.spanning_clusters, 0);
        assert_eq!(p.clusters, 1);
        // Stored wrapped or not, a chain body crossing the seam is one frame:
        // two 2-bead bodies making a loop round a box of width 8.
        let mut bed = bed2([8.0, 10.0], true, &[]);
        bed.push_bead(Vector([7.0, 1.0]), 1.0, 0, 0);
        bed.push_bead(Vector([1.0, 1.0]), 1.0, 0, 0);
        bed.push_bead(Vector([3.0, 1.0]), 1.0, 0, 1);
        bed.push_bead(Vector([5.0, 1.0]), 1.0, 0, 1);
        let p = run(&bed);
        assert_eq!(p.large_bodies, 2);
        assert!(p.spans);
    }

    #[test]
    fn periodic_3d_wraps_along_y_only() {
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 6.0, 10.0]),
                periodic: true,
            },
            Vec::new(),
        );
        for k in 0..3 {
            bed.push(Vector([5.0, 1.0 + 2.0 * k as Real, 1.0]), 1.0, 0);
        }
        let p = run(&bed);
        assert!(p.spans);
        assert!(!p.directions[0].spans);
        assert!(p.directions[1].spans);
        assert_eq!(p.directions[1].axis, "y");
        assert_eq!(p.directions[1].shortest_chain, Some(3));
        assert_eq!(p.shortest_chain, Some(3));
    }

    #[test]
    fn walled_3d_row_along_y() {
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 6.0, 10.0]),
                periodic: false,
            },
            Vec::new(),
        );
        for k in 0..3 {
            bed.push(Vector([5.0, 1.0 + 2.0 * k as Real, 1.0]), 1.0, 0);
        }
        let p = run(&bed);
        assert!(!p.directions[0].spans && p.directions[1].spans);
        assert_eq!(p.unique_chains, 1);
        assert_eq!(p.disjoint_chains, 1);
    }

    /// Every chain by plain recursion over simple paths.
    fn brute_chains(g: &LinkGraph, t: &Terminals) -> Vec<Vec<u32>> {
        fn go(
            g: &LinkGraph,
            t: &Terminals,
            path: &mut Vec<u32>,
            out: &mut std::collections::BTreeSet<Vec<u32>>,
        ) {
            let u = *path.last().unwrap() as usize;
            if t.end[u] {
                let mut s = path.clone();
                s.sort_unstable();
                out.insert(s);
                return;
            }
            for e in g.edges(u) {
                let v = g.adj[e];
                if path.contains(&v) || !t.usable(g, e) || t.start[v as usize] {
                    continue;
                }
                path.push(v);
                go(g, t, path, out);
                path.pop();
            }
        }
        let mut out = std::collections::BTreeSet::new();
        for s in 0..g.len() {
            if t.start[s] {
                go(g, t, &mut vec![s as u32], &mut out);
            }
        }
        out.into_iter().collect()
    }

    /// Most chains with no node in common, by exhaustive search.
    fn brute_disjoint(chains: &[Vec<u32>], used: &mut Vec<u32>, from: usize) -> u64 {
        let mut best = 0;
        for k in from..chains.len() {
            if chains[k].iter().any(|v| used.contains(v)) {
                continue;
            }
            let before = used.len();
            used.extend(&chains[k]);
            best = best.max(1 + brute_disjoint(chains, used, k + 1));
            used.truncate(before);
        }
        best
    }

    /// Wrapping by searching the lifted graph (node, offset) with bounded offsets.
    fn brute_wraps(g: &LinkGraph, comp: &[u32], ncomp: usize) -> Vec<[bool; 2]> {
        let n = g.len() as i32;
        let mut out = vec![[false; 2]; ncomp];
        for s in 0..g.len() {
            let mut seen = std::collections::HashSet::new();
            let mut stack = vec![(s, [0i32, 0i32])];
            seen.insert((s, [0, 0]));
            while let Some((u, o)) = stack.pop() {
                if u == s && o != [0, 0] {
                    for k in 0..2 {
                        out[comp[s] as usize][k] |= o[k] != 0;
                    }
                }
                for e in g.edges(u) {
                    let q = [o[0] + g.offset[e][0], o[1] + g.offset[e][1]];
                    if q[0].abs() > n || q[1].abs() > n {
                        continue;
                    }
                    let v = g.adj[e] as usize;
                    if seen.insert((v, q)) {
                        stack.push((v, q));
                    }
                }
            }
        }
        out
    }

    proptest! {
        #[test]
        fn algorithms_agree_with_brute_force_on_small_graphs(
            n in 1usize..9,
            raw in prop::collection::vec((0u32..9, 0u32..9, -1i32..2, -1i32..2), 0..16),
            flags in prop::collection::vec((any::<bool>(), any::<bool>()), 9),
            seam in any::<bool>(),
        ) {
            let edges: Vec<(u32, u32, [i32; 2])> = raw
                .iter()
                .filter(|e| (e.0 as usize) < n && (e.1 as usize) < n)
                .map(|e| (e.0, e.1, if seam { [e.2, e.3] } else { [0, 0] }))
                .collect();
            let g = LinkGraph::from_edges(n, &edges);
            // Rows as the plain definition: both directions, sorted, no repeats.
            let mut both: Vec<(u32, u32, [i32; 2])> = edges
                .iter()
                .filter(|e| !(e.0 == e.1 && e.2 == [0, 0]))
                .flat_map(|&(u, v, o)| [(u, v, o), (v, u, [-o[0], -o[1]])])
                .collect();
            both.sort_unstable();
            both.dedup();
            let rows: Vec<(u32, u32, [i32; 2])> = (0..n)
                .flat_map(|u| g.edges(u).map(move |e| (u as u32, e)))
                .map(|(u, e)| (u, g.adj[e], g.offset[e]))
                .collect();
            prop_assert_eq!(rows, both);
            let t = Terminals {
                start: flags[..n].iter().map(|f| f.0).collect(),
                end: flags[..n].iter().map(|f| f.1 && !(f.0 && seam)).collect(),
                seam: seam.then_some(0),
            };
            let chains = brute_chains(&g, &t);
            let en = unique_chains(&g, &t, 10_000, 250, u64::MAX);
            let mut got = en.chains.clone();
            got.sort();
            prop_assert_eq!(&got, &chains);
            prop_assert_eq!(shortest_chain(&g, &t), chains.iter().map(|c| c.len() as u64).min());
            prop_assert_eq!(disjoint_chains(&g, &t), brute_disjoint(&chains, &mut Vec::new(), 0));
            let c = clusters(&g);
            prop_assert_eq!(c.wraps, brute_wraps(&g, &c.comp, c.sizes.len()));
        }
    }
}
