//! Rigid chains of beads, shown from the outside (library API only):
//!
//! 1. invariants on several seeds and configurations (2D and 3D, walls and
//!    periodic, mixes with spheres), checked by the independent checker from
//!    positions only: no bead overlap between bodies beyond 1e-9 r, everything
//!    inside the box, every body at rest by the rigid-body test (force and torque
//!    balance about its centre of mass with compressive contacts);
//! 2. hand-checked cases: an upright chain on the floor ends lying flat, a chain
//!    across two discs rests on both, a chain leaning on a frictionless wall
//!    slides down flat;
//! 3. a one-bead chain is a sphere: the same bed for the same seed;
//! 4. determinism.

use crate::common::order_parameter;
use crate::common::{config, run, TOL};
use packbed::Bed;
use packbed::{check_bed, CheckReport as Report};
use packbed::{drop_onto, Entry};
use packbed::{ChainShape, Pose};
use packbed::{Config, Settling};
use packbed::{Real, Vector};

/// Drops one chain by hand; its bead centres at rest.
fn drop_chain<const D: usize>(
    bed: &Bed<D>,
    shape: ChainShape,
    start: Pose<D>,
    seed: u64,
) -> Option<Vec<Vector<D>>> {
    drop_onto(
        bed,
        Entry::Chain { shape, start },
        &Settling::default(),
        seed,
    )
}

fn empty<const D: usize>(size: [Real; D], periodic: bool) -> Bed<D> {
    Bed::of_spheres(size, periodic, [])
}

/// A bed holding the given beads as one body, for the checker.
fn with_chain<const D: usize>(fixed: &Bed<D>, beads: &[Vector<D>], r: Real) -> Bed<D> {
    let mut b = fixed.clone();
    let body = b.bodies.last().map_or(0, |&x| x + 1);
    for p in beads {
        b.push_bead(*p, r, 0, body);
    }
    b
}

fn assert_ok(report: &Report, what: &str) {
    assert!(report.is_ok(), "{what}: {report}");
    assert!(report.max_overlap <= TOL, "{what}: {report}");
}

// ---------------------------------------------------------------------------
// Hand-checked cases
// ---------------------------------------------------------------------------

#[test]
fn upright_two_bead_chain_on_the_floor_ends_lying_flat_2d() {
    let bed = empty([40.0, 40.0], false);
    let shape = ChainShape {
        beads: 2,
        spacing: 1.0,
        r: 1.0,
    };
    for seed in 1..6 {
        let start = Pose {
            com: Vector([20.0, 10.0]),
            axis: Vector([0.0, 1.0]),
        };
        let beads = drop_chain(&bed, shape, start, seed).expect("rests");
        for b in &beads {
            assert!((b[1] - 1.0).abs() < 1e-10, "seed {seed}: {beads:?}");
        }
        assert!(((beads[1] - beads[0]).norm() - 1.0).abs() < 1e-12);
        assert_ok(&check_bed(&with_chain(&bed, &beads, 1.0), TOL), "flat");
    }
}

#[test]
fn upright_chain_on_the_floor_ends_lying_flat_3d_and_tips_to_random_sides() {
    let bed = empty([40.0, 40.0, 40.0], false);
    let shape = ChainShape {
        beads: 2,
        spacing: 1.0,
        r: 1.0,
    };
    let mut directions = Vec::new();
    for seed in 1..9 {
        let start = Pose {
            com: Vector([20.0, 20.0, 10.0]),
            axis: Vector([0.0, 0.0, 1.0]),
        };
        let beads = drop_chain(&bed, shape, start, seed).expect("rests");
        for b in &beads {
            assert!((b[2] - 1.0).abs() < 1e-10, "seed {seed}: {beads:?}");
        }
        assert_ok(&check_bed(&with_chain(&bed, &beads, 1.0), TOL), "flat");
        let d = beads[1] - beads[0];
        directions.push(d[1].atan2(d[0]));
    }
    // The tilt direction is drawn at random: not all the same.
    let spread = directions.iter().cloned().fold(Real::MIN, Real::max)
        - directions.iter().cloned().fold(Real::MAX, Real::min);
    assert!(spread > 0.5, "{directions:?}");
}

#[test]
fn long_upright_chain_lies_flat_in_3d() {
    let bed = empty([60.0, 60.0, 60.0], false);
    let shape = ChainShape {
        beads: 5,
        spacing: 1.0,
        r: 1.0,
    };
    let start = Pose {
        com: Vector([30.0, 30.0, 30.0]),
        axis: Vector([0.0, 0.0, 1.0]),
    };
    let beads = drop_chain(&bed, shape, start, 3).expect("rests");
    for b in &beads {
        assert!((b[2] - 1.0).abs() < 1e-10, "{beads:?}");
    }
}

#[test]
fn chain_across_two_discs_rests_on_both_with_its_centre_of_mass_between() {
    // Two discs of radius 1 on the floor, 4 apart; a chain of 5 touching beads
    // (length 10) dropped horizontally across them, off-centre.
    let mut bed = empty([40.0, 40.0], false);
    bed.push(Vector([18.0, 1.0]), 1.0, 0);
    bed.push(Vector([22.0, 1.0]), 1.0, 0);
    let shape = ChainShape {
        beads: 5,
        spacing: 2.0,
        r: 1.0,
    };
    for (seed, x) in [(1, 20.3), (2, 19.1), (3, 20.9)] {
        let start = Pose {
            com: Vector([x, 10.0]),
            axis: Vector([1.0, 0.0]),
        };
        let beads = drop_chain(&bed, shape, start, seed).expect("rests");
        let all = with_chain(&bed, &beads, 1.0);
        assert_ok(&check_bed(&all, TOL), "across two discs");
        let com = beads.iter().fold(Vector::zero(), |a, b| a + *b) / 5.0;
        assert!(com[0] > 18.0 && com[0] < 22.0, "{beads:?}");
        // Touching both discs, off the floor.
        for disc in [Vector([18.0, 1.0]), Vector([22.0, 1.0])] {
            let gap = beads
                .iter()
                .map(|b| (*b - disc).norm() - 2.0)
                .fold(Real::INFINITY, Real::min);
            assert!(gap.abs() < 1e-9, "{gap} {beads:?}");
        }
        assert!(beads.iter().all(|b| b[1] > 1.0 + 1e-6), "{beads:?}");
        // Horizontal by symmetry of equal discs? Not necessarily (valleys between
        // beads), but the bead in contact with each disc sits above it.
    }
}

#[test]
fn chain_leaning_on_a_frictionless_wall_slides_down_flat() {
    // A 3-bead chain tilted 30° from vertical, its top bead against the wall at
    // x = 0: on a frictionless wall and floor nothing holds it up, it slides
    // down until it lies on the floor.
    let bed = empty([40.0, 40.0], false);
    let shape = ChainShape {
        beads: 3,
        spacing: 2.0,
        r: 1.0,
    };
    let t = (30.0 as Real).to_radians();
    let axis = Vector([-t.sin(), t.cos()]);
    // Top bead centre at x = 1 (touching the wall).
    let com = Vector([1.0, 10.0]) - axis * 2.0;
    let beads = drop_chain(&bed, shape, Pose { com, axis }, 1).expect("rests");
    for b in &beads {
        assert!((b[1] - 1.0).abs() < 1e-10, "{beads:?}");
        assert!(b[0] >= 1.0 - 1e-12, "{beads:?}");
    }
    assert_ok(&check_bed(&with_chain(&bed, &beads, 1.0), TOL), "wall");

    // The same in 3D, leaning into a corner.
    let bed = empty([40.0, 40.0, 40.0], false);
    let axis = Vector([-t.sin() * 0.6, -t.sin() * 0.8, t.cos()]);
    let com = Vector([1.0, 1.0, 10.0]) - axis * 2.0;
    let beads = drop_chain(&bed, shape, Pose { com, axis }, 1).expect("rests");
    for b in &beads {
        assert!((b[2] - 1.0).abs() < 1e-10, "{beads:?}");
    }
    assert_ok(&check_bed(&with_chain(&bed, &beads, 1.0), TOL), "corner");
}

#[test]
fn chain_in_a_v_groove_rests_on_both_flanks() {
    // Two large discs on the floor; a short chain dropped upright between them
    // tips over, slides into the groove and must rest there (or on the floor
    // below if it fits): either way at rest by the independent test.
    let mut bed = empty([60.0, 60.0], false);
    bed.push(Vector([25.0, 5.0]), 5.0, 0);
    bed.push(Vector([35.0, 5.0]), 5.0, 0);
    let shape = ChainShape {
        beads: 3,
        spacing: 1.0,
        r: 1.0,
    };
    for seed in 1..8 {
        let start = Pose {
            com: Vector([30.0 + 0.1 * seed as Real, 30.0]),
            axis: Vector([0.0, 1.0]),
        };
        let beads = drop_chain(&bed, shape, start, seed).expect("rests");
        assert_ok(&check_bed(&with_chain(&bed, &beads, 1.0), TOL), "groove");
    }
}

// ---------------------------------------------------------------------------
// Beds: invariants
// ---------------------------------------------------------------------------

fn chain_toml(dim: u8, seed: u64, boxed: &str, fill: &str, species: &str) -> Config {
    config(&format!(
        "dim = {dim}\nseed = {seed}\n\n[box]\n{boxed}\n\n[fill]\n{fill}\n\n{species}"
    ))
}

const CHAINS_5: &str =
    "[[species]]\nname = \"chains\"\nradius = 10\nshape = \"chain\"\nbeads = 5\n";

fn check_run<const D: usize>(c: &Config, what: &str) -> Bed<D> {
    let (bed, report) = run::<D>(c);
    let r = check_bed(&bed, TOL);
    assert_ok(&r, what);
    // The model's bound is < 1 in 10^5 (see `chain_redrops_are_rare_in_3d`):
    // none in these small beds.
    assert!(
        report.redrops == 0,
        "{what}: {} re-drops for {} dropped",
        report.redrops,
        report.dropped
    );
    bed
}

#[test]
fn invariants_2d_walls_and_periodic() {
    for seed in 1..4 {
        for periodic in [false, true] {
            for species in [
                CHAINS_5.to_string(),
                "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 2\n".to_string(),
                format!("{CHAINS_5}\n[[species]]\nradius = 5\n"),
                format!(
                    "{CHAINS_5}orientation = \"random\"\n\n[[species]]\nradius = 5\nshape = \"chain\"\nbeads = 5\nspacing = 0.5\norientation = \"horizontal\"\n"
                ),
            ] {
                let c = chain_toml(
                    2,
                    seed,
                    &format!("width = 300\nheight = 300\nperiodic = {periodic}"),
                    "count = 250",
                    &species,
                );
                let bed = check_run::<2>(&c, &format!("2D seed {seed} periodic {periodic}"));
                assert!(bed.len() >= 250);
            }
        }
    }
}

#[test]
fn invariants_3d_walls_and_periodic() {
    for seed in 1..3 {
        for periodic in [false, true] {
            for species in [
                CHAINS_5.to_string(),
                format!("{CHAINS_5}orientation = \"random\"\n\n[[species]]\nradius = 10\n"),
                "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 9\nspacing = 0.5\norientation = \"horizontal\"\n".to_string(),
            ] {
                let c = chain_toml(
                    3,
                    seed,
                    &format!("width = 150\nheight = 300\nperiodic = {periodic}"),
                    "count = 250",
                    &species,
                );
                check_run::<3>(&c, &format!("3D seed {seed} periodic {periodic}"));
            }
        }
    }
}

#[test]
fn thesis_box_until_roof_2d_and_3d() {
    // System D of the source study (5-bead chains, r 10, thesis box, roof fill).
    let c = chain_toml(2, 7, "preset = \"thesis\"", "until = \"roof\"", CHAINS_5);
    let bed = check_run::<2>(&c, "thesis 2D");
    assert!(bed.top() <= bed.container.height() + 1e-9);
    let c = chain_toml(3, 7, "preset = \"thesis\"", "until = \"roof\"", CHAINS_5);
    let bed = check_run::<3>(&c, "thesis 3D");
    assert!(bed.top() <= bed.container.height() + 1e-9);
}

#[test]
fn base_layer_of_chains_lies_flat_and_saturates() {
    let c = chain_toml(
        3,
        5,
        "width = 200\nheight = 100\nperiodic = true",
        "count = 2000\nbase_layer = \"random\"",
        CHAINS_5,
    );
    let (bed, report) = run::<3>(&c);
    assert!(report.base_layer > 0);
    for i in 0..report.base_layer as usize {
        assert!((bed.centres[i][2] - 10.0).abs() < 1e-12);
    }
    assert_eq!(report.base_layer % 5, 0, "whole chains");
    assert_ok(&check_bed(&bed, TOL), "base layer");
}

// ---------------------------------------------------------------------------
// One bead is a sphere; determinism
// ---------------------------------------------------------------------------

#[test]
fn one_bead_chains_are_spheres() {
    for dim in [2u8, 3] {
        let spheres = "[[species]]\nradius = 10\n\n[[species]]\nradius = 5\n";
        let chains = "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 1\n\n[[species]]\nradius = 5\nshape = \"chain\"\nbeads = 1\norientation = \"random\"\n";
        let a = chain_toml(dim, 3, "preset = \"thesis\"", "until = \"roof\"", spheres);
        let b = chain_toml(dim, 3, "preset = \"thesis\"", "until = \"roof\"", chains);
        if dim == 2 {
            let (x, _) = run::<2>(&a);
            let (y, _) = run::<2>(&b);
            assert_eq!(x.centres, y.centres);
            assert_eq!(x.bodies, y.bodies);
        } else {
            let (x, _) = run::<3>(&a);
            let (y, _) = run::<3>(&b);
            assert_eq!(x.centres, y.centres);
            assert_eq!(x.bodies, y.bodies);
        }
    }
}

#[test]
fn same_seed_same_chain_bed() {
    let c = chain_toml(
        3,
        11,
        "width = 120\nheight = 200\nperiodic = true",
        "count = 300",
        &format!("{CHAINS_5}orientation = \"random\"\n"),
    );
    let (a, _) = run::<3>(&c);
    let (b, _) = run::<3>(&c);
    assert_eq!(a.centres, b.centres);
}

/// Physics check (run with `--ignored`, prints the figures): a large periodic
/// 3D bed of rods of aspect ratio 5 (spacing 0.5, 17 beads). Deposited rods
/// lie closer to horizontal than to vertical: order parameter below 0.
#[test]
#[ignore]
fn rods_lie_closer_to_horizontal() {
    let c = chain_toml(
        3,
        1,
        "width = 400\nheight = 2000\nperiodic = true",
        "count = 85000\nbase_layer = \"none\"",
        "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 17\nspacing = 0.5\norientation = \"random\"\n",
    );
    let (bed, report) = run::<3>(&c);
    let (s, n) = order_parameter(&bed);
    let phi = packbed::bulk_fraction(&bed);
    println!("{n} rods, S = {s:.4}, bulk packing fraction {phi:?}, {report:?}");
    assert_ok(&check_bed(&bed, TOL), "rods");
    assert!(s < 0.0, "S = {s}");
}

#[test]
fn order_parameter_of_a_small_rod_bed_is_negative() {
    let c = chain_toml(
        3,
        2,
        "width = 200\nheight = 400\nperiodic = true",
        "count = 3400\nbase_layer = \"none\"",
        "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 17\nspacing = 0.5\norientation = \"random\"\n",
    );
    let bed = check_run::<3>(&c, "rods");
    let (s, n) = order_parameter(&bed);
    assert_eq!(n, 200);
    assert!(s < 0.0, "S = {s}");
}

/// The model asks re-drops to be rare (< 1 in 10^5). Rods of aspect 5 were the
/// hard case (nearly parallel supports: a rod along or across another, in the
/// groove between two); none of 2,500 here (and none of 5,000 in
/// `rods_lie_closer_to_horizontal`, none of 10^5 5-bead chains in 2D and in 3D
/// in `bench_chain_beds_pass_the_checker`). Every rod is checked too.
#[test]
fn chain_redrops_are_rare_in_3d() {
    let c = chain_toml(
        3,
        2,
        "width = 280\nheight = 600\nperiodic = true",
        "count = 42500\nbase_layer = \"none\"",
        "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 17\nspacing = 0.5\norientation = \"random\"\n",
    );
    let (bed, report) = run::<3>(&c);
    assert_eq!(report.dropped, 2500);
    assert_eq!(report.redrops, 0, "{report:?}");
    assert_ok(&check_bed(&bed, TOL), "rods");
}

/// Every config of `examples/thesis/chains` reads and plans: the source
/// study's seven systems in 2D and 3D, and rods of aspect 2 to 10.
#[test]
fn thesis_chain_examples_parse_and_plan() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/thesis/chains");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("examples/thesis/chains") {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            let c = config(&text);
            let ok = match c.dim {
                2 => c.plan::<2>().map(|_| ()),
                _ => c.plan::<3>().map(|_| ()),
            };
            ok.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            n += 1;
        }
    }
    assert_eq!(n, 23, "7 systems in 2D and 3D, and rods of aspect 2..10");
}

/// The beds of `packbed bench --dim 2|3 --chains 5 --n 100000 --periodic`
/// (same config: seed 1, bead radius 10, no base layer, a periodic cube of
/// the side `bench` computes), checked by the independent checker, with their
/// re-drop counts (run with `--ignored --nocapture`; about 2 minutes).
#[test]
#[ignore]
fn bench_chain_beds_pass_the_checker() {
    let n: u64 = 100_000;
    for dim in [2u8, 3] {
        let particles = 5 * n;
        let side = ((particles as f64).powf(1.0 / dim as f64).max(4.0) * 20.0).max(120.0);
        let depth = if dim == 3 {
            format!("depth = {side}\n")
        } else {
            String::new()
        };
        let c = chain_toml(
            dim,
            1,
            &format!("width = {side}\n{depth}height = {side}\nperiodic = true"),
            &format!("count = {particles}\nbase_layer = \"none\""),
            "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 5\n",
        );
        let (report, check) = if dim == 2 {
            let (b, r) = run::<2>(&c);
            (r, check_bed(&b, TOL))
        } else {
            let (b, r) = run::<3>(&c);
            (r, check_bed(&b, TOL))
        };
        println!("dim {dim}: {report:?}\n{check}");
        assert_ok(&check, "bench bed");
        assert_eq!(report.redrops, 0, "dim {dim}");
    }
}

/// No re-drop of 35,000 rods of aspect 5 over seven seeds (the bed of
/// `rods_lie_closer_to_horizontal`, 5,000 rods each), every bed checked by the
/// independent checker. Ignored because it takes about 2 minutes: run with
/// `--ignored --nocapture`.
#[test]
#[ignore]
fn rod_redrops_over_seeds() {
    let (mut redrops, mut rods) = (0, 0);
    for seed in 1..=7 {
        let c = chain_toml(
            3,
            seed,
            "width = 400\nheight = 2000\nperiodic = true",
            "count = 85000\nbase_layer = \"none\"",
            "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 17\nspacing = 0.5\norientation = \"random\"\n",
        );
        let (bed, report) = run::<3>(&c);
        let check = check_bed(&bed, TOL);
        println!("seed {seed}: {report:?}\n{check}");
        assert_ok(&check, "rods");
        assert_eq!(bed.body_count(), 5_000, "seed {seed}");
        rods += bed.body_count();
        redrops += report.redrops;
    }
    assert_eq!((redrops, rods), (0, 35_000), "re-drops in {rods} rods");
}
