//! A woven square mesh as the filter medium (`[[feeds]]` with `mesh = {..}`):
//! its wires are placed exactly, and it sieves: every particle finer than
//! its aperture passes, every one coarser stays at its surface.

use crate::common::{assert_alpha_fits, assert_checked, config, filtered, filtered_run, run, TOL};
use packbed::{
    capture, mesh_mid_plane, Bed, CaptureSummary, Config, DepositReport, InvariantChecks,
};

/// A periodic box of `side` (3D: side × side) with a mesh of wires of
/// diameter 2 and aperture 3 (pitch 5), then `count` spheres of radii
/// uniform in [`lo`, `hi`].
fn sieve(dim: u32, side: f64, lo: f64, hi: f64, count: u64) -> String {
    let depth = if dim == 3 {
        format!("depth = {side}\n")
    } else {
        String::new()
    };
    format!(
        "dim = {dim}\nseed = 3\n[box]\nwidth = {side}\n{depth}height = 3000\nperiodic = true\n\
         [fill]\nbase_layer = \"none\"\n\
         [[species]]\nname = \"slurry\"\nsize = {{ dist = \"uniform\", min = {lo}, max = {hi} }}\n\
         [[feeds]]\nmesh = {{ wire_diameter = 2, aperture = 3 }}\n\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = {count}\n"
    )
}

/// The mesh's species: those named after its wires (placed after the
/// config's own species).
fn mesh_flags<const D: usize>(b: &Bed<D>) -> Vec<bool> {
    b.species_info
        .iter()
        .map(|s| s.name.starts_with("mesh wires"))
        .collect()
}

fn sieved<const D: usize>(c: &Config) -> (Bed<D>, DepositReport, CaptureSummary) {
    let (b, report) = run::<D>(c);
    let cap = capture(
        &b,
        &mesh_flags(&b),
        &report.filtrate,
        report.medium_lift,
        mesh_mid_plane::<D>(&c.feeds),
    )
    .unwrap();
    (b, report, cap)
}

#[test]
fn the_wires_lie_where_the_mesh_says() {
    let c = config(&sieve(3, 25.0, 0.5, 1.0, 10));
    let (b, report) = run::<3>(&c);
    let lift = report.medium_lift;
    assert_eq!(lift, 2.0);
    let wire: Vec<usize> = (0..b.len())
        .filter(|&i| mesh_flags(&b)[b.species[i] as usize])
        .collect();
    // Five wires each way, one body each, closed through the periodic sides.
    let mut bodies: Vec<u32> = wire.iter().map(|&i| b.bodies[i]).collect();
    bodies.dedup();
    assert_eq!(bodies.len(), 10);
    for &i in &wire {
        assert_eq!(b.radii[i], 1.0);
        let (x, y, z) = (b.centres[i][0], b.centres[i][1], b.centres[i][2]);
        // Wires along x lie on the open floor's gap, wires along y on them.
        let along_x = b.species_info[b.species[i] as usize].name.ends_with('x');
        let (across, height) = if along_x { (y, 1.0) } else { (x, 3.0) };
        assert!(((across - 2.5) / 5.0 - ((across - 2.5) / 5.0).round()).abs() < 1e-12);
        assert!((z - lift - height).abs() < 1e-12, "{z}");
    }
    // Neighbouring beads of a wire at most a quarter radius apart, and the
    // wire closed: its beads times their spacing is the box.
    for &body in &bodies {
        let beads: Vec<usize> = wire
            .iter()
            .copied()
            .filter(|&i| b.bodies[i] == body)
            .collect();
        let along_x = b.species_info[b.species[beads[0]] as usize]
            .name
            .ends_with('x');
        let mut at: Vec<f64> = beads
            .iter()
            .map(|&i| b.centres[i][usize::from(!along_x)])
            .collect();
        at.sort_by(f64::total_cmp);
        let spacing = at[1] - at[0];
        assert!(spacing <= 0.25, "{spacing}");
        assert!(at.windows(2).all(|w| (w[1] - w[0] - spacing).abs() < 1e-9));
        assert!((at.len() as f64 * spacing - 25.0).abs() < 1e-9);
        // A bead right over (or under) every crossing, at 2.5 + 5 j.
        for j in 0..5 {
            let x = 2.5 + 5.0 * f64::from(j);
            assert!(at.iter().any(|&a| (a - x).abs() < 1e-9), "{x}");
        }
    }
    let checks = InvariantChecks {
        rest: false,
        ..InvariantChecks::new(TOL)
    };
    assert_checked(&b, &checks, "mesh");
}

#[test]
fn a_mesh_coarser_than_every_particle_passes_them_all() {
    // Diameters up to 2.9 through a 3-wide opening: none is held. The model
    // drops one particle at a time and carries no fluid, so nothing bridges
    // an opening that no particle stops in.
    for (dim, seed) in [(2, 3), (3, 1), (3, 2), (3, 3)] {
        let text = sieve(dim, 25.0, 0.5, 1.45, 2000).replace("seed = 3", &format!("seed = {seed}"));
        let (b, report, cap) = if dim == 3 {
            let (b, r, cap) = sieved::<3>(&config(&text));
            (b.len(), r, cap)
        } else {
            let (b, r, cap) = sieved::<2>(&config(&text));
            (b.len(), r, cap)
        };
        assert_eq!(
            (cap.passed, cap.lodged, cap.cake),
            (2000, 0, 0),
            "{dim}D, seed {seed}"
        );
        assert_eq!(report.filtrate.len(), 2000);
        // Only the wires are left in the bed: in 3D ten of 100 beads (a
        // pitch of 5 holds 20 beads a quarter radius apart), in 2D five discs.
        let (wires, beads) = if dim == 3 { (10, 1000) } else { (5, 5) };
        assert_eq!(cap.medium_bodies, wires);
        assert_eq!(b, beads);
    }
}

#[test]
fn a_mesh_finer_than_every_particle_holds_them_all_at_its_surface() {
    // Diameters from 3.1 up over a 3-wide opening: none passes, none enters
    // between the wires' layers; they sit in the openings and on each other.
    for dim in [2, 3] {
        let text = sieve(dim, 25.0, 1.55, 2.5, 400);
        let (passed, lodged, cake) = if dim == 3 {
            let (b, _, cap) = sieved::<3>(&config(&text));
            let checks = InvariantChecks {
                rest: false,
                ..InvariantChecks::new(TOL)
            };
            assert_checked(&b, &checks, "mesh and cake");
            // The surface is the mesh's mid-plane, where its layers touch.
            assert!((cap.medium_surface - cap.medium_bottom - 2.0).abs() < 1e-12);
            (cap.passed, cap.lodged, cap.cake)
        } else {
            let (_, _, cap) = sieved::<2>(&config(&text));
            (cap.passed, cap.lodged, cap.cake)
        };
        assert_eq!((passed, lodged, cake), (0, 0, 400), "{dim}D");
    }
}

#[test]
fn a_mesh_sieves_a_mix_at_its_aperture() {
    // Radii 0.5–2.5 over a 3-wide opening (d = 3 at r = 1.5): everything
    // coarser than the aperture stays; of the finer, only what the coarse
    // particles' layer catches stays, so the grade efficiency climbs to 1
    // by the aperture.
    let (_, report, cap) = sieved::<3>(&config(&sieve(3, 25.0, 0.5, 2.5, 3000)));
    assert!(report.filtrate.iter().all(|f| 2.0 * f.radius < 3.0));
    assert!(cap.passed > 0 && cap.cake > 0, "{cap:?}");
    for class in &cap.classes {
        if class.d_lo >= 3.0 {
            assert_eq!(class.grade_efficiency, Some(1.0), "{class:?}");
        }
    }
}

#[test]
fn bad_meshes_are_refused() {
    let good = sieve(3, 25.0, 0.5, 1.0, 10);
    for (text, needle) in [
        (
            good.replace("aperture = 3", "aperture = 0"),
            "no opening",
        ),
        (
            good.replace("aperture = 3", "aperture = -1"),
            "no opening",
        ),
        (
            good.replace("wire_diameter = 2", "wire_diameter = 0"),
            "wire_diameter",
        ),
        (good.replace("periodic = true", "periodic = false"), "periodic"),
        (
            good.replace("width = 25", "width = 24"),
            "make it 20 or 25",
        ),
        (
            good.replace("width = 25", "width = 5"),
            "at least two",
        ),
        (
            good.replace(
                "mesh = { wire_diameter = 2, aperture = 3 }\n",
                "mesh = { wire_diameter = 2, aperture = 3 }\ncount = 4\n",
            ),
            "placed, not fed",
        ),
        (
            good.replace(
                "[[feeds]]\nmesh = { wire_diameter = 2, aperture = 3 }\n[[feeds]]\nspecies = [\"slurry\"]\ncount = 10\n",
                "[[feeds]]\nspecies = [\"slurry\"]\ncount = 10\nmedium = true\n[[feeds]]\nmesh = { wire_diameter = 2, aperture = 3 }\n",
            ),
            "first feed",
        ),
    ] {
        let e = config(&text).plan::<3>().unwrap_err().to_string();
        assert!(e.contains(needle), "{needle}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
}

/// A mesh finer than every particle under 1,200 of them, filtered at 1 bar,
/// every length times `scale` in `unit`.
fn filtered_on_a_mesh(scale: f64, unit: &str) -> packbed::FiltrationSummary {
    let text = format!(
        "dim = 3\nseed = 5\n[box]\nwidth = {side}\ndepth = {side}\nheight = {h}\nperiodic = true\n\
         [fill]\nbase_layer = \"none\"\n\
         [[species]]\nname = \"slurry\"\nsize = {{ dist = \"uniform\", min = {lo}, max = {hi} }}\n\
         [[feeds]]\nmesh = {{ wire_diameter = {d}, aperture = {a} }}\n\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = 1200\n\
         [analysis]\nmeasures = [\"packing\"]\nlength_unit = \"{unit}\"\nsolid_density = 2650\n\
         [filtration]\npressure = 1e5\nconcentration = 100\n",
        side = 25.0 * scale,
        h = 3000.0 * scale,
        lo = 1.55 * scale,
        hi = 2.0 * scale,
        d = 2.0 * scale,
        a = 3.0 * scale,
    );
    filtered(&text)
}

#[test]
fn the_filtration_through_a_mesh_is_solved_and_the_same_in_um_and_mm() {
    let um = filtered_on_a_mesh(1.0, "um");
    let mm = filtered_on_a_mesh(1e-3, "mm");
    // The wires' upper and lower planes are mirror planes of the clean
    // mesh's flow: no cell's side of a cut is left to rounding.
    let same = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-9;
    assert!(
        same(um.r_medium_per_m, mm.r_medium_per_m),
        "{} {}",
        um.r_medium_per_m,
        mm.r_medium_per_m
    );
    assert!(same(um.r_medium_clogged_per_m, mm.r_medium_clogged_per_m));
    // Every particle stays on the mesh: the cake is homogeneous, and Ruth's
    // line gives the network's α.
    assert_alpha_fits(&um);
    // Armour & Cannon's screen, by hand: d = 2 µm, pitch 5 µm, ε = 1 − π/10,
    // a = (π/10)·4/d, L = 2d, R = 8.61 a² L / ε².
    let d = 2e-6;
    let solid = std::f64::consts::PI * 2.0 / (4.0 * 5.0);
    let a = solid * 4.0 / d;
    let r = 8.61 * a * a * 2.0 * d / (1.0 - solid).powi(2);
    let screen = um.r_medium_screen_per_m.unwrap();
    assert!((screen / r - 1.0).abs() < 1e-12, "{screen:e} {r:e}");
    // The network's mirrored stack of screens lies below one screen's
    // correlation, within a factor of three (docs/guide/filtration.md).
    let ratio = um.r_medium_per_m / screen;
    assert!(
        ratio > 1.0 / 3.0 && ratio < 1.0,
        "network over screen {ratio}"
    );
}

#[test]
fn a_mesh_lies_on_the_floor_whatever_the_base_layer() {
    // The default base layer is random; a mesh is laid on the floor, so
    // none is laid under it: the bed is the same as with "none".
    let none = sieve(3, 25.0, 0.5, 1.0, 300);
    let default = none.replace("base_layer = \"none\"\n", "");
    assert_ne!(none, default);
    let (a, ra, ca) = sieved::<3>(&config(&none));
    let (b, rb, cb) = sieved::<3>(&config(&default));
    assert_eq!(rb.base_layer, 0);
    assert_eq!(a.centres, b.centres);
    assert_eq!(
        (ca.passed, ca.lodged, ca.cake),
        (cb.passed, cb.lodged, cb.cake)
    );
    assert_eq!(ra.filtrate, rb.filtrate);
}

/// A precoat of spheres coarser than the opening (median diameter 5) on
/// the mesh of [`sieve`] (wires 2, aperture 3), then `slurry` particles
/// finer than the opening (median diameter 1.2), filtered at 1 bar (µm).
fn precoated_mesh(slurry: u64) -> String {
    format!(
        "dim = 3\nseed = 4\n[box]\nwidth = 25\ndepth = 25\nheight = 3000\nperiodic = true\n\
         [fill]\nbase_layer = \"none\"\n\
         [[species]]\nname = \"precoat\"\nsize = {{ dist = \"lognormal\", median = 2.5, gsd = 1.05 }}\n\
         [[species]]\nname = \"slurry\"\nsize = {{ dist = \"lognormal\", median = 0.6, gsd = 1.2 }}\n\
         [[feeds]]\nmesh = {{ wire_diameter = 2, aperture = 3 }}\n\
         [[feeds]]\nspecies = [\"precoat\"]\ncount = 150\nmedium = true\n\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = {slurry}\n\
         [analysis]\nmeasures = [\"packing\"]\nlength_unit = \"um\"\nsolid_density = 2650\n\
         [filtration]\npressure = 1e5\nconcentration = 100\n"
    )
}

#[test]
fn a_precoat_on_a_mesh_is_one_granular_medium() {
    let text = precoated_mesh(20_000);
    let c = config(&text);
    // The medium's surface is the precoat's top, not the mesh's mid-plane:
    // fines caught inside the precoat have lodged in the medium.
    assert_eq!(mesh_mid_plane::<3>(&c.feeds), None);
    let run = filtered_run(&text);
    let cap = run.summary.capture.unwrap();
    let wires_top = cap.medium_bottom + 4.0;
    assert!(
        cap.medium_surface > wires_top + 4.0,
        "surface {} over the wires' top {wires_top}",
        cap.medium_surface
    );
    assert!(cap.lodged > 0, "{cap:?}");
    assert_eq!(cap.fed, cap.passed + cap.lodged + cap.cake);
    // The curve starts at that surface: the clean medium is the mesh and
    // the precoat, and Ruth's line over the cake gives the network's α.
    let f = run.summary.filtration.unwrap();
    let bare = filtered_on_a_mesh(1.0, "um");
    assert!(
        f.r_medium_per_m > bare.r_medium_per_m,
        "mesh and precoat {:e}, bare mesh {:e}",
        f.r_medium_per_m,
        bare.r_medium_per_m
    );
    assert!(f.r_medium_screen_per_m.is_some());
    assert!(f.checkpoints[0].cake_height_m.abs() < 1e-12);
    assert_alpha_fits(&f);
    // What lodged in the precoat raised the medium's resistance.
    assert!(f.r_medium_clogged_per_m > f.r_medium_per_m);
}
