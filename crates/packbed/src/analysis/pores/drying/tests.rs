//! The drying against a step-by-step drying, closed forms, the mass
//! balance and the agglomerates' definition.

use super::*;
use crate::analysis::pores::drainage::bridge::Pair;
use crate::analysis::pores::drainage::pendular::neck_for_volume;
use crate::analysis::pores::drainage::{drain_wet, StatePressure};
use crate::analysis::pores::network::network;
use crate::{run_bed, Config};
use proptest::prelude::*;

/// The drying simulated one pore at a time: the cluster of the pore that
/// empties searched afresh, its concentration uniform (each liquid pore
/// holds its cluster's concentration), the deposit by the module's rule.
fn step_by_step(
    n: usize,
    throats: &[(u32, u32)],
    order: &[u32],
    voids: &[Real],
    c: Real,
    s: Real,
) -> Vec<Real> {
    let mut liquid = vec![true; n];
    let mut conc = vec![c; n];
    let mut out = vec![0.0; n];
    for &p in order {
        let p = p as usize;
        // The cluster of p among the liquid pores.
        let mut seen = vec![false; n];
        let mut stack = vec![p];
        seen[p] = true;
        let mut cluster = Vec::new();
        while let Some(q) = stack.pop() {
            cluster.push(q);
            for &(a, b) in throats {
                let (a, b) = (a as usize, b as usize);
                for (x, y) in [(a, b), (b, a)] {
                    if x == q && liquid[y] && !seen[y] {
                        seen[y] = true;
                        stack.push(y);
                    }
                }
            }
        }
        let volume: Real = cluster.iter().map(|&q| voids[q]).sum();
        let mass: Real = cluster.iter().map(|&q| conc[q] * voids[q]).sum();
        let after = volume - voids[p];
        let d = if !(after > 0.0) {
            mass
        } else if s.is_finite() {
            (mass - s * after).max(0.0)
        } else {
            0.0
        };
        out[p] = d;
        liquid[p] = false;
        if after > 0.0 {
            let left = (mass - d) / after;
            for &q in &cluster {
                conc[q] = left;
            }
        }
    }
    out
}

/// The adjacency `deposits` reads, of `n` pores joined by `throats`.
fn adjacency(n: usize, throats: &[(u32, u32)]) -> Adjacency {
    Adjacency::new(&InvasionGraph {
        pores: n,
        throats: throats.iter().map(|&(a, b)| (a, b, 0.0)).collect(),
        ..InvasionGraph::default()
    })
}

/// A random network: `n` pores, throats, an order, voids.
type Case = (usize, Vec<(u32, u32)>, Vec<u32>, Vec<Real>);

fn network_case() -> impl Strategy<Value = Case> {
    (1usize..24).prop_flat_map(|n| {
        (
            Just(n),
            proptest::collection::vec((0..n as u32, 0..n as u32), 0..3 * n),
            Just((0..n as u32).collect::<Vec<u32>>()).prop_shuffle(),
            proptest::collection::vec(0.1f64..2.0, n),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// The deposits equal the step-by-step drying's, and add up to the
    /// solid dissolved at the start.
    #[test]
    fn deposits_match_a_step_by_step_drying(
        (n, throats, order, voids) in network_case(),
        c in 0.0f64..0.1,
        over in prop_oneof![Just(Real::INFINITY), 1.0f64..3.0],
    ) {
        let throats: Vec<(u32, u32)> = throats.into_iter().filter(|t| t.0 != t.1).collect();
        let s = c * over;
        let s = if s > 0.0 { s } else { Real::INFINITY };
        let fast = deposits(&adjacency(n, &throats), &order, &voids, c, s);
        let slow = step_by_step(n, &throats, &order, &voids, c, s);
        for (a, b) in fast.iter().zip(&slow) {
            prop_assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{:?} against {:?}", fast, slow);
            prop_assert!(*a >= 0.0);
        }
        let total: Real = fast.iter().sum();
        let dissolved = c * voids.iter().sum::<Real>();
        prop_assert!((total - dissolved).abs() <= 1e-12 * (1.0 + dissolved));
    }

    /// Agglomerates are the connected components of the bonds: two
    /// particles share one exactly when a path of bonds joins them.
    #[test]
    fn components_are_the_bond_graphs_connected_parts(
        n in 1usize..40,
        bonds in proptest::collection::vec((0u32..40, 0u32..40), 0..60),
    ) {
        let bonds: Vec<(u32, u32)> = bonds
            .into_iter()
            .filter(|b| (b.0 as usize) < n && (b.1 as usize) < n)
            .collect();
        let fast = components(n, &bonds);
        for p in 0..n {
            // Brute force: everything reachable from p.
            let mut seen = vec![false; n];
            seen[p] = true;
            let mut grew = true;
            while grew {
                grew = false;
                for &(a, b) in &bonds {
                    let (a, b) = (a as usize, b as usize);
                    if seen[a] != seen[b] {
                        seen[a] = true;
                        seen[b] = true;
                        grew = true;
                    }
                }
            }
            for q in 0..n {
                prop_assert_eq!(fast[p] == fast[q], seen[q]);
            }
        }
    }
}

/// A saturated liquid deposits `s × v` in each pore that empties while its
/// cluster lives on, and the rest in the cluster's last pore; a liquid far
/// below its solubility deposits everything in the last pore.
#[test]
fn saturated_liquid_deposits_as_it_goes_and_dilute_liquid_at_the_end() {
    // A chain of three pores 0 - 1 - 2 emptying 0, 1, 2.
    let throats = [(0, 1), (1, 2)];
    let voids = [1.0, 2.0, 3.0];
    let chain = adjacency(3, &throats);
    let sat = deposits(&chain, &[0, 1, 2], &voids, 0.1, 0.1);
    assert!((sat[0] - 0.1).abs() < 1e-15 && (sat[1] - 0.2).abs() < 1e-15);
    assert!((sat[2] - 0.3).abs() < 1e-15);
    let dilute = deposits(&chain, &[0, 1, 2], &voids, 0.01, Real::INFINITY);
    assert_eq!(dilute[..2], [0.0, 0.0]);
    assert!((dilute[2] - 0.06).abs() < 1e-15);
    // Emptying the middle pore first splits the cluster: each end keeps
    // the solid of its own volume (uniform concentration).
    let split = deposits(&chain, &[1, 0, 2], &voids, 0.01, Real::INFINITY);
    assert_eq!(split[1], 0.0);
    assert!((split[0] - 0.06 * 1.0 / 4.0).abs() < 1e-15);
    assert!((split[2] - 0.06 * 3.0 / 4.0).abs() < 1e-15);
}

/// The neck of a small solid bridge between touching spheres follows the
/// small-angle pendular ring, `V ≈ π R³ β⁴ / 2` with neck `≈ R β` (θ = 0):
/// `π a² ≈ (2π V R)^{1/2}`, Endo et al.'s square-root law.
#[test]
fn a_small_solid_bridge_between_touching_spheres_follows_the_ring_law() {
    let pair = Pair::new(1.0, 1.0, 0.0, 0.0).unwrap();
    let bridge = |k: Real| pair.bridge(k).map(|b| (b.volume, b.neck_radius));
    for v in [1e-8, 1e-7, 1e-6] {
        let a = neck_for_volume(bridge, 1.0, v, None).unwrap();
        let ring = (2.0 / std::f64::consts::PI * v).powf(0.25);
        assert!((a / ring - 1.0).abs() < 0.03, "{v}: {a} against {ring}");
        // The bridge of that neck (found here by bisection on the
        // curvature: the neck falls as it rises) holds the volume asked for.
        let (mut lo, mut hi) = (1e-3f64.ln(), 1e9f64.ln());
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if pair.bridge(mid.exp()).unwrap().neck_radius > a {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let back = pair.bridge(lo.exp()).unwrap().volume;
        assert!(
            (back / v - 1.0).abs() < 1e-6,
            "{v}: the neck's bridge holds {back}"
        );
    }
    // The neck grows with the volume.
    let a1 = neck_for_volume(bridge, 1.0, 1e-4, None).unwrap();
    let a2 = neck_for_volume(bridge, 1.0, 1e-3, None).unwrap();
    assert!(a2 > a1);
}

/// Spheres apart by a gap form no solid bridge from a deposit smaller than
/// the gap's smallest liquid bridge, and spheres far apart none at all.
#[test]
fn spheres_apart_form_no_bridge_from_too_little_solid() {
    let pair = Pair::new(1.0, 1.0, 0.1, 0.0).unwrap();
    let bridge = |k: Real| pair.bridge(k).map(|b| (b.volume, b.neck_radius));
    let smallest = pair.bridge(pair.kappa_max).unwrap().volume;
    // With the fold given and found by bisection alike.
    for fold in [Some(pair.kappa_max), None] {
        assert!(neck_for_volume(bridge, 1.0, 0.5 * smallest, fold).is_none());
        assert!(neck_for_volume(bridge, 1.0, 2.0 * smallest, fold).is_some());
    }
    let far = Pair::new(1.0, 1.0, 5.0, 0.0);
    let none = |k: Real| {
        far.and_then(|p| p.bridge(k))
            .map(|b| (b.volume, b.neck_radius))
    };
    // A small deposit cannot span five radii.
    assert!(neck_for_volume(none, 1.0, 1e-3, None).is_none());
}

fn deposited(count: u64, seed: u64) -> Bed<3> {
    let text = format!(
        "dim = 3\nseed = {seed}\n[box]\nwidth = 10\ndepth = 10\nheight = 400\nperiodic = true\n\
         [fill]\ncount = {count}\n[[species]]\nradius = 1.0\n"
    );
    let config = Config::from_toml(&text, "test").unwrap();
    match run_bed(&config, &mut |_| {}).unwrap().bed {
        crate::bed::AnyBed::D3(b) => b,
        crate::bed::AnyBed::D2(_) => unreachable!(),
    }
}

fn dry_bed(
    bed: &Bed<3>,
    slab: (Real, Real),
    drain_options: &DrainageOptions,
    options: &DryingOptions,
) -> (Drainage, Drying) {
    let net = network(bed, slab).unwrap();
    let (d, wet) = drain_wet(bed, &net, slab, 2.0, Some(1e-6), drain_options).unwrap();
    let dried = dry(
        bed,
        &net,
        slab,
        &d,
        &wet,
        drain_options,
        options,
        Some(1e-6),
    )
    .unwrap();
    (d, dried)
}

/// The solid deposited (at pairs and on surfaces) is the solid dissolved in
/// the liquid the drainage left; the liquid dried is the drainage's.
#[test]
fn the_solid_is_conserved_and_the_agglomerates_are_the_bonds_components() {
    let bed = deposited(1000, 5);
    let slab = (3.0, 13.0);
    for (c, s) in [(50.0, 50.0), (5.0, 50.0), (50.0, Real::INFINITY)] {
        let options = DryingOptions {
            concentration: c,
            solubility: s,
            ..DryingOptions::default()
        };
        let (d, dried) = dry_bed(&bed, slab, &DrainageOptions::default(), &options);
        let a = &dried.summary;
        assert!(a.solid_volume > 0.0);
        let placed = a.solid_at_pairs + a.solid_on_surfaces;
        assert!((placed - a.solid_volume).abs() < 1e-9 * a.solid_volume);
        let rows: Real = dried.bridges.iter().map(|b| b.solid).sum();
        assert!((rows - a.solid_at_pairs).abs() < 1e-9 * a.solid_volume);
        // The liquid dried is the liquid left: the filled and trapped pores'
        // void and the bridges of liquid.csv.
        let filled: Real = d
            .pores
            .iter()
            .filter(|p| matches!(p.0, PoreState::Filled | PoreState::Trapped))
            .map(|p| p.2)
            .sum();
        let bridges: Real = d.bridges.iter().map(|b| b.volume).sum();
        assert!((a.liquid_volume - filled - bridges).abs() < 1e-9 * a.liquid_volume);
        assert!((a.solid_volume - c / 1500.0 * a.liquid_volume).abs() < 1e-9 * a.solid_volume);
        // Agglomerates: particles share an id exactly when bonds join them.
        let bonds: Vec<(u32, u32)> = dried
            .bridges
            .iter()
            .filter(|b| b.bond)
            .map(|b| (b.particles[0], b.particles[1]))
            .collect();
        let roots = components(bed.len(), &bonds);
        for &(x, y) in &bonds {
            assert_eq!(
                dried.agglomerate_of[x as usize],
                dried.agglomerate_of[y as usize]
            );
            assert!(dried.agglomerate_of[x as usize] > 0);
        }
        let tag = &dried.agglomerate_of;
        for p in 0..bed.len() {
            for q in (0..bed.len()).step_by(7).filter(|&q| q != p) {
                let tagged = tag[p] > 0 && tag[p] == tag[q];
                assert_eq!(roots[p] == roots[q], tagged, "{p} {q}");
            }
        }
        let members: u64 = dried.agglomerates.iter().map(|g| g.particles).sum();
        assert_eq!(
            members,
            dried.agglomerate_of.iter().filter(|&&g| g > 0).count() as u64
        );
    }
}

/// No solid, no bridges and no agglomerates.
#[test]
fn zero_concentration_gives_no_agglomerates() {
    let bed = deposited(600, 2);
    let options = DryingOptions {
        concentration: 0.0,
        solubility: Real::INFINITY,
        ..DryingOptions::default()
    };
    let (_, dried) = dry_bed(&bed, (3.0, 9.0), &DrainageOptions::default(), &options);
    assert!(dried.bridges.is_empty());
    assert!(dried.agglomerates.is_empty());
    assert_eq!(dried.summary.agglomerates, 0);
    assert_eq!(dried.summary.fraction_in_agglomerates, 0.0);
}

/// A bed the gas has drained of every pore keeps liquid only in pendular
/// bridges: the solid is exactly where those bridges were, each pair's
/// solid the solid its own bridge held.
#[test]
fn a_fully_drained_bed_leaves_solid_only_where_the_bridges_were() {
    let bed = deposited(600, 4);
    let drain_options = DrainageOptions {
        trapping: false,
        state: Some(StatePressure::Reduced(60.0)),
        ..DrainageOptions::default()
    };
    let options = DryingOptions::default();
    let (d, dried) = dry_bed(&bed, (3.0, 9.0), &drain_options, &options);
    assert!(!d
        .pores
        .iter()
        .any(|p| matches!(p.0, PoreState::Filled | PoreState::Trapped)));
    assert!(!d.bridges.is_empty());
    assert_eq!(dried.bridges.len(), d.bridges.len());
    let c = options.concentration / options.crystal_density;
    for (liquid, solid) in d.bridges.iter().zip(&dried.bridges) {
        assert_eq!(liquid.particles, solid.particles);
        assert!((solid.solid - c * liquid.volume).abs() < 1e-12 * liquid.volume);
    }
    assert_eq!(dried.summary.pores_dried, 0);
}

#[test]
fn bad_settings_are_refused() {
    let ok = DryingOptions::default();
    assert!(check_options(&ok).is_ok());
    for bad in [
        DryingOptions {
            concentration: -1.0,
            ..ok
        },
        DryingOptions {
            concentration: 60.0,
            solubility: 50.0,
            ..ok
        },
        DryingOptions {
            crystal_density: 0.0,
            ..ok
        },
        DryingOptions {
            min_neck: Real::NAN,
            ..ok
        },
        DryingOptions {
            tensile_strength: -2.0,
            ..ok
        },
    ] {
        let why = check_options(&bad).unwrap_err();
        assert!(why.starts_with("drying: ") && !why.contains('\n'), "{why}");
    }
}

/// A rigid chain is one particle: two chains of three beads bridged at one
/// contact are one agglomerate of two particles holding all six beads; a
/// third chain with no bridge is a single particle, not three.
#[test]
fn a_chain_is_one_particle_of_an_agglomerate() {
    let mut bed = Bed::<3>::of_spheres(
        [20.0, 20.0, 20.0],
        false,
        (0..9).map(|i| {
            let (chain, bead) = (i / 3, i % 3);
            let y = 2.0 + 2.0 * chain as Real + if chain == 2 { 3.0 } else { 0.0 };
            ([2.0 + 2.0 * bead as Real, y, 5.0], 1.0, 0)
        }),
    );
    bed.bodies = (0..9).map(|i| i / 3).collect();
    let bead = crate::math::ball_volume::<3>(1.0);
    // Bead 2 of chain 0 touches bead 5 of chain 1 (both at x = 6).
    let p = product(&bed, (0.0, 20.0), &[(2, 5)]);
    assert_eq!(p.agglomerates.len(), 1);
    assert_eq!(p.agglomerates[0].particles, 2);
    assert!((p.agglomerates[0].volume - 6.0 * bead).abs() <= 1e-12 * bead);
    assert!((p.fraction_in_agglomerates - 6.0 / 9.0).abs() <= 1e-12);
    assert_eq!(p.agglomerate_of, vec![1, 1, 1, 1, 1, 1, 0, 0, 0]);
    assert_eq!(p.largest_particles, 2);
    // Units of 1 particle (the lone chain, 3 beads) and of 2 (6 beads).
    assert_eq!(p.volume_by_particles.len(), 2);
    assert!((p.volume_by_particles[0] - 1.0 / 3.0).abs() <= 1e-12);
    assert!((p.volume_by_particles[1] - 2.0 / 3.0).abs() <= 1e-12);
    // No bridges: no agglomerate, three single particles.
    let none = product(&bed, (0.0, 20.0), &[]);
    assert!(none.agglomerates.is_empty());
    assert_eq!(none.volume_by_particles, vec![1.0]);
    assert_eq!(none.fraction_in_agglomerates, 0.0);
}
