//! The elimination order of the stiffness matrix: nested dissection of the
//! body graph, by coordinate bisection in 2D and by METIS's multilevel
//! bisection in 3D.
//!
//! A bed's bond network is a geometric graph (bonds join touching bodies), so
//! cutting it at the median of one axis (of the axis whose cut needs the
//! smallest separator) splits it in halves joined only through a thin layer
//! of bodies, and a minimum vertex cover of the bonds across the cut (König)
//! is the thinnest such layer; ordering both halves first (each in the
//! same way) and that layer last keeps the Cholesky factor's fill near the
//! optimum for planar and spatial meshes (George 1973; Lipton, Rose & Tarjan
//! 1979). Measured on periodic beds of equal spheres it roughly halves the
//! factor of the approximate minimum degree order of the whole matrix and
//! orders 10⁵ bodies in a fraction of the time (docs/history/benchmarks.md,
//! "Contact forces and breakage"). The order is on bodies; each body's
//! unknowns stay together, which the supernodal factorisation turns into
//! dense blocks.
//!
//! In 3D the factor's work grows as the square of the bodies and its top
//! separators are dense blocks thousands of unknowns wide, so a few percent
//! off a separator is worth far more than the ordering's own time. There
//! METIS's multilevel nested dissection (Karypis & Kumar 1998: coarsening by
//! matchings, separators refined by Fiduccia–Mattheyses moves, the best of
//! `SEPARATOR_TRIALS` at each level) finds separators a flat cut cannot:
//! on the 3D benchmark bed (2·10⁴ spheres) it needs 20 % fewer flops than
//! coordinate bisection (3.50·10¹¹ against 4.37·10¹¹) for 0.3 s of ordering.
//! In 2D the factor is cheap (10⁵ discs: 3.6·10⁹ flops) and METIS's 0.5–1 s
//! would cost more than its 13 % fewer flops save, so 2D keeps the flat cut.

use crate::math::Vector;

/// Subgraphs at most this large are ordered as they come.
const LEAF: usize = 32;

/// Separators METIS tries at each level, keeping the smallest (its
/// `NSEPS`; 1 by default). Measured on the 3D benchmark bed: 1 gives
/// 3.74·10¹¹ flops, 3 gives 3.50·10¹¹, 5 and 10 no better than 3.
const SEPARATOR_TRIALS: i32 = 3;

/// The bodies in elimination order for a bed in `D` dimensions: multilevel
/// nested dissection in 3D, coordinate bisection in 2D (see the module
/// comment) and wherever METIS cannot take the graph.
pub fn elimination_order<const D: usize>(
    points: &[Vector<D>],
    offsets: &[usize],
    neighbours: &[u32],
) -> Vec<u32> {
    if D == 3 {
        if let Some(order) = multilevel_dissection(offsets, neighbours) {
            return order;
        }
    }
    nested_dissection(points, offsets, neighbours)
}

/// METIS's nested dissection of the graph (`offsets`/`neighbours` in
/// compressed rows; self-loops and repeated bonds are dropped, as METIS asks),
/// or `None` when the graph is too large for its 32-bit indices or METIS
/// reports an error.
pub fn multilevel_dissection(offsets: &[usize], neighbours: &[u32]) -> Option<Vec<u32>> {
    use std::sync::Mutex;
    // METIS draws its random numbers from one global generator that each call
    // reseeds: two calls at once (beds of an ensemble on separate threads)
    // would draw from each other's sequence and lose determinism.
    static METIS: Mutex<()> = Mutex::new(());
    let n = offsets.len().checked_sub(1)?;
    if n == 0 {
        return Some(Vec::new());
    }
    let mut xadj: Vec<i32> = Vec::with_capacity(n + 1);
    let mut adjncy: Vec<i32> = Vec::with_capacity(neighbours.len());
    xadj.push(0);
    let mut row: Vec<u32> = Vec::new();
    for v in 0..n {
        row.clear();
        row.extend(
            neighbours[offsets[v]..offsets[v + 1]]
                .iter()
                .filter(|&&u| u as usize != v),
        );
        row.sort_unstable();
        row.dedup();
        for &u in &row {
            adjncy.push(i32::try_from(u).ok()?);
        }
        xadj.push(i32::try_from(adjncy.len()).ok()?);
    }
    let mut nvtxs = i32::try_from(n).ok()?;
    let mut options = [0; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0i32; n];
    let mut iperm = vec![0i32; n];
    let guard = METIS.lock().unwrap_or_else(|e| e.into_inner());
    // SAFETY: `options` has METIS_NOPTIONS entries; `xadj` has n + 1 entries
    // and `adjncy` the xadj[n] neighbours they index, all below n; `perm` and
    // `iperm` have n entries; a null `vwgt` means unit weights. METIS reads the
    // graph, writes only `perm` and `iperm`, and keeps no pointer.
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        options[metis_sys::moptions_et_METIS_OPTION_SEED as usize] = 0;
        options[metis_sys::moptions_et_METIS_OPTION_NSEPS as usize] = SEPARATOR_TRIALS;
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    drop(guard);
    if status != metis_sys::rstatus_et_METIS_OK {
        return None;
    }
    // `perm[new] = old`; refuse anything but a permutation.
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for &v in &perm {
        let v = usize::try_from(v).ok().filter(|&v| v < n && !seen[v])?;
        seen[v] = true;
        order.push(v as u32);
    }
    Some(order)
}

/// The bodies in elimination order, given each body's position and its
/// neighbours (`offsets`/`neighbours` in compressed rows).
pub fn nested_dissection<const D: usize>(
    points: &[Vector<D>],
    offsets: &[usize],
    neighbours: &[u32],
) -> Vec<u32> {
    let n = points.len();
    let mut label = vec![0u32; n];
    let mut next_label = 1u32;
    let mut order = Vec::with_capacity(n);
    let nodes: Vec<u32> = (0..n as u32).collect();
    // Depth first with an explicit stack: (nodes, separator to emit after them).
    enum Task {
        Split(Vec<u32>),
        Emit(Vec<u32>),
    }
    let mut stack = vec![Task::Split(nodes)];
    while let Some(task) = stack.pop() {
        let nodes = match task {
            Task::Emit(sep) => {
                order.extend(sep);
                continue;
            }
            Task::Split(nodes) => nodes,
        };
        if nodes.len() <= LEAF {
            order.extend(nodes);
            continue;
        }
        // Each axis cut at its median; the one with the smallest separator
        // wins (the first axis on a tie). The longest extent is not always
        // it: across a periodic side a cut needs a second plane at the seam,
        // so a thick periodic slab is best cut first through its height.
        let mut best: Option<Cut> = None;
        for axis in 0..D {
            let cut = Cut::new(
                points,
                offsets,
                neighbours,
                &nodes,
                axis,
                &mut label,
                &mut next_label,
            );
            if best.as_ref().is_none_or(|b| cut.sep.len() < b.sep.len()) {
                best = Some(cut);
            }
        }
        let Cut {
            nodes,
            sep,
            keep_low,
            keep_high,
        } = best.expect("D >= 1 axes");
        let half = nodes.len() / 2;
        let (low, high) = nodes.split_at(half);
        for &v in &sep {
            label[v as usize] = u32::MAX;
        }
        let rest = |part: &[u32], whole: bool, label: &[u32]| -> Vec<u32> {
            if whole {
                part.to_vec()
            } else {
                part.iter()
                    .copied()
                    .filter(|&v| label[v as usize] != u32::MAX)
                    .collect()
            }
        };
        let a = rest(low, keep_low, &label);
        let b = rest(high, keep_high, &label);
        stack.push(Task::Emit(sep));
        stack.push(Task::Split(b));
        stack.push(Task::Split(a));
    }
    order
}

/// One bisection: `nodes` split at the median of `axis` (the low half first),
/// and a smallest set of nodes that covers every bond between the halves.
struct Cut {
    nodes: Vec<u32>,
    sep: Vec<u32>,
    /// Whether a half is kept whole (no separator node came from it).
    keep_low: bool,
    keep_high: bool,
}

impl Cut {
    fn new<const D: usize>(
        points: &[Vector<D>],
        offsets: &[usize],
        neighbours: &[u32],
        nodes: &[u32],
        axis: usize,
        label: &mut [u32],
        next_label: &mut u32,
    ) -> Cut {
        let mut nodes = nodes.to_vec();
        let half = nodes.len() / 2;
        nodes.select_nth_unstable_by(half, |&a, &b| {
            points[a as usize][axis]
                .total_cmp(&points[b as usize][axis])
                .then(a.cmp(&b))
        });
        let (low, high) = nodes.split_at(half);
        let (la, lb) = (*next_label, *next_label + 1);
        *next_label += 2;
        for &v in low {
            label[v as usize] = la;
        }
        for &v in high {
            label[v as usize] = lb;
        }
        let touches = |v: u32, other: u32| {
            let v = v as usize;
            neighbours[offsets[v]..offsets[v + 1]]
                .iter()
                .any(|&u| label[u as usize] == other)
        };
        let sep_high: Vec<u32> = high.iter().copied().filter(|&v| touches(v, la)).collect();
        let sep_low: Vec<u32> = low.iter().copied().filter(|&v| touches(v, lb)).collect();
        let sep = min_vertex_cover(&sep_low, &sep_high, offsets, neighbours, label, lb);
        let keep_low = !sep.iter().any(|&v| label[v as usize] == la);
        let keep_high = !sep.iter().any(|&v| label[v as usize] == lb);
        Cut {
            nodes,
            sep,
            keep_low,
            keep_high,
        }
    }
}

/// A minimum vertex cover of the bonds between `low` and `high` (the nodes of
/// each half touching the other; `label[v] == high_label` marks the high
/// half): a maximum matching by augmenting paths, then König's construction.
/// It is never larger than either one-sided separator and often smaller: it
/// takes from each side the bodies that carry the most crossing bonds.
fn min_vertex_cover(
    low: &[u32],
    high: &[u32],
    offsets: &[usize],
    neighbours: &[u32],
    label: &[u32],
    high_label: u32,
) -> Vec<u32> {
    use std::collections::HashMap;
    let high_index: HashMap<u32, usize> = high.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    let adj: Vec<Vec<usize>> = low
        .iter()
        .map(|&v| {
            let v = v as usize;
            neighbours[offsets[v]..offsets[v + 1]]
                .iter()
                .filter(|&&u| label[u as usize] == high_label)
                .filter_map(|u| high_index.get(u).copied())
                .collect()
        })
        .collect();
    let mut match_low = vec![usize::MAX; low.len()];
    let mut match_high = vec![usize::MAX; high.len()];
    // Augmenting paths (Kuhn), iterative; greedy first.
    for a in 0..low.len() {
        if let Some(&b) = adj[a].iter().find(|&&b| match_high[b] == usize::MAX) {
            match_low[a] = b;
            match_high[b] = a;
        }
    }
    let mut seen = vec![0usize; high.len()];
    let mut round = 0;
    for a0 in 0..low.len() {
        if match_low[a0] != usize::MAX {
            continue;
        }
        round += 1;
        // Depth-first search over alternating paths: (low node, next edge).
        let mut stack: Vec<(usize, usize)> = vec![(a0, 0)];
        let mut via: Vec<usize> = Vec::new();
        while let Some(&mut (a, ref mut e)) = stack.last_mut() {
            if *e >= adj[a].len() {
                stack.pop();
                via.pop();
                continue;
            }
            let b = adj[a][*e];
            *e += 1;
            if seen[b] == round {
                continue;
            }
            seen[b] = round;
            via.push(b);
            if match_high[b] == usize::MAX {
                // Flip the path: stack[k].0 takes via[k].
                for (k, &(a, _)) in stack.iter().enumerate() {
                    let b = via[k];
                    match_low[a] = b;
                    match_high[b] = a;
                }
                break;
            }
            stack.push((match_high[b], 0));
        }
    }
    // König: Z = what alternating paths reach from unmatched low nodes;
    // the cover is (low ∖ Z) ∪ (high ∩ Z).
    let mut z_low = vec![false; low.len()];
    let mut z_high = vec![false; high.len()];
    let mut queue: Vec<usize> = (0..low.len())
        .filter(|&a| match_low[a] == usize::MAX)
        .collect();
    for &a in &queue {
        z_low[a] = true;
    }
    while let Some(a) = queue.pop() {
        for &b in &adj[a] {
            if !z_high[b] {
                z_high[b] = true;
                let next = match_high[b];
                if next != usize::MAX && !z_low[next] {
                    z_low[next] = true;
                    queue.push(next);
                }
            }
        }
    }
    let mut cover: Vec<u32> = low
        .iter()
        .zip(&z_low)
        .filter(|(_, z)| !**z)
        .map(|(&v, _)| v)
        .collect();
    cover.extend(
        high.iter()
            .zip(&z_high)
            .filter(|(_, z)| **z)
            .map(|(&v, _)| v),
    );
    cover
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Real;

    #[test]
    fn a_grid_is_ordered_once_each_with_the_middle_column_last() {
        // A 40 × 40 grid graph.
        let w = 40usize;
        let (points, offsets, neighbours) = grid::<2>(w);
        let order = nested_dissection(&points, &offsets, &neighbours);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..(w * w) as u32).collect::<Vec<_>>());
        // The top separator is one grid line of 40 nodes, eliminated last.
        let last: Vec<u32> = order[order.len() - w..].to_vec();
        let xs: std::collections::BTreeSet<usize> = last.iter().map(|&k| k as usize % w).collect();
        let ys: std::collections::BTreeSet<usize> = last.iter().map(|&k| k as usize / w).collect();
        assert!(xs.len() == 1 || ys.len() == 1, "{xs:?} {ys:?}");
    }

    /// A grid graph of `w` nodes a side in `D` dimensions (each node joined
    /// to its axis neighbours), x fastest, in compressed rows.
    fn grid<const D: usize>(w: usize) -> (Vec<Vector<D>>, Vec<usize>, Vec<u32>) {
        let n = w.pow(D as u32);
        let mut points = Vec::with_capacity(n);
        let mut offsets = vec![0];
        let mut neighbours = Vec::new();
        for k in 0..n {
            let mut at = [0usize; D];
            let mut rest = k;
            for a in &mut at {
                *a = rest % w;
                rest /= w;
            }
            points.push(Vector(at.map(|a| a as Real)));
            let mut stride = 1;
            for a in at {
                if a > 0 {
                    neighbours.push((k - stride) as u32);
                }
                if a + 1 < w {
                    neighbours.push((k + stride) as u32);
                }
                stride *= w;
            }
            offsets.push(neighbours.len());
        }
        (points, offsets, neighbours)
    }

    /// The entries of the Cholesky factor for the elimination `order`, by
    /// eliminating the graph node by node (bit sets), independent of any
    /// symbolic analysis.
    fn factor_entries(offsets: &[usize], neighbours: &[u32], order: &[u32]) -> usize {
        let n = offsets.len() - 1;
        let words = n.div_ceil(64);
        let mut position = vec![0usize; n];
        for (p, &v) in order.iter().enumerate() {
            position[v as usize] = p;
        }
        let mut adj = vec![vec![0u64; words]; n];
        for v in 0..n {
            for &u in &neighbours[offsets[v]..offsets[v + 1]] {
                let (a, b) = (position[v], position[u as usize]);
                adj[a][b / 64] |= 1 << (b % 64);
            }
        }
        let mut entries = 0;
        for p in 0..n {
            let later: Vec<usize> = (p + 1..n)
                .filter(|&q| adj[p][q / 64] >> (q % 64) & 1 == 1)
                .collect();
            entries += later.len() + 1;
            for &q in &later {
                for &r in &later {
                    if r != q {
                        adj[q][r / 64] |= 1 << (r % 64);
                    }
                }
            }
        }
        entries
    }

    #[test]
    fn multilevel_dissection_orders_a_3d_grid_with_far_less_fill_than_its_rows() {
        let (points, offsets, neighbours) = grid::<3>(10);
        let order = multilevel_dissection(&offsets, &neighbours).expect("METIS orders a grid");
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..1000u32).collect::<Vec<_>>());
        let natural: Vec<u32> = (0..1000).collect();
        let flat = nested_dissection(&points, &offsets, &neighbours);
        let [metis, banded, bisected] =
            [&order, &natural, &flat].map(|o| factor_entries(&offsets, &neighbours, o));
        // Measured: 35 842 entries against 91 909 for the rows in turn and
        // 49 649 for coordinate bisection.
        assert!(2 * metis < banded, "{metis} {banded}");
        assert!(metis < bisected, "{metis} {bisected}");
        assert_eq!(elimination_order(&points, &offsets, &neighbours), order);
    }

    #[test]
    fn multilevel_dissection_is_the_same_on_every_call_and_thread() {
        let (_, offsets, neighbours) = grid::<3>(9);
        let first = multilevel_dissection(&offsets, &neighbours).unwrap();
        let runs: Vec<Vec<u32>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..4)
                .map(|_| s.spawn(|| multilevel_dissection(&offsets, &neighbours).unwrap()))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert!(runs.iter().all(|r| *r == first));
    }

    #[test]
    fn multilevel_dissection_takes_loops_repeats_isolated_nodes_and_no_nodes() {
        assert_eq!(multilevel_dissection(&[0], &[]), Some(Vec::new()));
        // 0–1 twice, a self-loop on 2, node 3 alone, 4–5.
        let offsets = [0, 2, 4, 5, 5, 6, 7];
        let neighbours = [1, 1, 0, 0, 2, 5, 4];
        let mut order = multilevel_dissection(&offsets, &neighbours).unwrap();
        order.sort_unstable();
        assert_eq!(order, vec![0, 1, 2, 3, 4, 5]);
        let mut lonely = multilevel_dissection(&[0, 0, 0, 0], &[]).unwrap();
        lonely.sort_unstable();
        assert_eq!(lonely, vec![0, 1, 2]);
    }

    proptest::proptest! {
        /// The cover covers every bond between the halves and is as small as
        /// the smallest cover found by trying every subset.
        #[test]
        fn vertex_cover_is_minimum(
            n_low in 1usize..7,
            n_high in 1usize..7,
            bits in proptest::collection::vec(proptest::bool::ANY, 36),
        ) {
            let n = n_low + n_high;
            let mut edges = Vec::new();
            for a in 0..n_low {
                for b in 0..n_high {
                    if bits[a * 6 + b] {
                        edges.push((a, n_low + b));
                    }
                }
            }
            let mut adj = vec![Vec::new(); n];
            for &(a, b) in &edges {
                adj[a].push(b as u32);
                adj[b].push(a as u32);
            }
            let mut offsets = vec![0];
            let mut neighbours = Vec::new();
            for list in &adj {
                neighbours.extend(list);
                offsets.push(neighbours.len());
            }
            let label: Vec<u32> = (0..n).map(|v| if v < n_low { 1 } else { 2 }).collect();
            let low: Vec<u32> = (0..n_low as u32).filter(|&v| !adj[v as usize].is_empty()).collect();
            let high: Vec<u32> = (n_low as u32..n as u32).filter(|&v| !adj[v as usize].is_empty()).collect();
            let cover = min_vertex_cover(&low, &high, &offsets, &neighbours, &label, 2);
            let inside = |v: usize| cover.contains(&(v as u32));
            proptest::prop_assert!(edges.iter().all(|&(a, b)| inside(a) || inside(b)));
            let best = (0u32..1 << n)
                .filter(|set| edges.iter().all(|&(a, b)| set >> a & 1 == 1 || set >> b & 1 == 1))
                .map(u32::count_ones)
                .min()
                .unwrap_or(0);
            proptest::prop_assert_eq!(cover.len() as u32, best);
        }
    }
}
