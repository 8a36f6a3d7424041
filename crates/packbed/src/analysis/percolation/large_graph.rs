//! The graph of large bodies built from a bed and its contacts, and the chain
//! problem (start and end bodies) along one horizontal axis.

use super::graph::{LinkGraph, Terminals};
use super::options::{large_particles, LargeRule, LargeSource};
use crate::analysis::contacts::Contacts;
use crate::bed::Bed;
use crate::container::Wall;
use crate::math::Real;
use rayon::prelude::*;

/// The graph of large bodies of `bed` and, per node, its particles' body id.
pub struct LargeGraph {
    /// The contact graph of large bodies.
    pub graph: LinkGraph,
    /// For each particle, its node (`u32::MAX`: not large).
    pub node_of: Vec<u32>,
    /// Radius threshold in use.
    pub large_radius: Real,
    /// Where the threshold came from.
    pub large_source: LargeSource,
}

/// Builds the graph of large bodies from the contacts of `bed`.
pub fn large_graph<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    large: LargeRule,
) -> LargeGraph {
    let n = bed.len();
    let (is_large, large_radius, large_source) = large_particles(bed, large);
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
        large_source,
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
