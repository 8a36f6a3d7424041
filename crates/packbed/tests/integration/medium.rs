//! A filter medium (`[[feeds]]` with `medium = true`): the later feeds fall
//! through its openings to the open floor and leave as filtrate, lodge
//! inside it, or form the cake; the capture per size class.

use crate::common::{assert_checked, config, run, TOL};
use packbed::capture;
use packbed::Bed;
use packbed::Config;
use packbed::DepositReport;
use packbed::InvariantChecks;

const BOX: &str =
    "dim = 3\nseed = 5\n[box]\nwidth = 24\ndepth = 24\nheight = 3000\nperiodic = true\n\
                   [fill]\nbase_layer = \"none\"\n";

/// A medium of `medium` spheres of radius `r_medium`, then a slurry of
/// `slurry` lognormal spheres of median radius `r_slurry`.
fn filter(medium: u64, r_medium: f64, slurry: u64, r_slurry: f64) -> String {
    format!(
        "{BOX}[[species]]\nname = \"medium\"\nradius = {r_medium}\n\
         [[species]]\nname = \"slurry\"\nsize = {{ dist = \"lognormal\", median = {r_slurry}, gsd = 1.6 }}\n\
         [[feeds]]\nspecies = [\"medium\"]\ncount = {medium}\nmedium = true\n\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = {slurry}\n"
    )
}

fn on(threads: usize, c: &Config) -> (Bed<3>, DepositReport) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| run::<3>(c))
}

/// Medium species flags of `b`: species 0 is the medium in these beds.
fn medium_flags(b: &Bed<3>) -> Vec<bool> {
    (0..b.species_info.len()).map(|s| s == 0).collect()
}

/// The capture of `b`, whose species 0 is the medium.
fn capture_of(b: &Bed<3>, report: &DepositReport) -> packbed::CaptureSummary {
    capture(
        b,
        &medium_flags(b),
        &report.filtrate,
        report.medium_lift,
        None,
    )
    .unwrap()
}

#[test]
fn fed_is_passed_plus_lodged_plus_cake_and_the_medium_stands_clear_of_the_floor() {
    let c = config(&filter(400, 1.5, 3000, 0.25));
    let (b, report) = run::<3>(&c);
    let cap = capture_of(&b, &report);
    // Every slurry body fed is in exactly one place.
    assert_eq!(cap.fed, 3000);
    assert_eq!(cap.passed + cap.lodged + cap.cake, cap.fed);
    assert_eq!(cap.passed as usize, report.filtrate.len());
    assert!(cap.passed > 0 && cap.lodged > 0 && cap.cake > 0, "{cap:?}");
    let slurry_in_bed = b.species.iter().filter(|&&s| s == 1).count() as u64;
    assert_eq!(slurry_in_bed, cap.lodged + cap.cake);
    assert_eq!(cap.medium_bodies, 400);
    let by_class: u64 = cap.classes.iter().map(|c| c.fed).sum();
    assert_eq!(by_class, cap.fed);
    let lodged: u64 = cap.depth_profile.iter().map(|d| d.lodged).sum();
    assert_eq!(lodged, cap.lodged);
    // The medium was lifted by the largest slurry diameter (the lognormal's
    // upper bound), and nothing in the bed reaches below half of it: the
    // filtrate rests on the floor, out of the bed.
    let d_max = 2.0 * c.plan::<3>().unwrap().species[1].size.bounds().1;
    assert_eq!(report.medium_lift, d_max);
    assert!(
        (cap.medium_bottom - d_max).abs() < 1e-9,
        "{}",
        cap.medium_bottom
    );
    let lowest = (0..b.len())
        .map(|i| b.centres[i][2] - b.radii[i])
        .fold(f64::INFINITY, f64::min);
    assert!(lowest > 0.5 * d_max, "{lowest}");
    // No overlaps, nothing through a wall. (The rest test does not apply:
    // the medium's bottom rested on the floor before it was lifted; it
    // stands fixed, as a filter medium is held.)
    let checks = InvariantChecks {
        rest: false,
        ..InvariantChecks::new(TOL)
    };
    assert_checked(&b, &checks, "medium bed");
    // What passed is finer than what the medium holds: its mean size is
    // below the fed mean.
    let mean = |v: &mut dyn Iterator<Item = f64>| {
        let (s, n) = v.fold((0.0, 0), |a, x| (a.0 + x, a.1 + 1));
        s / n as f64
    };
    // The retention criteria from the sizes: D15 of the medium by mass
    // (equal spheres: their diameter), d85 of everything fed after it.
    let crit = cap.criteria.as_ref().expect("criteria");
    assert!((crit.medium_d15 - 3.0).abs() < 1e-12, "{crit:?}");
    let mut fed: Vec<f64> = (0..b.len())
        .filter(|&i| b.species[i] == 1)
        .map(|i| 2.0 * b.radii[i])
        .chain(report.filtrate.iter().map(|f| 2.0 * f.radius))
        .collect();
    fed.sort_by(f64::total_cmp);
    let total: f64 = fed.iter().map(|d| d.powi(3)).sum();
    let mut acc = 0.0;
    let d85 = *fed
        .iter()
        .find(|d| {
            acc += d.powi(3);
            acc >= 0.85 * total
        })
        .unwrap();
    assert_eq!(crit.slurry_d85, d85);
    assert!((crit.terzaghi_ratio - 3.0 / d85).abs() < 1e-12);
    assert!((crit.kenney_constriction - 0.6).abs() < 1e-12);
    // The medium's constrictions: positive, ordered, d_c35 not below the
    // tightest throat of its spheres (three touching: 0.155 D, less a
    // tenth for the merged and clipped cells) and below their diameter.
    let c = crit.constriction_diameter;
    assert!(
        0.0 < c[0] && c[0] <= c[1] && c[1] <= c[2] && c[2] <= c[3],
        "{c:?}"
    );
    assert!(c[1] > 0.155 * 3.0 * 0.9 && c[1] < 3.0, "{c:?}");
    assert!((crit.indraratna_ratio - c[1] / crit.slurry_d85_by_surface).abs() < 1e-12);
    // The full distribution (`constrictions.csv`) holds every slurry body
    // fed, and its throats: at each percentile's class the fraction finer
    // passes the percentile's share, one class below it does not.
    let classes = &cap.constrictions;
    assert!(!classes.is_empty());
    let slurry: u64 = classes.iter().map(|k| k.slurry).sum();
    assert_eq!(slurry, fed.len() as u64);
    assert_eq!(classes.last().unwrap().constrictions_finer, 1.0);
    assert_eq!(classes.last().unwrap().slurry_finer, 1.0);
    let throats: u64 = classes.iter().map(|k| k.constrictions).sum();
    for (q, d) in [(0.10, c[0]), (0.35, c[1]), (0.50, c[2]), (0.90, c[3])] {
        let k = classes
            .iter()
            .position(|k| d < k.d_hi)
            .unwrap_or(classes.len() - 1);
        // by_number picks entry round((n − 1) q) of the sorted throats.
        let rank = ((throats - 1) as f64 * q).round() + 1.0;
        let below = if k == 0 {
            0.0
        } else {
            classes[k - 1].constrictions_finer
        };
        assert!(
            classes[k].constrictions_finer * throats as f64 >= rank - 1e-9
                && below * throats as f64 <= rank - 1.0 + 1e-9,
            "{q}: {d} in class {k}"
        );
    }
    let finer = fed.iter().filter(|&&d| d < classes[3].d_hi).count();
    assert!((classes[3].slurry_finer - finer as f64 / fed.len() as f64).abs() < 1e-12);
    let passed = mean(&mut report.filtrate.iter().map(|f| f.radius));
    let held = mean(
        &mut (0..b.len())
            .filter(|&i| b.species[i] == 1)
            .map(|i| b.radii[i]),
    );
    assert!(passed < held, "passed {passed}, held {held}");
}

#[test]
fn the_filtrate_is_the_same_on_any_number_of_threads() {
    let c = config(&filter(300, 1.5, 2000, 0.3));
    let (one, r1) = on(1, &c);
    let (three, r3) = on(3, &c);
    assert_eq!(one.centres, three.centres);
    assert_eq!(r1.filtrate, r3.filtrate);
    assert!(!r1.filtrate.is_empty());
}

#[test]
fn a_medium_of_lone_spheres_holds_nothing() {
    // Four spheres far apart: a fine rolls off any one of them, finds no
    // three supports and reaches the floor.
    let c = config(&filter(4, 2.0, 300, 0.3));
    let (b, report) = run::<3>(&c);
    let cap = capture_of(&b, &report);
    assert_eq!((cap.passed, cap.lodged, cap.cake), (300, 0, 0), "{cap:?}");
    assert_eq!(b.len(), 4);
    assert!(cap
        .classes
        .iter()
        .all(|c| c.grade_efficiency.unwrap_or(0.0) == 0.0));
    assert!(cap.x50.is_none() && cap.note.as_deref().unwrap().contains("above the largest"));
}

#[test]
fn a_dense_medium_passes_fines_below_its_throats_when_they_carry_momentum() {
    // Equal spheres of diameter D = 3 settled by rolling: the tightest
    // throat of a close packing, three touching spheres, passes a sphere of
    // (2/√3 − 1) D = 0.155 D. Fines that bounce (restitution 0.5) pass the
    // medium's throats down to about there: the cut lies near 0.155 D.
    // Fines that roll quasi-statically stop in the first pocket of three
    // supports they meet, so the rolling cut lies far below it.
    let d = 3.0;
    let text = filter(600, 0.5 * d, 4000, 0.2);
    let x50 = |text: &str| {
        let (b, report) = run::<3>(&config(text));
        let cap = capture_of(&b, &report);
        let first = cap.classes.first().unwrap().grade_efficiency.unwrap();
        let last = cap.classes.last().unwrap().grade_efficiency.unwrap();
        assert!(first < 0.5 && last == 1.0, "{first} {last}");
        cap.x50.unwrap()
    };
    let bouncing = x50(&format!("{text}settling = {{ restitution = 0.5 }}\n"));
    let throat = (2.0 / 3f64.sqrt() - 1.0) * d;
    assert!(
        (bouncing / throat - 1.0).abs() < 0.25,
        "x50 {bouncing}, throat {throat}"
    );
    let rolling = x50(&text);
    assert!(
        rolling < 0.5 * bouncing,
        "rolling {rolling}, bouncing {bouncing}"
    );
}

#[test]
fn a_medium_fed_last_or_after_the_slurry_is_refused() {
    let species =
        "[[species]]\nname = \"a\"\nradius = 1\n[[species]]\nname = \"b\"\nradius = 0.5\n";
    for (feeds, needle) in [
        (
            "[[feeds]]\nspecies = [\"a\"]\ncount = 10\nmedium = true\n[[feeds]]\nspecies = [\"b\"]\ncount = 5\nmedium = true\n",
            "every feed is a medium",
        ),
        (
            "[[feeds]]\nspecies = [\"a\"]\ncount = 10\n[[feeds]]\nspecies = [\"b\"]\ncount = 5\nmedium = true\n",
            "the medium's feeds come first",
        ),
    ] {
        let e = config(&format!("{BOX}{species}{feeds}"))
            .plan::<3>()
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{feeds}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
}
