//! `[compaction]`: a settled bed lowered collectively toward a frictionless
//! DEM pour. Each compacted bed is checked by brute force (no overlap beyond
//! 10⁻⁹ of a radius) and by the independent checker (nothing outside the
//! box, spheres held up by compressive forces of their contacts), and
//! measured against the same bed settled without it.

use crate::common::{config, run, TOL};
use packbed::{analyze, Bed, CompactionStop, InvariantChecks, Real, Supports};

/// The bed of `text` with and without `[compaction]` (the table's keys in
/// `compaction`): bulk φ and mean Z of each, and the compacted bed.
fn with_and_without<const D: usize>(text: &str, compaction: &str) -> ([(Real, Real); 2], Bed<D>) {
    let settled = config(text);
    let compacted = config(&format!("{text}\n[compaction]\n{compaction}\n"));
    let measure = |b: &Bed<D>| {
        let (_, s) = analyze(b, settled.analysis.contact_tol);
        (
            s.packing.unwrap().bulk.expect("bulk"),
            s.coordination.unwrap().mean_bulk.expect("bulk"),
        )
    };
    let (before, _) = run::<D>(&settled);
    let (after, report) = run::<D>(&compacted);
    let c = report.compaction.expect("a compaction report");
    eprintln!("{c:?}");
    assert!(
        [CompactionStop::Until, CompactionStop::Steps].contains(&c.stopped_by),
        "{c:?}"
    );
    ([measure(&before), measure(&after)], after)
}

/// Held collectively: every sphere's weight within the cone of its contact
/// normals (a later sphere may hold an earlier one up), with a residual of
/// at most 10⁻⁶ of the weight; contacts closed to the analysis's tolerance
/// (10⁻⁶ of a radius). Overlaps are checked exactly by [`deepest_overlap`].
fn collectively_held() -> InvariantChecks {
    InvariantChecks {
        supports: Supports::All,
        rest_tol: 1e-6,
        ..InvariantChecks::new(1e-6)
    }
}

/// Checks `bed` (no overlap, nothing outside) and returns the share of its
/// spheres held collectively (see [`collectively_held`]).
fn held_share<const D: usize>(bed: &Bed<D>, what: &str) -> Real {
    let rep = packbed::check_bed_with(bed, &collectively_held());
    eprintln!("{what}: {rep}");
    assert_eq!(rep.invalid + rep.overlaps + rep.outside, 0, "{what}: {rep}");
    assert!(
        deepest_overlap(bed) <= TOL,
        "{what}: {}",
        deepest_overlap(bed)
    );
    1.0 - rep.not_at_rest as Real / rep.bodies as Real
}

/// The deepest overlap of any pair (or with the floor), relative to the
/// smaller radius, by brute force over every pair and periodic image: 0 if
/// none overlaps.
fn deepest_overlap<const D: usize>(b: &Bed<D>) -> Real {
    let mut deepest: Real = 0.0;
    for i in 0..b.len() {
        deepest = deepest.max((b.radii[i] - b.centres[i][D - 1]) / b.radii[i]);
        for j in 0..i {
            let d = b.container.displacement(&b.centres[i], &b.centres[j]);
            let contact = b.radii[i] + b.radii[j];
            let overlap = (contact - d.norm()) / b.radii[i].min(b.radii[j]);
            deepest = deepest.max(overlap);
        }
    }
    deepest
}

#[test]
fn compaction_packs_equal_spheres_denser_without_an_overlap() {
    let text = "dim = 3\nseed = 1\n[box]\nwidth = 6\ndepth = 6\nheight = 100\nperiodic = true\n\
                [fill]\ncount = 600\nbase_layer = \"none\"\n[[species]]\nradius = 0.5\n";
    let ([(phi0, z0), (phi1, z1)], bed) = with_and_without::<3>(text, "");
    eprintln!("settled φ {phi0:.4} Z {z0:.3}; compacted φ {phi1:.4} Z {z1:.3}");
    // Measured: 0.583 → 0.634 (a frictionless DEM pour of 4,000: 0.642),
    // Z 6.02 → 6.02 (isostatic: 6).
    assert!(phi0 < 0.60 && phi1 > 0.625, "{phi0} → {phi1}");
    assert!((z1 - 6.0).abs() < 0.3, "{z1}");
    // Every sphere held (measured: residual 4·10⁻¹⁵ of a weight).
    assert_eq!(held_share(&bed, "compacted 3D"), 1.0);
}

#[test]
fn friction_in_the_compaction_reaches_a_frictional_pour() {
    // The bed of the test above compacted with `friction = 0.05`: contacts
    // slide only where the slide's slope beats µ, so the bed stops looser
    // and with fewer contacts than without friction, and it comes to rest
    // (stopped by `until`, not by the budget). Measured: φ 0.583 → 0.606,
    // Z 6.01 → 5.31, 259 steps; a LAMMPS pour of the same spheres at
    // µ = 0.3: φ 0.609, Z 5.17 (docs/settling.md).
    let text = "dim = 3\nseed = 1\n[box]\nwidth = 6\ndepth = 6\nheight = 100\nperiodic = true\n\
                [fill]\ncount = 600\nbase_layer = \"none\"\n[[species]]\nradius = 0.5\n";
    let compacted = config(&format!("{text}\n[compaction]\nfriction = 0.05\n"));
    let (bed, report) = run::<3>(&compacted);
    let c = report.compaction.expect("a compaction report");
    eprintln!("{c:?}");
    assert_eq!(c.stopped_by, CompactionStop::Until, "{c:?}");
    let (_, s) = analyze(&bed, compacted.analysis.contact_tol);
    let phi = s.packing.unwrap().bulk.expect("bulk");
    let z = s.coordination.unwrap().mean_bulk.expect("bulk");
    eprintln!("compacted with µ 0.05: φ {phi:.4} Z {z:.3}");
    assert!(phi > 0.595 && phi < 0.62, "{phi}");
    assert!(z > 4.8 && z < 5.7, "{z}");
    assert!(deepest_overlap(&bed) <= TOL, "{}", deepest_overlap(&bed));
    // Not the frictionless rest test: friction holds some spheres off the
    // cone of their contact normals.
    let no_rest = InvariantChecks {
        rest: false,
        ..InvariantChecks::new(1e-6)
    };
    let rep = packbed::check_bed_with(&bed, &no_rest);
    assert_eq!(rep.invalid + rep.overlaps + rep.outside, 0, "{rep}");
}

#[test]
fn compaction_packs_discs_denser_without_an_overlap() {
    let text = "dim = 2\nseed = 1\n[box]\nwidth = 20.3\nheight = 200\nperiodic = true\n\
                [fill]\ncount = 400\nbase_layer = \"none\"\n[[species]]\nradius = 0.5\n";
    let ([(phi0, z0), (phi1, z1)], bed) = with_and_without::<2>(text, "");
    eprintln!("settled φ {phi0:.4} Z {z0:.3}; compacted φ {phi1:.4} Z {z1:.3}");
    // Measured: 0.833 → 0.898 (the hexagonal packing: 0.9069; discs order).
    assert!(phi0 < 0.86 && phi1 > 0.89, "{phi0} → {phi1}");
    assert_eq!(held_share(&bed, "compacted 2D"), 1.0);
}

#[test]
fn compaction_packs_a_lognormal_bed_denser_without_an_overlap() {
    let text = "dim = 3\nseed = 2\n[box]\nwidth = 6\ndepth = 6\nheight = 100\nperiodic = true\n\
                [fill]\ncount = 500\nbase_layer = \"none\"\n\
                [[species]]\nsize = { dist = \"lognormal\", median = 0.5, gsd = 1.3 }\n";
    let ([(phi0, z0), (phi1, z1)], bed) = with_and_without::<3>(text, "");
    eprintln!("settled φ {phi0:.4} Z {z0:.3}; compacted φ {phi1:.4} Z {z1:.3}");
    assert!(phi1 > phi0 + 0.03, "{phi0} → {phi1}");
    // Measured: one sphere of 500 still creeping after the 1,000 steps
    // (residual 0.05 of its weight), the rest held.
    assert!(held_share(&bed, "compacted lognormal") >= 0.99);
}

#[test]
fn compaction_refuses_chains_rsa_and_bad_steps_in_one_line() {
    let base = "dim = 3\n[fill]\ncount = 10\n";
    for (text, says) in [
        (
            "[[species]]\nradius = 1\nshape = \"chain\"\nbeads = 3\n[compaction]\n",
            "a rigid chain's rotations",
        ),
        ("mode = \"rsa\"\n", "mode = \"rsa\""),
        ("[compaction]\nstep = 0.5\n", "compaction.step must be"),
        ("[compaction]\nuntil = -1\n", "compaction.until must be"),
        (
            "[compaction]\nfriction = -0.1\n",
            "compaction.friction must be",
        ),
        ("[compaction]\nsteps = 3\nshake = 1\n", "shake"),
    ] {
        let text = if text.starts_with("mode") {
            format!("{text}{base}[compaction]\n")
        } else {
            format!("{base}{text}")
        };
        let e = packbed::Config::from_toml(&text, "test")
            .and_then(|c| c.plan::<3>().map(|_| ()))
            .expect_err(&text)
            .to_string();
        assert!(e.contains(says) && !e.contains('\n'), "{text}: {e}");
    }
}
