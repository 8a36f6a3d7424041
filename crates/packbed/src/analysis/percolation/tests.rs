//! Hand-made beds and brute force on small graphs.

use super::*;
use crate::analysis::find_contacts;
use crate::bed::Bed;
use crate::math::{Real, Vector};
use proptest::prelude::*;

fn bed2(size: [Real; 2], periodic: bool, discs: &[(Real, Real, Real, u32)]) -> Bed<2> {
    Bed::of_spheres(
        size,
        periodic,
        discs.iter().map(|&(x, y, r, s)| ([x, y], r, s)),
    )
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

/// Three touching spheres in a row along y, across a box 6 deep.
fn row_along_y(periodic: bool) -> Bed<3> {
    let row = (0..3).map(|k| ([5.0, 1.0 + 2.0 * k as Real, 1.0], 1.0, 0));
    Bed::of_spheres([10.0, 6.0, 10.0], periodic, row)
}

#[test]
fn periodic_3d_wraps_along_y_only() {
    let p = run(&row_along_y(true));
    assert!(p.spans);
    assert!(!p.directions[0].spans);
    assert!(p.directions[1].spans);
    assert_eq!(p.directions[1].axis, "y");
    assert_eq!(p.directions[1].shortest_chain, Some(3));
    assert_eq!(p.shortest_chain, Some(3));
}

#[test]
fn walled_3d_row_along_y() {
    let p = run(&row_along_y(false));
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

/// Spheres of these radii and species, far apart in a big box (the default
/// threshold depends on the radii alone).
fn apart(radii: &[(Real, u32)]) -> Bed<3> {
    Bed::of_spheres(
        [100.0 * radii.len() as Real + 100.0, 100.0, 100.0],
        false,
        radii
            .iter()
            .enumerate()
            .map(|(i, &(r, s))| ([100.0 * i as Real + 50.0, 50.0, 50.0], r, s)),
    )
}

#[test]
fn default_threshold_of_a_lognormal_is_its_volume_median() {
    use crate::species::SizeDist;
    use rand::SeedableRng;
    let (lo, hi) = SizeDist::lognormal_window(10.0, 1.5);
    let dist = SizeDist::Lognormal {
        median: 10.0,
        gsd: 1.5,
        lo,
        hi,
    };
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(28);
    let radii: Vec<Real> = (0..1000).map(|_| dist.sample(&mut rng)).collect();
    // Brute force: the drawn radius with less than half of the volume strictly
    // below it and at least half at or below it.
    let total: Real = radii.iter().map(|r| r.powi(3)).sum();
    let volume = |keep: &dyn Fn(Real) -> bool| -> Real {
        radii.iter().filter(|&&r| keep(r)).map(|r| r.powi(3)).sum()
    };
    let want: Vec<Real> = radii
        .iter()
        .copied()
        .filter(|&c| volume(&|r| r < c) < total / 2.0 && volume(&|r| r <= c) >= total / 2.0)
        .collect();
    assert_eq!(want.len(), 1);
    let bed = apart(&radii.iter().map(|&r| (r, 0)).collect::<Vec<_>>());
    assert_eq!(default_large(&bed), (want[0], LargeSource::VolumeMedian));
    // Not the number median the rule replaced: the coarse tail holds the volume.
    let mut sorted = radii.clone();
    sorted.sort_by(Real::total_cmp);
    assert!(want[0] > 1.2 * sorted[500], "{} {}", want[0], sorted[500]);
}

#[test]
fn default_threshold_of_two_sizes_is_the_larger() {
    let bed = apart(&[(10.0, 0), (20.0, 1), (10.0, 0), (20.0, 1), (10.0, 0)]);
    assert_eq!(default_large(&bed), (20.0, LargeSource::LargestSize));
    let p = run(&bed);
    assert_eq!((p.large_radius, p.large_bodies), (20.0, 2));
    // Equal radii, one species or two: every particle.
    let bed = apart(&[(10.0, 0), (10.0, 1), (10.0, 0)]);
    assert_eq!(default_large(&bed), (10.0, LargeSource::LargestSize));
}

#[test]
fn fines_of_a_table_do_not_make_every_particle_large() {
    // A measured PSD in miniature: 12 fines of radius 5, 6 of 10, 2 of 20 in
    // one species. By number the median is 5 (every particle large); by
    // volume 1500 + 6000 < 23500 / 2, so the volume median is 20.
    let mut radii = vec![(5.0, 0); 12];
    radii.extend([(10.0, 0); 6]);
    radii.extend([(20.0, 0); 2]);
    let p = run(&apart(&radii));
    assert_eq!(p.large_radius, 20.0);
    assert_eq!(p.large_bodies, 2);
    assert_eq!(p.large_rule, LargeSource::VolumeMedian);
    let json = serde_json::to_value(&p).unwrap();
    assert_eq!(json["large_rule"], "volume median");
}

#[test]
fn volume_median_weighs_by_area_in_2d() {
    // Seven radii 1 and one 2: volumes 7 against 8 (3D), areas 7 against 4 (2D).
    let radii = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 2.0];
    assert_eq!(volume_median::<3>(&radii), 2.0);
    assert_eq!(volume_median::<2>(&radii), 1.0);
    assert_eq!(volume_median::<3>(&[]), 0.0);
}
