//! The drainage against closed forms, invariants and bad input.

use super::*;
use crate::analysis::pores::network::network;
use crate::{run_bed, Config};

/// Touching spheres of radius 1 on a simple cubic lattice, periodic sides.
fn simple_cubic(n: usize, layers: usize) -> Bed<3> {
    super::super::tests::simple_cubic(n, layers, 1.0)
}

fn deposited(count: u64, seed: u64, radius: &str) -> Bed<3> {
    let text = format!(
        "dim = 3\nseed = {seed}\n[box]\nwidth = 12\ndepth = 12\nheight = 400\nperiodic = true\n\
         [fill]\ncount = {count}\n[[species]]\nradius = {radius}\n"
    );
    let config = Config::from_toml(&text, "test").unwrap();
    match run_bed(&config, &mut |_| {}).unwrap().bed {
        crate::bed::AnyBed::D3(b) => b,
        crate::bed::AnyBed::D2(_) => unreachable!(),
    }
}

/// The network's pores in the slab (flags), their indices, and their void
/// volumes times `scale`.
fn slab_pores(
    net: &crate::analysis::pores::network::Network<3>,
    slab: (Real, Real),
    scale: Real,
) -> (Vec<bool>, Vec<u32>, Vec<Real>) {
    let in_slab: Vec<bool> = net
        .pores
        .iter()
        .map(|p| p.centre[2] >= slab.0 && p.centre[2] <= slab.1)
        .collect();
    let members: Vec<u32> = (0..net.pores.len() as u32)
        .filter(|&p| in_slab[p as usize])
        .collect();
    let voids: Vec<Real> = members
        .iter()
        .map(|&p| scale * net.pores[p as usize].void_volume.max(0.0))
        .collect();
    (in_slab, members, voids)
}

fn drain_bed(bed: &Bed<3>, slab: (Real, Real), o: &DrainageOptions) -> Drainage {
    let net = network(bed, slab).unwrap();
    drain(bed, &net, slab, 2.0, None, o).unwrap()
}

/// Every throat of a touching simple cubic array that gas must pass is a
/// square face of four spheres, whose inscribed circle has radius
/// `(√2 − 1) R`: the gas breaks through at `P_c R / γ = 2 / (√2 − 1)`.
#[test]
fn simple_cubic_breaks_through_at_its_square_faces() {
    let bed = simple_cubic(4, 12);
    let o = DrainageOptions {
        entry: EntryModel::Inscribed,
        ..DrainageOptions::default()
    };
    // Cube centres sit at even heights; the slab holds whole cubes.
    let d = drain_bed(&bed, (5.0, 17.0), &o);
    let bt = d.summary.breakthrough.unwrap().reduced / 2.0; // P_c R / γ
    let exact = 2.0 / (2f64.sqrt() - 1.0);
    assert!((bt - exact).abs() < 1e-9 * exact, "{bt} against {exact}");
    // Below it the slab is full, above it nothing but bridges is left
    // (no cube is cut off: each drains through its faces).
    let full = d
        .curve
        .iter()
        .find(|p| p.pc_reduced < 2.0 * exact * 0.99)
        .unwrap();
    assert!((full.saturation - 1.0).abs() < 1e-12);
}

#[test]
fn the_curve_is_monotone_and_the_liquid_is_accounted_for() {
    let bed = deposited(1500, 3, "1.0");
    let slab = (4.0, 16.0);
    for trapping in [true, false] {
        let o = DrainageOptions {
            trapping,
            ..DrainageOptions::default()
        };
        let d = drain_bed(&bed, slab, &o);
        assert!(d.summary.breakthrough.is_some());
        for w in d.curve.windows(2) {
            assert!(w[1].pc_reduced > w[0].pc_reduced);
            assert!(w[1].saturation <= w[0].saturation + 1e-12, "{:?}", w);
            assert!(w[1].trapped + 1e-12 >= w[0].trapped);
        }
        for p in &d.curve {
            let parts = p.connected + p.trapped + p.pendular;
            assert!((parts - p.saturation).abs() < 1e-12);
            assert!((0.0..=1.0 + 1e-12).contains(&p.saturation));
        }
        // The pores' liquid at the reported pressure: the full void of the
        // filled and trapped ones, the bridges' share (never more than the
        // void) of the drained ones, adding up to the summary's saturation.
        let s = &d.summary;
        let v = s.pore_volume;
        let mut filled = 0.0;
        let mut held = 0.0;
        let net = network(&bed, slab).unwrap();
        for (p, &(state, cluster, liquid)) in d.pores.iter().enumerate() {
            let void = net.pores[p].void_volume.max(0.0);
            match state {
                PoreState::Outside => assert_eq!(liquid, 0.0),
                PoreState::Filled => {
                    assert_eq!(cluster, 0);
                    assert_eq!(liquid, void);
                    filled += liquid;
                }
                PoreState::Trapped => {
                    assert!(cluster > 0 && trapping);
                    assert_eq!(liquid, void);
                    filled += liquid;
                }
                PoreState::Drained => {
                    assert!(liquid <= void && liquid >= 0.0);
                    held += liquid;
                }
            }
        }
        let total = s.residual_saturation.unwrap();
        assert!(
            ((filled + held) / v - total).abs() < 1e-9,
            "{} {}",
            (filled + held) / v,
            total
        );
        // The bridges of liquid.csv carry the drained pores' liquid.
        let bridged: Real = d.bridges.iter().map(|b| b.volume).sum();
        assert!((bridged - held).abs() <= 1e-9 * v, "{bridged} {held}");
        if !trapping {
            assert_eq!(s.residual_trapped, Some(0.0));
        }
    }
}

/// Trapping keeps liquid: without it the same bed holds less at the same
/// pressure, and the breakthrough does not move (it is the first path).
#[test]
fn trapping_keeps_liquid_the_breakthrough_stays() {
    let bed = deposited(1500, 4, "1.0");
    let slab = (4.0, 16.0);
    let on = drain_bed(&bed, slab, &DrainageOptions::default());
    let off = drain_bed(
        &bed,
        slab,
        &DrainageOptions {
            trapping: false,
            ..DrainageOptions::default()
        },
    );
    assert_eq!(on.summary.breakthrough, off.summary.breakthrough);
    assert!(on.summary.residual_saturation > off.summary.residual_saturation);
    assert!(on.summary.residual_trapped.unwrap() > 0.0);
}

#[test]
fn bad_wetting_and_missing_outlets_are_refused() {
    let bed = simple_cubic(3, 8);
    let net = network(&bed, (3.0, 13.0)).unwrap();
    let run = |o: DrainageOptions, slab: (Real, Real)| drain(&bed, &net, slab, 2.0, None, &o);
    let theta = DrainageOptions {
        contact_angle: 90f64.to_radians(),
        ..DrainageOptions::default()
    };
    assert!(run(theta, (3.0, 13.0))
        .unwrap_err()
        .contains("not a drainage"));
    let gamma = DrainageOptions {
        surface_tension: -1.0,
        ..DrainageOptions::default()
    };
    assert!(run(gamma, (3.0, 13.0))
        .unwrap_err()
        .contains("surface_tension"));
    // A slab down to the floor has no liquid below it.
    let e = run(DrainageOptions::default(), (-1.0, 13.0)).unwrap_err();
    assert!(e.contains("no outlet"), "{e}");
    let e = run(DrainageOptions::default(), (3.0, 100.0)).unwrap_err();
    assert!(e.contains("gas above"), "{e}");
}

/// The summary's fixed curve: the grid of [`table_pressures`], each point
/// the curve's own row at that pressure (computed, not interpolated), full
/// below the curve's start.
#[test]
fn the_fixed_curve_is_the_curve_at_the_table_pressures() {
    let bed = deposited(1500, 3, "1.0");
    let d = drain_bed(&bed, (4.0, 16.0), &DrainageOptions::default());
    let f = &d.summary.curve;
    assert_eq!(f.pc_reduced, table_pressures());
    assert_eq!(f.pc_reduced.len(), 41);
    assert_eq!((f.pc_reduced[0], f.pc_reduced[40]), (1.0, 100.0));
    let start = d.curve[0].pc_reduced;
    for ((&p, &s), &pend) in f.pc_reduced.iter().zip(&f.saturation).zip(&f.pendular) {
        match d
            .curve
            .iter()
            .find(|c| (c.pc_reduced - p).abs() <= 1e-12 * p)
        {
            Some(row) => assert_eq!((s, pend), (row.saturation, row.pendular)),
            None => {
                assert!(p < start, "{p} is on the curve's range but not a row");
                assert_eq!((s, pend), (1.0, 0.0));
            }
        }
    }
    for w in f.saturation.windows(2) {
        assert!(w[1] <= w[0] + 1e-12);
    }
    // The breakthrough (about 9 for equal spheres) lies inside the grid.
    let bt = d.summary.breakthrough.unwrap().reduced;
    assert!(bt > 1.0 && bt < 100.0);
}

/// The curve is found in two sweeps (the liquid's split backwards in
/// pressure, the bridges edge by edge); the reported state is found pore by
/// pore (a union–find of the liquid at that pressure, each pore's bridges
/// capped at its void). The state's pressure is a row of the curve: the two
/// ways agree there.
#[test]
fn the_curve_and_the_pore_by_pore_state_agree_at_the_reported_pressure() {
    let bed = deposited(1500, 5, "1.0");
    for trapping in [true, false] {
        for state in [
            None,
            Some(StatePressure::Reduced(12.0)),
            Some(StatePressure::Reduced(40.0)),
        ] {
            let o = DrainageOptions {
                trapping,
                state,
                ..DrainageOptions::default()
            };
            let d = drain_bed(&bed, (4.0, 16.0), &o);
            let s = &d.summary;
            let at = s.state.unwrap().reduced;
            let row = d
                .curve
                .iter()
                .find(|p| p.pc_reduced == at)
                .expect("the state's pressure is a row of the curve");
            let near = |a: Real, b: Real| (a - b).abs() <= 1e-12;
            assert!(
                near(row.saturation, s.residual_saturation.unwrap()),
                "{row:?} {s:?}"
            );
            assert!(
                near(row.connected, s.residual_connected.unwrap()),
                "{row:?} {s:?}"
            );
            assert!(
                near(row.trapped, s.residual_trapped.unwrap()),
                "{row:?} {s:?}"
            );
            assert!(
                near(row.pendular, s.residual_pendular.unwrap()),
                "{row:?} {s:?}"
            );
            if !trapping {
                assert_eq!(row.trapped, 0.0);
            }
        }
    }
}

/// The bridges' totals for a whole curve, edge by edge, equal the pore by
/// pore sums at each pressure, also where pores' bridges overflow their
/// void. In a sphere pack drained pores' rings never fill them (at most 15 %
/// of the void here, every pore drained): the cap is exercised with voids
/// made 50 times smaller.
#[test]
fn the_bridges_totals_edge_by_edge_equal_the_pore_by_pore_sums() {
    let bed = deposited(1500, 5, "1.0");
    let slab = (4.0, 16.0);
    let net = network(&bed, slab).unwrap();
    let (in_slab, members, voids) = slab_pores(&net, slab, 0.02);
    let kappas = [0.6, 1.0, 1.5, 2.0, 3.0, 5.0];
    let pendular = pendular::Pendular::new(&bed, &net, &in_slab, 0.3, kappas[0]);
    // Pores drain one after another: some edges only from the middle on.
    let drains_at: Vec<Real> = (0..net.pores.len())
        .map(|p| {
            if p % 3 == 0 {
                0.0
            } else {
                [0.0, 0.5, 1.5][p % 3]
            }
        })
        .collect();
    let totals = pendular.totals(&drains_at, &kappas, &voids);
    let mut capped = 0;
    for (&kappa, &total) in kappas.iter().zip(&totals) {
        let v = pendular.volumes(&drains_at, kappa, &members, &voids);
        assert!(v.total > 0.0);
        assert!(
            (total - v.total).abs() <= 1e-12 * v.total,
            "{total} against {}",
            v.total
        );
        capped += v.funicular;
    }
    assert!(capped > 0, "no pore was capped: the cap is not exercised");
}

/// Newton's search for the MS-P entry radius finds the bracketed search's
/// root on every throat of deposited beds (equal and lognormal sizes, several
/// contact angles).
#[test]
fn newton_entry_radii_equal_the_bracketed_ones_on_a_bed() {
    let lognormal = |count: u64| {
        let text = format!(
            "dim = 3\nseed = 7\n[box]\nwidth = 12\ndepth = 12\nheight = 400\nperiodic = true\n\
             [fill]\ncount = {count}\n[[species]]\nsize = {{ dist = \"lognormal\", median = 1.0, \
             gsd = 1.5 }}\n"
        );
        let config = Config::from_toml(&text, "test").unwrap();
        match run_bed(&config, &mut |_| {}).unwrap().bed {
            crate::bed::AnyBed::D3(b) => b,
            crate::bed::AnyBed::D2(_) => unreachable!(),
        }
    };
    for (radius, bed) in [
        ("equal", deposited(1500, 7, "1.0")),
        ("lognormal", lognormal(1500)),
    ] {
        let top = bed.centres.iter().map(|p| p[2]).fold(0.0, Real::max);
        let net = network(&bed, (0.2 * top, 0.8 * top)).unwrap();
        for deg in [0.0f64, 30.0, 60.0] {
            let theta = deg.to_radians();
            let (mut worst, mut n, mut mismatched) = (0.0f64, 0, Vec::new());
            for t in 0..net.throats.len() {
                let r_c = net.throats[t].constriction_radius;
                if !(r_c > 0.0) {
                    continue;
                }
                let (c, radii) = entry::facet_circles(&bed, &net, t);
                let fast = msp::entry_radius(&c, &radii, theta, Some(r_c), true);
                let slow = msp::entry_radius(&c, &radii, theta, Some(r_c), false);
                n += 1;
                match (fast, slow) {
                    (Some(a), Some(b)) => {
                        let d = (a - b).abs() / b;
                        worst = worst.max(d);
                        if d > 1e-9 {
                            mismatched.push((t, a, b, c, radii));
                        }
                    }
                    (None, None) => {}
                    _ => mismatched.push((t, fast.unwrap_or(-1.0), slow.unwrap_or(-1.0), c, radii)),
                }
            }
            println!(
                "{radius} θ={deg}: {n} throats, worst {worst:.2e}, {} mismatched",
                mismatched.len()
            );
            for m in mismatched.iter().take(5) {
                println!("  {m:?}");
            }
            assert!(mismatched.is_empty());
        }
    }
}

/// The contacts of a bed of few sizes share one bridge per pressure and pair
/// of radii: the curve's bridge totals (the shared path) equal the pore by
/// pore sums (each edge's own bridge) on equal spheres (one kind of
/// contact) and two sizes (several kinds); a lognormal bed shares none.
#[test]
fn recurring_contacts_share_their_bridges_and_the_totals_stand() {
    let bed_of = |species: &str| {
        let text = format!(
            "dim = 3\nseed = 11\n[box]\nwidth = 12\ndepth = 12\nheight = 400\nperiodic = true\n\
             [fill]\ncount = 1200\n{species}"
        );
        let config = Config::from_toml(&text, "test").unwrap();
        match run_bed(&config, &mut |_| {}).unwrap().bed {
            crate::bed::AnyBed::D3(b) => b,
            crate::bed::AnyBed::D2(_) => unreachable!(),
        }
    };
    for (name, species, kinds) in [
        ("equal", "[[species]]\nradius = 1.0\n", 1..=1),
        (
            "two sizes",
            "[[species]]\nradius = 1.0\n[[species]]\nradius = 0.7\n",
            3..=4,
        ),
        (
            "lognormal",
            "[[species]]\nsize = { dist = \"lognormal\", median = 1.0, gsd = 1.5 }\n",
            0..=0,
        ),
    ] {
        let bed = bed_of(species);
        let top = bed.centres.iter().map(|p| p[2]).fold(0.0, Real::max);
        let slab = (0.2 * top, 0.8 * top);
        let net = network(&bed, slab).unwrap();
        let (in_slab, members, voids) = slab_pores(&net, slab, 1.0);
        let kappas = [0.8, 1.2, 2.0, 3.5, 6.0, 20.0];
        let pendular = pendular::Pendular::new(&bed, &net, &in_slab, 0.4, kappas[0]);
        assert!(
            kinds.contains(&pendular.shared_kinds()),
            "{name}: {} kinds of contact shared",
            pendular.shared_kinds()
        );
        // Half the pores drained from the start, the rest at 1.5.
        let drains_at: Vec<Real> = (0..net.pores.len())
            .map(|p| if p % 2 == 0 { 0.0 } else { 1.5 })
            .collect();
        let totals = pendular.totals(&drains_at, &kappas, &voids);
        for (&kappa, &total) in kappas.iter().zip(&totals) {
            let v = pendular.volumes(&drains_at, kappa, &members, &voids);
            assert!(v.total > 0.0, "{name} at {kappa}: no bridge");
            assert!(
                (total - v.total).abs() <= 1e-12 * v.total,
                "{name} at {kappa}: {total} against {}",
                v.total
            );
        }
    }
}
