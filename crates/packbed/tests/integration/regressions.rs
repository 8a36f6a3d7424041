//! Regression tests: the source study's fill rule, beds
//! that must never be written, and measures whose definitions were wrong.
//! Each test failed on the code before its fix.

use crate::common::{assert_checked, config, run, TOL};
use packbed::analyze;
use packbed::Bed;
use packbed::{check_bed_with, InvariantChecks};
use packbed::{Config, Fill};

fn assert_valid<const D: usize>(b: &Bed<D>, what: &str) {
    let checks = InvariantChecks {
        roof: true,
        ..InvariantChecks::new(TOL)
    };
    assert_checked(b, &checks, what);
}

// ---------------------------------------------------------------------------
// 1. The fill rule: 100 roof misses in total by default
// ---------------------------------------------------------------------------

fn thesis_box(dim: u8, seed: u64, fill: &str, species: &str) -> Config {
    config(&format!(
        "dim = {dim}\nseed = {seed}\n[box]\npreset = \"thesis\"\n[fill]\n{fill}\n{species}"
    ))
}

const SPHERES: &str = "[[species]]\nradius = 10\n[[species]]\nradius = 20\n";
const CHAINS: &str = "[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 3\n";

fn fill_rule<const D: usize>(species: &str) {
    let mut global = [0.0; 2];
    for seed in 1..=4 {
        let c = thesis_box(D as u8, seed, "until = \"roof\"", species);
        assert_eq!(c.fill.roof_misses, 100);
        let plan = c.plan::<D>().unwrap();
        assert!(matches!(plan.fill, Fill::Roof { misses: 100 }));
        let (b, rep) = run::<D>(&c);
        // The 101st miss stops the fill: 100 are tolerated in total.
        assert_eq!(rep.roof_overflows, 101, "{D}D seed {seed}");
        assert_valid(&b, "default fill");
        global[0] += analyze(&b, 1e-9).1.packing.as_ref().unwrap().global;

        let c = thesis_box(D as u8, seed, "roof_misses = 0", species);
        let (b, rep) = run::<D>(&c);
        assert_eq!(rep.roof_overflows, 1, "{D}D seed {seed}");
        assert_valid(&b, "roof_misses = 0");
        global[1] += analyze(&b, 1e-9).1.packing.as_ref().unwrap().global;
    }
    // Going on after misses fills the hollows below the roof.
    assert!(
        global[0] > global[1] + 4.0 * 0.02,
        "{D}D: global packing summed over 4 seeds {} (100 misses) vs {} (0)",
        global[0],
        global[1]
    );
}

#[test]
fn roof_fill_defaults_to_100_misses_in_total_2d() {
    fill_rule::<2>(SPHERES);
    fill_rule::<2>(CHAINS);
}

#[test]
fn roof_fill_defaults_to_100_misses_in_total_3d() {
    fill_rule::<3>(SPHERES);
    fill_rule::<3>(CHAINS);
}

#[test]
fn roof_misses_round_trip_in_the_config_as_used() {
    let c = thesis_box(3, 1, "", SPHERES);
    let text = toml::to_string(&c).unwrap();
    assert!(text.contains("roof_misses = 100"), "{text}");
}

// ---------------------------------------------------------------------------
// 2. Chains longer than the box are refused; none stands through the floor
// ---------------------------------------------------------------------------

#[test]
fn chains_longer_than_the_box_are_refused() {
    for base in ["random", "none"] {
        // 20 beads of radius 10, spacing 1: 210 long; the 3D thesis box is 120 wide.
        let c = config(&format!(
            "dim = 3\n[box]\npreset = \"thesis\"\n[fill]\nbase_layer = \"{base}\"\n[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 20\n"
        ));
        let Err(e) = c.plan::<3>() else {
            panic!("a chain of 20 beads in the 3D thesis box was accepted")
        };
        let e = e.to_string();
        assert!(
            e.contains("210 long") && e.contains("longer than the box"),
            "{e}"
        );
    }
    // Across periodic sides it would overlap its own image.
    let c = config(
        "dim = 2\n[box]\nwidth = 100\nheight = 400\nperiodic = true\n[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 10\n",
    );
    assert!(c.plan::<2>().is_err());
    // Exactly as long as the box is wide still fits.
    let c = config(
        "dim = 2\n[box]\nwidth = 110\nheight = 400\n[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 10\n",
    );
    let (b, _) = run::<2>(&c);
    assert_valid(&b, "2D chains as long as the box");
}

#[test]
fn chains_as_long_as_the_box_is_wide_settle_inside_it() {
    // 100 long on a 100 × 100 floor: the longest accepted. The base layer lays
    // them flat and never upright (an upright chain with its lowest bead at the
    // floor's level stood through it when no flat pose fitted).
    for seed in 1..=3 {
        let c = config(&format!(
            "dim = 3\nseed = {seed}\n[box]\nwidth = 100\ndepth = 100\nheight = 150\n[fill]\ncount = 40\n[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 9\n"
        ));
        let (b, _) = run::<3>(&c);
        let lowest = (0..b.len())
            .map(|i| b.centres[i][2] - b.radii[i])
            .fold(f64::INFINITY, f64::min);
        assert!(lowest >= -1e-9, "seed {seed}: a bead reaches z = {lowest}");
        let rep = check_bed_with(&b, &InvariantChecks::new(1e-9));
        assert!(rep.is_ok(), "seed {seed}: {rep}");
    }
}

// ---------------------------------------------------------------------------
// 4. "Large" is a radius, not a species
// ---------------------------------------------------------------------------

#[test]
fn equal_radii_in_two_species_are_all_large() {
    let c = config(
        "dim = 2\nseed = 3\n[box]\npreset = \"thesis\"\n[[species]]\nradius = 10\n[[species]]\nradius = 10\n",
    );
    let (b, _) = run::<2>(&c);
    assert!(b.species.contains(&0) && b.species.contains(&1));
    let p = analyze(&b, 1e-9).1.percolation.unwrap();
    assert_eq!(p.large_bodies, b.len() as u64);
    assert_eq!(p.large_radius, 10.0);
}

#[test]
fn large_threshold_of_a_size_distribution_is_below_a_coarser_fixed_size() {
    // The README's mix: radius 20, and lognormal radii of median 10 (volume
    // median about 10 · e^(3 ln²1.3) = 12.3, truncation bound 10 · 1.3^3 = 22).
    // The 20s are large, and the few lognormal particles of radius >= 20; the
    // species names follow the medians.
    let c = config(
        "dim = 2\nseed = 7\n[box]\npreset = \"thesis\"\n[[species]]\nradius = 20\nratio = 1\n[[species]]\nsize = { dist = \"lognormal\", median = 10.0, gsd = 1.3 }\nratio = 2\n",
    );
    let plan = c.plan::<2>().unwrap();
    assert_eq!(plan.species[0].name, "large");
    assert_eq!(plan.species[1].name, "small");
    let (b, _) = run::<2>(&c);
    let p = analyze(&b, 1e-9).1.percolation.unwrap();
    assert_eq!(p.large_radius, 20.0);
    let by_radius = b.radii.iter().filter(|&&r| r >= 20.0).count() as u64;
    assert_eq!(p.large_bodies, by_radius);
    assert!(b.radii.iter().any(|&r| r < 20.0 && r > 2.7));
}

#[test]
fn median_of_a_psd_table_weighs_rows_in_order_of_radius() {
    use packbed::{SizeDist, SizeTable, Within};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("psd.csv");
    std::fs::write(&path, "radius,number\n30,1\n10,2\n20,1.5\n").unwrap();
    let d = SizeDist::Table(SizeTable::read(&path, Within::LogUniform, None).unwrap());
    // Weights by radius: 10 → 2/4.5 = 0.44, 20 → 0.78: the median is 20.
    assert_eq!(d.median(), 20.0);
    assert_eq!(SizeDist::Uniform { min: 2.0, max: 4.0 }.median(), 3.0);
}

// ---------------------------------------------------------------------------
// 10. A species of ratio 0 never appears
// ---------------------------------------------------------------------------

#[test]
fn a_species_of_ratio_zero_never_appears() {
    for dim in [2u8, 3] {
        for base in ["random", "none"] {
            // The small species has ratio 0: the base layer's gap sweep used it.
            let text = format!(
                "dim = {dim}\nseed = 2\n[box]\npreset = \"thesis\"\n[fill]\nbase_layer = \"{base}\"\n[[species]]\nradius = 20\nratio = 1\n[[species]]\nradius = 10\nratio = 0\n"
            );
            let c = config(&text);
            let species: Vec<u32> = if dim == 2 {
                run::<2>(&c).0.species
            } else {
                run::<3>(&c).0.species
            };
            assert!(!species.is_empty());
            assert!(
                species.iter().all(|&s| s == 0),
                "{dim}D {base}: {} particles of the ratio-0 species",
                species.iter().filter(|&&s| s == 1).count()
            );
        }
    }
}

// ---------------------------------------------------------------------------
// 5. The bulk region: a surface robust to spikes, and a minimum of bodies
// ---------------------------------------------------------------------------

#[test]
fn a_spike_does_not_lower_the_bulk_region() {
    use packbed::Container;
    use packbed::Vector;
    use packbed::{bulk_region, surface_height};
    // Unit spheres on a cubic lattice, 40 × 40 × 10 cells, one sphere on top at z = 30.
    let mut bed: Bed<3> = Bed::new(
        Container {
            size: Vector([40.0, 40.0, 40.0]),
            periodic: false,
        },
        Vec::new(),
    );
    for i in 0..40 {
        for j in 0..40 {
            for k in 0..10 {
                let c = |n: i32| n as f64 + 0.5;
                bed.push(Vector([c(i), c(j), c(k)]), 0.5, 0);
            }
        }
    }
    bed.push(Vector([20.5, 20.5, 30.0]), 0.5, 0);
    // 1600 columns of side 1: the spike lifts the mean top by 20.5 / 1600.
    let surface = surface_height(&bed);
    assert!(
        (surface - (10.0 + 20.5 / 1600.0)).abs() < 1e-12,
        "{surface}"
    );
    let reg = bulk_region(&bed).unwrap();
    assert!((reg.hi[2] - (surface - 3.0)).abs() < 1e-12);
    // The highest top would have put the region's top at 27.5, above the bed.
    assert!(reg.hi[2] < 7.1);
    let (_, s) = analyze(&bed, 1e-6);
    let bulk = s.packing.as_ref().unwrap().bulk.unwrap();
    // The region cuts the top layer off the lattice planes: within 0.3 %.
    assert!((bulk - std::f64::consts::PI / 6.0).abs() < 3e-3, "{bulk}");
}

#[test]
fn a_bulk_of_a_few_bodies_is_null_with_its_reason() {
    // The source study's 3D box with radii 10 and 50 has a bulk of a few bodies.
    let c = config(
        "dim = 3\nseed = 1\n[box]\npreset = \"thesis\"\n[[species]]\nradius = 10\n[[species]]\nradius = 50\n",
    );
    let run = packbed::run_bed(&c, &mut |_| {}).unwrap();
    let v = serde_json::to_value(&run.summary).unwrap();
    let p = &v["packing"];
    assert!(p["bulk"].is_null(), "{p}");
    assert!(v["coordination"]["mean_bulk"].is_null());
    let n = p["bulk_bodies"].as_u64().unwrap();
    assert!(n > 0 && n < 50, "{n}");
    assert!(p["bulk_note"].as_str().unwrap().contains("minimum of 50"));
    // The minimum is a setting.
    let mut c = c;
    c.analysis.bulk_min_bodies = 0;
    let run = packbed::run_bed(&c, &mut |_| {}).unwrap();
    let v = serde_json::to_value(&run.summary).unwrap();
    let bulk = v["packing"]["bulk"].as_f64().expect("a bulk value");
    assert!(bulk > 0.0 && bulk < 1.0, "{bulk}");
    assert!(v["packing"].get("bulk_note").is_none());
}

// ---------------------------------------------------------------------------
// 15. Percolation in 3D: per direction and summed; lengths agree with the shortest
// ---------------------------------------------------------------------------

#[test]
fn disjoint_chains_are_reported_per_direction_and_summed() {
    use packbed::Container;
    use packbed::Vector;
    // One layer of unit spheres on a 10 × 6 square lattice: 6 rows span x, 10 columns span y.
    let mut bed: Bed<3> = Bed::new(
        Container {
            size: Vector([10.0, 6.0, 5.0]),
            periodic: false,
        },
        Vec::new(),
    );
    for i in 0..10 {
        for j in 0..6 {
            bed.push(Vector([i as f64 + 0.5, j as f64 + 0.5, 0.5]), 0.5, 0);
        }
    }
    let p = analyze(&bed, 1e-9).1.percolation.unwrap();
    let per: Vec<(String, u64)> = p
        .directions
        .iter()
        .map(|d| (d.axis.clone(), d.disjoint_chains))
        .collect();
    assert_eq!(per, vec![("x".into(), 6), ("y".into(), 10)]);
    assert_eq!(p.disjoint_chains, 10);
    assert_eq!(p.disjoint_chains_sum, 16);
    let v = serde_json::to_value(&p).unwrap();
    assert_eq!(v["disjoint_chains_sum"], 16);
}

#[test]
fn enumerated_chain_lengths_never_undercut_nor_skip_the_shortest_chain() {
    use packbed::find_contacts;
    use packbed::{percolation, PercolationOptions};
    // With the enumeration capped at a few chains, the first chains met used to
    // be longer than the breadth-first shortest ("shortest 47, lengths 50-250").
    let mut checked = 0;
    for seed in 1..=12 {
        let c = config(&format!(
            "dim = 2\nseed = {seed}\n[box]\nwidth = 300\nheight = 200\n[[species]]\nradius = 10\n"
        ));
        let (b, _) = run::<2>(&c);
        let contacts = find_contacts(&b, 1e-6);
        for max_chains in [1, 3] {
            let opts = PercolationOptions {
                max_chains,
                ..PercolationOptions::default()
            };
            let p = percolation(&b, &contacts, &opts);
            if let Some(shortest) = p.shortest_chain {
                let l = p.chain_length.expect("a chain was enumerated");
                assert_eq!(l.min, shortest, "seed {seed}, max_chains {max_chains}");
                checked += 1;
            }
        }
    }
    assert!(checked >= 6, "only {checked} beds percolated");
}
