//! Maximum number of vertex-disjoint paths from a set of start nodes to a set of
//! end nodes in an undirected graph: a maximum flow with unit node capacities,
//! found by a round of depth-first searches that head for the end nodes, then
//! push–relabel for the paths they miss.
//!
//! Why not shortest augmenting paths alone (Dinic): in a bed the chains
//! are far longer than the shortest one (on a 2·10^5-sphere bed the shortest
//! path has 70 nodes and the last of ~2000 chains needs over 150), and
//! shortest-path methods climb through every length in between, one sweep of the
//! whole network per length. A depth-first search that heads for the far wall
//! takes whatever path it meets.
//!
//! The flow is kept as the paths themselves: `pred[v]` and `succ[v]` are the
//! neighbours before and after `v` on its path (`NONE` for a free node). The
//! residual network of the split-node flow network (inlet → outlet of capacity 1
//! per node) is implicit in them:
//! - from the inlet of a free node: its outlet; of a used node: back to the
//!   outlet of its predecessor (cancelling that arc of its path);
//! - from the outlet of any node: the inlet of every neighbour but its successor,
//!   the sink if it is an end node not yet ending a path, and for a used node its
//!   own inlet (cancelling its passage).
//!
//! One round of such searches, from every start node with marks that persist
//! through the round, costs one sweep of the network and finds most of the
//! paths (on a 2·10^5-sphere bed about 1200 of 2130). The paths it leaves out
//! would need many more rounds, each rerouting only a few paths, so the rest is
//! left to push–relabel ([`FlowNet`]) on the explicit split network, started from
//! the flow the round found. Push–relabel ends with a maximum flow, so the count
//! is exact whatever the round found.

use super::maxflow::FlowNet;

/// No node (a free node's `pred`/`succ`).
const NONE: u32 = u32::MAX;
/// The source, as the predecessor of a path's first node.
const SOURCE: u32 = u32::MAX - 1;
/// The sink, as the successor of a path's last node.
const SINK: u32 = u32::MAX - 2;

/// One state of the search: a node's inlet or outlet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    In,
    Out,
}

/// An undirected graph in compressed rows (`adj[row[u]..row[u + 1]]`), with
/// start and end flags.
#[derive(Clone, Copy)]
pub struct PathProblem<'a> {
    pub row: &'a [u32],
    pub adj: &'a [u32],
    pub start: &'a [bool],
    pub end: &'a [bool],
}

/// The maximum number of vertex-disjoint start-to-end paths (a node that is both
/// a start and an end node is a path on its own).
pub fn max_disjoint_paths(p: &PathProblem) -> u64 {
    let n = p.start.len();
    // Try neighbours nearest the end nodes first: the search then heads for the
    // far wall instead of wandering through the bed.
    let dist = distances(p);
    let mut adj = p.adj.to_vec();
    for v in 0..n {
        adj[p.row[v] as usize..p.row[v + 1] as usize].sort_by_key(|&w| (dist[w as usize], w));
    }
    let p = &PathProblem { adj: &adj, ..*p };
    let (pred, succ, greedy) = greedy_paths(p);
    // The rest by push–relabel on the split network, starting from these paths.
    let sink = 2 * n;
    let mut net = FlowNet::new(2 * n + 1);
    let mut sources = Vec::new();
    let mut carried = Vec::new();
    for v in 0..n {
        net.add(2 * v, 2 * v + 1);
        if p.start[v] && pred[v] != SOURCE {
            sources.push(2 * v);
        }
        if p.end[v] {
            net.add(2 * v + 1, sink);
        }
        for &w in &p.adj[p.row[v] as usize..p.row[v + 1] as usize] {
            net.add(2 * v + 1, 2 * w as usize);
        }
        if pred[v] != NONE {
            carried.push((2 * v, 2 * v + 1));
            match succ[v] {
                SINK => carried.push((2 * v + 1, sink)),
                w => carried.push((2 * v + 1, 2 * w as usize)),
            }
        }
    }
    net.max_flow_from(&sources, sink, &carried, greedy)
}

/// One round of depth-first searches from every start node, each heading for
/// the end nodes; a state any search of the round has seen is not entered
/// again, so the round costs one sweep of the network at most. Returns the paths
/// (`pred`, `succ`) and their number.
fn greedy_paths(p: &PathProblem) -> (Vec<u32>, Vec<u32>, u64) {
    let n = p.start.len();
    let mut pred = vec![NONE; n];
    let mut succ = vec![NONE; n];
    let mut mark = vec![false; 2 * n];
    // The stack of the search: (node, side, next choice to try).
    let mut stack: Vec<(u32, Side, u32)> = Vec::new();
    let mut flow = 0u64;
    for s in 0..n {
        if !p.start[s] || mark[2 * s] {
            continue;
        }
        mark[2 * s] = true;
        stack.clear();
        stack.push((s as u32, Side::In, 0));
        if search(p, &pred, &succ, &mut mark, &mut stack) {
            augment(&stack, &mut pred, &mut succ);
            flow += 1;
        }
    }
    (pred, succ, flow)
}

/// Hops from each node to the nearest end node (`u32::MAX`: none reachable).
fn distances(p: &PathProblem) -> Vec<u32> {
    let n = p.start.len();
    let mut dist = vec![u32::MAX; n];
    let mut queue: Vec<u32> = (0..n as u32).filter(|&v| p.end[v as usize]).collect();
    for &v in &queue {
        dist[v as usize] = 0;
    }
    let mut head = 0;
    while head < queue.len() {
        let v = queue[head] as usize;
        head += 1;
        for &w in &p.adj[p.row[v] as usize..p.row[v + 1] as usize] {
            if dist[w as usize] == u32::MAX {
                dist[w as usize] = dist[v] + 1;
                queue.push(w);
            }
        }
    }
    dist
}

/// Depth-first search from the state on top of `stack` to the sink; on success
/// the stack holds the path's states, the last an outlet of an end node.
fn search(
    p: &PathProblem,
    pred: &[u32],
    succ: &[u32],
    mark: &mut [bool],
    stack: &mut Vec<(u32, Side, u32)>,
) -> bool {
    let enter = |x: usize, mark: &mut [bool]| -> bool { !std::mem::replace(&mut mark[x], true) };
    while let Some(top) = stack.last_mut() {
        let (v, side, k) = *top;
        let vi = v as usize;
        top.2 += 1;
        match side {
            Side::In => {
                // One way on: forward through a free node, or back along a path.
                if k > 0 {
                    stack.pop();
                    continue;
                }
                if pred[vi] == NONE {
                    if enter(2 * vi + 1, mark) {
                        stack.push((v, Side::Out, 0));
                    }
                } else if pred[vi] != SOURCE {
                    let u = pred[vi] as usize;
                    if enter(2 * u + 1, mark) {
                        stack.push((u as u32, Side::Out, 0));
                    }
                }
            }
            Side::Out => {
                // Choice 0: the sink; 1..=deg: neighbours; deg + 1: own inlet.
                if k == 0 {
                    if p.end[vi] && succ[vi] != SINK {
                        return true;
                    }
                    continue;
                }
                let (lo, hi) = (p.row[vi], p.row[vi + 1]);
                let deg = hi - lo;
                if k <= deg {
                    let w = p.adj[(lo + k - 1) as usize];
                    if succ[vi] != w && enter(2 * w as usize, mark) {
                        stack.push((w, Side::In, 0));
                    }
                    continue;
                }
                if k == deg + 1 && pred[vi] != NONE && enter(2 * vi, mark) {
                    stack.push((v, Side::In, 0));
                    continue;
                }
                stack.pop();
            }
        }
    }
    false
}

/// Applies the augmenting path on `stack` to the paths.
fn augment(stack: &[(u32, Side, u32)], pred: &mut [u32], succ: &mut [u32]) {
    // Arcs are added and cancelled in path order. A cancel clears only an entry
    // that still holds the cancelled arc: an earlier step of the same path may
    // already have given it its new value.
    fn cancel(a: u32, b: u32, pred: &mut [u32], succ: &mut [u32]) {
        if succ[a as usize] == b {
            succ[a as usize] = NONE;
        }
        if pred[b as usize] == a {
            pred[b as usize] = NONE;
        }
    }
    pred[stack[0].0 as usize] = SOURCE;
    for w in stack.windows(2) {
        let ((a, sa, _), (b, sb, _)) = (w[0], w[1]);
        match (sa, sb) {
            // Forward through a free node (`a == b`): its arcs in and out say it.
            (Side::In, Side::Out) if a == b => {}
            // Back from an inlet along the path arc into it.
            (Side::In, Side::Out) => cancel(b, a, pred, succ),
            // Back through a used node: the next step cancels the arc into it.
            (Side::Out, Side::In) if a == b => {}
            // Out of a node into a neighbour: a new path arc.
            (Side::Out, Side::In) => {
                succ[a as usize] = b;
                pred[b as usize] = a;
            }
            _ => unreachable!("the search alternates inlets and outlets"),
        }
    }
    if let Some(&(last, _, _)) = stack.last() {
        succ[last as usize] = SINK;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn problem(n: usize, edges: &[(usize, usize)]) -> (Vec<u32>, Vec<u32>) {
        let mut lists = vec![Vec::new(); n];
        for &(a, b) in edges {
            if a != b {
                lists[a].push(b as u32);
                lists[b].push(a as u32);
            }
        }
        let mut row = vec![0u32];
        let mut adj = Vec::new();
        for mut l in lists {
            l.sort_unstable();
            l.dedup();
            adj.extend(l);
            row.push(adj.len() as u32);
        }
        (row, adj)
    }

    fn by_flow(n: usize, row: &[u32], adj: &[u32], start: &[bool], end: &[bool]) -> u64 {
        let mut net = FlowNet::new(2 * n + 1);
        let mut sources = Vec::new();
        for u in 0..n {
            net.add(2 * u, 2 * u + 1);
            if start[u] {
                sources.push(2 * u);
            }
            if end[u] {
                net.add(2 * u + 1, 2 * n);
            }
            for &v in &adj[row[u] as usize..row[u + 1] as usize] {
                net.add(2 * u + 1, 2 * v as usize);
            }
        }
        net.max_flow(&sources, 2 * n)
    }

    #[test]
    fn rerouting_through_a_used_node() {
        // Start 0 and 1, end 4 and 5. The greedy path 0-2-3-4 blocks 1 unless
        // it is rerouted: 0-2-5 and 1-3-4.
        let (row, adj) = problem(6, &[(0, 2), (2, 3), (3, 4), (1, 3), (2, 5)]);
        let start = [true, true, false, false, false, false];
        let end = [false, false, false, false, true, true];
        let p = PathProblem {
            row: &row,
            adj: &adj,
            start: &start,
            end: &end,
        };
        assert_eq!(max_disjoint_paths(&p), 2);
    }

    proptest! {
        #[test]
        fn agrees_with_push_relabel(
            n in 1usize..40,
            raw in prop::collection::vec((0usize..40, 0usize..40), 0..120),
            flags in prop::collection::vec((0u8..4, 0u8..4), 40),
        ) {
            let edges: Vec<(usize, usize)> =
                raw.into_iter().filter(|&(a, b)| a < n && b < n).collect();
            let (row, adj) = problem(n, &edges);
            let start: Vec<bool> = flags[..n].iter().map(|f| f.0 == 0).collect();
            let end: Vec<bool> = flags[..n].iter().map(|f| f.1 == 0).collect();
            let p = PathProblem { row: &row, adj: &adj, start: &start, end: &end };
            prop_assert_eq!(max_disjoint_paths(&p), by_flow(n, &row, &adj, &start, &end));
        }
    }
}
