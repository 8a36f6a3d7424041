//! Random sequential addition (`mode = "rsa"`), shown from the outside:
//!
//! 1. saturation for real: after a run no point of the box can take another
//!    particle of the smallest size, checked independently of the engine by a
//!    fine sampling of candidate centres (2D and 3D, walls and periodic sides,
//!    mixtures) and, in 2D, exactly: every vertex of the arrangement of exclusion
//!    circles and walls lies strictly inside another exclusion circle;
//! 2. the literature's saturation densities on periodic boxes of 10^4 particles;
//! 3. no overlap, every particle inside the box (the independent checker with
//!    the rest test off), `count = N`, determinism.

use crate::common::{assert_checked, run};
use packbed::analyze;
use packbed::Bed;
use packbed::Config;
use packbed::InvariantChecks;
use packbed::{Real, Vector};

fn config(dim: u8, seed: u64, boxed: &str, fill: &str, species: &str) -> Config {
    let text = format!(
        "dim = {dim}\nseed = {seed}\nmode = \"rsa\"\n\n[box]\n{boxed}\n\n[fill]\n{fill}\n\n{species}"
    );
    crate::common::config(&text)
}

const ONE: &str = "[[species]]\nradius = 10\n";
const TWO: &str = "[[species]]\nradius = 20\nratio = 1\n\n[[species]]\nradius = 10\nratio = 2\n";
const LOGNORMAL: &str = "[[species]]\nsize = { dist = \"lognormal\", median = 10.0, gsd = 1.2 }\n";
/// Smallest radius of `LOGNORMAL`: the median over `gsd^3` (the default
/// truncation at -3 sd).
fn lognormal_min() -> Real {
    10.0 / 1.2f64.powi(3)
}

/// No overlap beyond 1e-12 of a radius, every particle inside the box.
fn assert_valid<const D: usize>(b: &Bed<D>, what: &str) {
    let checks = InvariantChecks {
        roof: true,
        rest: false,
        ..InvariantChecks::new(1e-12)
    };
    assert_checked(b, &checks, what);
}

/// The largest radius that fits centred at `p`, by brute force over every
/// particle (nearest periodic image) and the walls.
fn room<const D: usize>(b: &Bed<D>, p: &Vector<D>) -> Real {
    let c = &b.container;
    let mut room = Real::INFINITY;
    for k in 0..D {
        if !(c.periodic && k < D - 1) {
            room = room.min(p[k]).min(c.size[k] - p[k]);
        }
    }
    for (q, &r) in b.centres.iter().zip(&b.radii) {
        room = room.min(c.displacement(p, q).norm() - r);
    }
    room
}

/// Samples candidate centres on a lattice of spacing `h` (shifted by a
/// fraction of `h` on each pass) over the box and returns the largest room
/// found, with its point.
fn largest_room<const D: usize>(b: &Bed<D>, h: Real, passes: usize) -> (Real, Vector<D>) {
    let mut best = (Real::NEG_INFINITY, Vector::zero());
    let mut counts = [0usize; D];
    for k in 0..D {
        counts[k] = (b.container.size[k] / h).ceil() as usize;
    }
    let total: usize = counts.iter().product();
    for pass in 0..passes {
        let offset = (pass as Real + 0.5) / passes as Real * 0.618_033_988_75 % 1.0;
        for flat in 0..total {
            let mut rest = flat;
            let mut p = Vector::<D>::zero();
            for k in 0..D {
                let i = rest % counts[k];
                rest /= counts[k];
                // Irrational per-axis shifts so that passes do not repeat points.
                let o = (offset + 0.414_213_562 * k as Real) % 1.0;
                p[k] = ((i as Real + o) * h).min(b.container.size[k]);
            }
            let r = room(b, &p);
            if r > best.0 {
                best = (r, p);
            }
        }
    }
    best
}

/// Saturation by fine sampling: no sampled centre has room for `r_min`.
fn assert_saturated_sampled<const D: usize>(b: &Bed<D>, r_min: Real, h: Real, what: &str) {
    let (r, p) = largest_room(b, h, 2);
    assert!(
        r < r_min,
        "{what}: a particle of radius {r_min} fits at {p:?} (room {r})"
    );
}

/// Exact saturation in 2D: the available region (outside every exclusion
/// circle of radius `r_i + r_min`, inside the box shrunk by `r_min`), if not
/// empty, has a vertex where two of its boundary curves meet. So it is empty
/// exactly when every such meeting point lies strictly inside some other
/// exclusion circle or outside the shrunk box.
fn assert_saturated_exact_2d(b: &Bed<2>, r_min: Real, what: &str) {
    let c = &b.container;
    let (w, hgt) = (c.size[0], c.size[1]);
    // Circles with their periodic images (two suffice: the box is wider than
    // twice any exclusion radius in these tests).
    let mut circles: Vec<(Vector<2>, Real)> = Vec::new();
    for (p, &r) in b.centres.iter().zip(&b.radii) {
        circles.push((*p, r + r_min));
        if c.periodic {
            circles.push((*p + Vector([w, 0.0]), r + r_min));
            circles.push((*p - Vector([w, 0.0]), r + r_min));
        }
    }
    // Lines of the shrunk box: (axis, value).
    let mut lines = vec![(1usize, r_min), (1usize, hgt - r_min)];
    if !c.periodic {
        lines.push((0, r_min));
        lines.push((0, w - r_min));
    }
    let mut points: Vec<Vector<2>> = Vec::new();
    for i in 0..circles.len() {
        let (a, ra) = circles[i];
        for (bc, rb) in circles.iter().skip(i + 1) {
            let d = *bc - a;
            let dist = d.norm();
            if dist >= ra + rb || dist <= (ra - rb).abs() || dist == 0.0 {
                continue;
            }
            let x = (dist * dist + ra * ra - rb * rb) / (2.0 * dist);
            let y = (ra * ra - x * x).max(0.0).sqrt();
            let (u, v) = (d / dist, Vector([-d[1] / dist, d[0] / dist]));
            points.push(a + u * x + v * y);
            points.push(a + u * x - v * y);
        }
        for &(axis, value) in &lines {
            let off = value - a[axis];
            if off.abs() >= ra {
                continue;
            }
            let along = (ra * ra - off * off).sqrt();
            for s in [-1.0, 1.0] {
                let mut p = a;
                p[axis] = value;
                p[1 - axis] += s * along;
                points.push(p);
            }
        }
    }
    // Corners of the shrunk box.
    if !c.periodic {
        for x in [r_min, w - r_min] {
            for y in [r_min, hgt - r_min] {
                points.push(Vector([x, y]));
            }
        }
    }
    let slack = 1e-9 * r_min;
    let mut checked = 0;
    for p in points {
        let inside = (c.periodic || (p[0] >= r_min - slack && p[0] <= w - r_min + slack))
            && p[1] >= r_min - slack
            && p[1] <= hgt - r_min + slack;
        if !inside {
            continue;
        }
        let mut q = p;
        if c.periodic {
            q[0] = q[0].rem_euclid(w);
        }
        // The point lies on its own two curves (room = r_min there, up to
        // rounding); it is covered when another particle leaves less room.
        let r = room(b, &q);
        checked += 1;
        assert!(
            r < r_min - slack,
            "{what}: the vertex {q:?} of the available region is free (room {r}, r_min {r_min})"
        );
    }
    assert!(checked > 0, "{what}: no vertex checked");
}

// ---------------------------------------------------------------------------
// 1. Saturation
// ---------------------------------------------------------------------------

#[test]
fn saturated_2d_equal_discs_walls_and_periodic() {
    for seed in 1..=6 {
        for periodic in [false, true] {
            let c = config(
                2,
                seed,
                &format!("width = 300\nheight = 260\nperiodic = {periodic}"),
                "",
                ONE,
            );
            let (b, rep) = run::<2>(&c);
            let what = format!("2D seed {seed} periodic {periodic}");
            assert_valid(&b, &what);
            assert_eq!(rep.dropped, b.len() as u64);
            assert_eq!(rep.redrops, 0);
            assert_saturated_exact_2d(&b, 10.0, &what);
            assert_saturated_sampled(&b, 10.0, 1.0, &what);
        }
    }
}

#[test]
fn saturated_2d_mixtures() {
    for seed in 1..=3 {
        for periodic in [false, true] {
            for (species, r_min) in [(TWO, 10.0), (LOGNORMAL, lognormal_min())] {
                let c = config(
                    2,
                    seed,
                    &format!("width = 320\nheight = 280\nperiodic = {periodic}"),
                    "",
                    species,
                );
                let (b, _) = run::<2>(&c);
                let what = format!("2D mixture seed {seed} periodic {periodic} r_min {r_min}");
                assert_valid(&b, &what);
                assert!(b.r_min() >= r_min * (1.0 - 1e-12), "{what}: {}", b.r_min());
                assert_saturated_exact_2d(&b, r_min, &what);
                assert_saturated_sampled(&b, r_min, 0.4 * r_min, &what);
                // Both sizes of the binary mixture are there.
                if species == TWO {
                    assert!(b.radii.contains(&20.0), "{what}");
                    assert!(b.radii.contains(&10.0), "{what}");
                }
            }
        }
    }
}

#[test]
fn saturated_3d_walls_and_periodic_equal_and_mixed() {
    for seed in 1..=2 {
        for periodic in [false, true] {
            for (species, r_min, h) in [(ONE, 10.0, 2.0), (TWO, 10.0, 2.0)] {
                let c = config(
                    3,
                    seed,
                    &format!("width = 120\ndepth = 110\nheight = 100\nperiodic = {periodic}"),
                    "",
                    species,
                );
                let (b, _) = run::<3>(&c);
                let what = format!("3D seed {seed} periodic {periodic} r_min {r_min}");
                assert_valid(&b, &what);
                assert_saturated_sampled(&b, r_min, h, &what);
            }
        }
    }
}

#[test]
fn saturation_check_finds_a_hole() {
    // The checks above can fail: take one particle out of a saturated bed and
    // both find room for it again.
    let c = config(2, 3, "width = 300\nheight = 260", "", ONE);
    let (mut b, _) = run::<2>(&c);
    let gone = b.centres.remove(b.len() / 2);
    b.radii.pop();
    b.species.pop();
    b.bodies.pop();
    let (r, _) = largest_room(&b, 1.0, 1);
    assert!(
        r >= 10.0,
        "room {r} after removing the particle at {gone:?}"
    );
    let caught = std::panic::catch_unwind(|| assert_saturated_exact_2d(&b, 10.0, "holed"));
    assert!(caught.is_err());
}

// ---------------------------------------------------------------------------
// 2. Reference values: Zhang & Torquato (2013), as docs/validation.md cites them
// ---------------------------------------------------------------------------

/// Mean bulk packing fraction over `seeds` replicates.
fn mean_bulk<const D: usize>(boxed: &str, seeds: std::ops::Range<u64>) -> (Real, usize) {
    let mut sum = 0.0;
    let mut n = 0;
    let mut particles = usize::MAX;
    for seed in seeds {
        let c = config(D as u8, seed, boxed, "", ONE);
        let (b, _) = run::<D>(&c);
        assert_valid(&b, boxed);
        let (_, summary) = analyze(&b, 1e-6);
        assert!(!summary.packing.as_ref().unwrap().bulk_region_empty);
        eprintln!(
            "RSA {D}D seed {seed}: {} particles, global {:.4}, bulk {:.4}",
            b.len(),
            summary.packing.as_ref().unwrap().global,
            summary.packing.as_ref().unwrap().bulk.expect("bulk")
        );
        sum += summary.packing.as_ref().unwrap().bulk.expect("bulk");
        n += 1;
        particles = particles.min(b.len());
    }
    (sum / n as Real, particles)
}

#[test]
fn reference_saturation_density_discs() {
    // 0.547 ± 0.003 (Zhang & Torquato: 0.547067), bulk of periodic boxes.
    let (phi, n) = mean_bulk::<2>("width = 2420\nheight = 2420\nperiodic = true", 1..5);
    assert!(n >= 10_000, "{n} particles");
    assert!((phi - 0.547).abs() <= 0.003, "discs: {phi}");
}

#[test]
fn reference_saturation_density_spheres() {
    // 0.384 ± 0.003 (Zhang & Torquato: 0.384130), bulk of periodic boxes.
    let (phi, n) = mean_bulk::<3>(
        "width = 490\ndepth = 490\nheight = 490\nperiodic = true",
        1..4,
    );
    assert!(n >= 10_000, "{n} particles");
    assert!((phi - 0.384).abs() <= 0.003, "spheres: {phi}");
}

// ---------------------------------------------------------------------------
// 3. Count, determinism, inputs
// ---------------------------------------------------------------------------

#[test]
fn count_stops_at_n_or_at_saturation() {
    let c = config(
        3,
        5,
        "width = 200\ndepth = 200\nheight = 200",
        "count = 50",
        TWO,
    );
    let (b, rep) = run::<3>(&c);
    assert_eq!(b.len(), 50);
    assert_eq!(rep.dropped, 50);
    assert_valid(&b, "count 50");
    // More than fits: stops at saturation, with fewer particles.
    let c = config(2, 5, "width = 200\nheight = 200", "count = 100000", ONE);
    let (b, rep) = run::<2>(&c);
    assert!(b.len() < 100_000 && b.len() > 50, "{}", b.len());
    assert_eq!(rep.dropped, b.len() as u64);
    assert_saturated_exact_2d(&b, 10.0, "count beyond saturation");
}

#[test]
fn deterministic_for_a_seed() {
    let c = config(
        3,
        9,
        "width = 150\ndepth = 150\nheight = 150\nperiodic = true",
        "",
        TWO,
    );
    let (a, _) = run::<3>(&c);
    let (b, _) = run::<3>(&c);
    assert_eq!(a.centres, b.centres);
    assert_eq!(a.radii, b.radii);
    assert_eq!(a.species, b.species);
    let c2 = config(
        3,
        10,
        "width = 150\ndepth = 150\nheight = 150\nperiodic = true",
        "",
        TWO,
    );
    let (d, _) = run::<3>(&c2);
    assert_ne!(a.centres, d.centres);
}

#[test]
fn roof_and_base_layer_do_not_apply() {
    // The whole box is filled (up to the roof, not beyond) whatever base_layer
    // says; particles float, so many touch nothing.
    for base in ["none", "random"] {
        let c = config(
            2,
            2,
            "width = 300\nheight = 300",
            &format!("base_layer = \"{base}\""),
            ONE,
        );
        let (b, rep) = run::<2>(&c);
        assert_eq!(rep.base_layer, 0);
        assert!(b.top() <= 300.0);
        assert!(b.top() > 300.0 - 2.0 * 10.0 * 2.0);
        let (contacts, _) = analyze(&b, 1e-6);
        assert!(
            contacts.pairs.len() < b.len() / 4,
            "{} contacts",
            contacts.pairs.len()
        );
    }
}

#[test]
fn a_box_that_fits_one_particle() {
    let c = config(2, 1, "width = 20\nheight = 20", "", ONE);
    let (b, _) = run::<2>(&c);
    assert_eq!(b.len(), 1);
    assert_eq!(b.centres[0], Vector([10.0, 10.0]));
}
