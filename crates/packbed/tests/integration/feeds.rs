//! `[[feeds]]`: one bed from several feeds in sequence, each with its own
//! species, count and settling rule.

use crate::common::{assert_checked, config, run, TOL};
use packbed::find_contacts;
use packbed::Bed;
use packbed::Config;
use packbed::DepositReport;
use packbed::InvariantChecks;

const BOX: &str =
    "dim = 3\nseed = 11\n[box]\nwidth = 24\ndepth = 24\nheight = 3000\nperiodic = true\n\
                   [fill]\nbase_layer = \"none\"\n";

/// A precoat of coarse spheres settled with momentum, then a two-species
/// slurry of fines that stick by the cohesion law.
fn precoat_and_slurry() -> String {
    format!(
        "{BOX}[[species]]\nname = \"sand\"\nsize = {{ dist = \"lognormal\", median = 2.0, gsd = 1.2 }}\n\
         [[species]]\nname = \"fines\"\nsize = {{ dist = \"lognormal\", median = 0.6, gsd = 1.3 }}\n\
         [[species]]\nname = \"rods\"\nradius = 0.5\nshape = \"chain\"\nbeads = 3\nratio = 0.25\n\
         [[feeds]]\nspecies = [\"sand\"]\ncount = 300\nsettling = {{ restitution = 0.5 }}\n\
         [[feeds]]\nspecies = [\"fines\", \"rods\"]\ncount = 1500\n\
         settling = {{ cohesion_diameter = 1.0, cohesion_exponent = 0.7 }}\n"
    )
}

fn deposit_on(threads: usize, c: &Config) -> (Bed<3>, DepositReport) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| run::<3>(c))
}

#[test]
fn feeds_place_their_counts_in_turn_from_their_own_species() {
    let c = config(&precoat_and_slurry());
    let (b, report) = run::<3>(&c);
    // Counts are particles, a chain's beads each (as `fill.count`): the
    // 300 spheres of the first feed, then 1500 particles of the second,
    // its last chain perhaps reaching past by up to two beads.
    assert!((1800..1803).contains(&b.len()), "{}", b.len());
    // Bodies in deposition order: the first feed's, then the second's.
    let mut body_species = Vec::new();
    for i in 0..b.len() {
        if i == 0 || b.bodies[i] != b.bodies[i - 1] {
            body_species.push(b.species[i]);
        }
    }
    assert_eq!(body_species.len() as u64, report.dropped);
    assert!(body_species[..300].iter().all(|&s| s == 0));
    assert!(body_species[300..].iter().all(|&s| s == 1 || s == 2));
    let rods = body_species.iter().filter(|&&s| s == 2).count();
    let fines = body_species.iter().filter(|&&s| s == 1).count();
    // A 1 : 0.25 ratio of bodies, within sampling.
    let share = rods as f64 / (rods + fines) as f64;
    assert!((share - 0.2).abs() < 0.04, "{rods} rods, {fines} fines");
    let feeds: Vec<_> = b.species_info.iter().map(|s| s.feed).collect();
    assert_eq!(feeds, [Some(0), Some(1), Some(1)]);
    // The ratios say each species' share of the bed in bodies: 300 sand;
    // the second feed's 1,500 particles are 1,500 / 1.4 bodies (a body is
    // 0.8 × 1 + 0.2 × 3 beads on average), 0.8 of them fines, 0.2 rods.
    // (They were once its particles split by ratio, 1,200 and 300, which
    // counted each rod's beads as bodies in the requested size distribution.)
    let ratios: Vec<_> = b.species_info.iter().map(|s| s.ratio).collect();
    let bodies = 1500.0 / 1.4;
    assert!((ratios[0] - 300.0).abs() < 1e-9, "{ratios:?}");
    assert!((ratios[1] - 0.8 * bodies).abs() < 1e-9, "{ratios:?}");
    assert!((ratios[2] - 0.2 * bodies).abs() < 1e-9, "{ratios:?}");
    // Every particle at rest by the loosest rule of the bed (sticking).
    let checks = InvariantChecks::new(TOL).held_by(&c.plan::<3>().unwrap().feeds[1].settling);
    assert_checked(&b, &checks, "feeds");
}

#[test]
fn feeds_build_the_same_bed_on_any_number_of_threads() {
    let c = config(&precoat_and_slurry());
    let (one, _) = deposit_on(1, &c);
    let (three, _) = deposit_on(3, &c);
    assert_eq!(one.centres, three.centres);
    assert_eq!(one.species, three.species);
}

#[test]
fn one_feed_is_the_bed_of_fill_and_settling_bit_for_bit() {
    let species = "[[species]]\nname = \"a\"\nradius = 1\n";
    for rule in ["", "sticking = 0.3", "restitution = 0.4"] {
        let plain = config(&format!(
            "{}{species}[settling]\n{rule}\n",
            BOX.replace("[fill]\n", "[fill]\ncount = 900\n")
        ));
        let fed = config(&format!(
            "{BOX}{species}[[feeds]]\nspecies = [\"a\"]\ncount = 900\nsettling = {{ {} }}\n",
            rule.replace('\n', ", ")
        ));
        let (a, _) = run::<3>(&plain);
        let (b, _) = run::<3>(&fed);
        assert_eq!(a.centres, b.centres, "{rule}");
    }
}

#[test]
fn the_second_feed_settles_by_its_own_rule() {
    // Hit-and-stick fines on a rolled precoat: the fines' bulk coordination
    // is far below the precoat's, whose particles rest on three supports.
    let text = format!(
        "{BOX}[[species]]\nname = \"coarse\"\nradius = 1\n[[species]]\nname = \"fine\"\nradius = 1\n\
         [[feeds]]\nspecies = [\"coarse\"]\ncount = 1500\n\
         [[feeds]]\nspecies = [\"fine\"]\ncount = 1500\nsettling = {{ contacts = 1 }}\n"
    );
    let (b, _) = run::<3>(&config(&text));
    let z = |s: u32| {
        let ids: Vec<usize> = (0..b.len()).filter(|&i| b.species[i] == s).collect();
        let contacts = find_contacts(&b, 1e-9);
        let mut n = vec![0usize; b.len()];
        for c in &contacts.pairs {
            n[c.i as usize] += 1;
            n[c.j as usize] += 1;
        }
        ids.iter().map(|&i| n[i] as f64).sum::<f64>() / ids.len() as f64
    };
    let (coarse, fine) = (z(0), z(1));
    assert!(coarse > 4.5 && fine < 2.6, "Z coarse {coarse}, fine {fine}");
}

#[test]
fn bad_feeds_are_refused_in_one_line() {
    let species =
        "[[species]]\nname = \"a\"\nradius = 1\n[[species]]\nname = \"b\"\nradius = 0.5\n";
    for (feeds, needle) in [
        ("[[feeds]]\nspecies = [\"a\"]\ncount = 10\n", "species `b` is in no"),
        (
            "[[feeds]]\nspecies = [\"a\", \"b\"]\ncount = 10\n[[feeds]]\nspecies = [\"b\"]\ncount = 5\n",
            "fed by feeds[0] already",
        ),
        (
            "[[feeds]]\nspecies = [\"a\", \"c\"]\ncount = 10\n",
            "no species is named `c`",
        ),
        (
            "[[feeds]]\nspecies = [\"a\", \"b\"]\ncount = 0\n",
            "feeds[0].count",
        ),
        ("[[feeds]]\nspecies = []\ncount = 3\n", "feeds[0].species is empty"),
        (
            "[[feeds]]\nspecies = [\"a\", \"b\"]\ncount = 3\nsettling = { sticking = 2 }\n",
            "settling.sticking",
        ),
    ] {
        let text = format!("{BOX}{species}{feeds}");
        let e = config(&text).plan::<3>().unwrap_err().to_string();
        assert!(e.contains(needle), "{feeds}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
    let counted = format!(
        "{}{species}[[feeds]]\nspecies = [\"a\", \"b\"]\ncount = 3\n",
        BOX.replace("[fill]\n", "[fill]\ncount = 9\n")
    );
    let e = config(&counted).plan::<3>().unwrap_err().to_string();
    assert!(e.contains("remove fill.count"), "{e}");
}

/// A precoat by count, then the slurry by mass per area (kg/m²) in a box of
/// 24 × 24 µm: `mass` kg/m² of fines and rods.
fn by_mass(mass: &str) -> String {
    precoat_and_slurry().replace("count = 1500", &format!("mass_per_area = {mass}"))
        + "[analysis]\nlength_unit = \"um\"\nsolid_density = 2500\n"
}

/// The solids of feed 1 in `b` (each bead whole), kg per m² of the box,
/// and the mass of its last body.
fn fed_mass(b: &Bed<3>) -> (f64, f64) {
    let (unit, rho, area) = (1e-6, 2500.0, 24.0 * 24.0);
    let mass = |i: usize| rho * 4.0 / 3.0 * std::f64::consts::PI * (b.radii[i] * unit).powi(3);
    let per_area = |m: f64| m / (area * unit * unit);
    let second: Vec<usize> = (0..b.len())
        .filter(|&i| b.species_info[b.species[i] as usize].feed == Some(1))
        .collect();
    let total: f64 = second.iter().map(|&i| mass(i)).sum();
    let last_body = b.bodies[*second.last().unwrap()];
    let last: f64 = second
        .iter()
        .filter(|&&i| b.bodies[i] == last_body)
        .map(|&i| mass(i))
        .sum();
    (per_area(total), per_area(last))
}

#[test]
fn a_feed_by_mass_ends_with_the_body_that_reaches_its_mass() {
    for mass in ["0.002", "0.005"] {
        let m: f64 = mass.parse().unwrap();
        let c = config(&by_mass(mass));
        let (b, _) = run::<3>(&c);
        let (fed, last) = fed_mass(&b);
        // At least the mass asked, and short of it without the last body.
        assert!(
            fed >= m && fed - last < m,
            "{mass}: fed {fed}, last body {last}"
        );
        let checks = InvariantChecks::new(TOL).held_by(&c.plan::<3>().unwrap().feeds[1].settling);
        assert_checked(&b, &checks, "a feed by mass");
    }
    // The same bed by mass on one thread and on three (the speculative
    // batches stop where the serial engine does).
    let c = config(&by_mass("0.005"));
    let (one, _) = deposit_on(1, &c);
    let (three, _) = deposit_on(3, &c);
    assert_eq!(one.centres, three.centres);
    assert_eq!(one.radii, three.radii);
}

#[test]
fn bad_feed_amounts_are_refused_in_one_line() {
    let both = by_mass("0.002").replace("mass_per_area", "count = 10\nmass_per_area");
    let cases = [
        (by_mass("-1"), "must be a positive number of kg per m²"),
        (by_mass("0"), "must be a positive number of kg per m²"),
        (both, "not both"),
        (
            precoat_and_slurry().replace("count = 1500", "mass_per_area = 0.002"),
            "set analysis.length_unit and analysis.solid_density",
        ),
        (
            precoat_and_slurry().replace("count = 1500", ""),
            "count must be at least 1 (or give",
        ),
    ];
    for (text, expect) in cases {
        let e = config(&text).plan::<3>().unwrap_err().to_string();
        assert!(e.contains(expect) && !e.contains('\n'), "{e}");
    }
}
