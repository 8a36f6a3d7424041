//! Contacts: touching pairs of particles, particles touching walls, and the
//! coordination number (touching bodies per body).
//!
//! Periodic sides use the minimum image. In a box only one or two diameters wide a
//! pair can touch through two images at once (left and right); it is listed once,
//! with the smaller gap, because a contact list is a list of touching *pairs*. A
//! particle touching its own image (period narrower than its diameter) is not a
//! contact either: it is not a pair. The rest checker in [`super::validate`] does
//! see every image, since there each image is a separate force.

use super::cells::CellList;
use crate::bed::Bed;
use crate::container::Wall;
use crate::math::Real;
use rayon::prelude::*;
use serde::Serialize;

/// Two touching particles (`i < j`) and the gap between their surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Smaller particle id.
    pub i: u32,
    /// Larger particle id.
    pub j: u32,
    /// Surface gap (negative: overlap).
    pub gap: Real,
}

/// A particle touching the floor or a side wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallContact {
    /// Particle id.
    pub i: u32,
    /// Which wall.
    pub wall: Wall,
    /// Gap between the particle's surface and the wall.
    pub gap: Real,
}

/// All contacts of a bed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Contacts {
    /// Particle–particle contacts, sorted by `(i, j)`.
    pub pairs: Vec<Contact>,
    /// Particle–wall contacts, sorted by particle then wall.
    pub walls: Vec<WallContact>,
}

/// Every contact of `bed`: pairs of particles of different bodies whose surface gap
/// is `<= contact_tol × min(r_i, r_j)` (overlaps included, with negative gap), and
/// particles within `contact_tol × r` of the floor or a side wall. O(n).
pub fn find_contacts<const D: usize>(bed: &Bed<D>, contact_tol: Real) -> Contacts {
    let n = bed.len();
    let mut pairs = Vec::new();
    if n >= 2 {
        // A contact's centre distance is at most r_i + r_j + tol × min(r_i, r_j).
        let cells = CellList::new(bed, contact_tol);
        pairs = cells.close_pairs(|i, j| {
            if bed.bodies[i] == bed.bodies[j] {
                return None;
            }
            let (ri, rj) = (bed.radii[i], bed.radii[j]);
            let d = bed.container.displacement(&bed.centres[i], &bed.centres[j]);
            let gap = d.norm() - ri - rj;
            (gap <= contact_tol * ri.min(rj)).then_some(Contact {
                i: i as u32,
                j: j as u32,
                gap,
            })
        });
        pairs.par_sort_unstable_by_key(|c| (c.i, c.j));
    }
    let mut walls = Vec::new();
    let all_walls = bed.container.walls();
    for i in 0..n {
        let r = bed.radii[i];
        for &wall in &all_walls {
            let gap = bed.container.wall_distance(wall, &bed.centres[i]) - r;
            if gap <= contact_tol * r {
                walls.push(WallContact {
                    i: i as u32,
                    wall,
                    gap,
                });
            }
        }
    }
    Contacts { pairs, walls }
}

/// Overlaps smaller than this fraction of the smaller radius are touches, not
/// overlaps: packbed's own beds overlap by about `1e-13` of a radius (chains up
/// to `1e-10`), and a bed written with six or seven significant digits by
/// another tool by about `1e-6`.
pub const OVERLAP_TOL: Real = 1e-6;

/// Pairs of particles of different bodies that overlap, for the checks on
/// beds read from files (beads of one chain overlap by design).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Overlaps {
    /// Pairs overlapping by more than [`OVERLAP_TOL`] of the smaller radius.
    pub overlapping_pairs: u64,
    /// The worst of those overlaps relative to the smaller radius (2 for two
    /// copies of one particle); 0 without any.
    pub max_overlap: Real,
}

/// The overlaps among `contacts` (which hold every overlapping pair of
/// different bodies whenever the contact tolerance is not negative).
pub fn overlaps<const D: usize>(bed: &Bed<D>, contacts: &Contacts) -> Overlaps {
    let mut o = Overlaps::default();
    for c in &contacts.pairs {
        let r = bed.radii[c.i as usize].min(bed.radii[c.j as usize]);
        let by = -c.gap / r;
        if by > OVERLAP_TOL {
            o.overlapping_pairs += 1;
            o.max_overlap = o.max_overlap.max(by);
        }
    }
    o
}

/// Coordination number of every particle: the number of distinct other bodies its
/// body touches (walls excluded). All beads of a chain get their chain's number;
/// for spheres body = particle.
pub fn coordination<const D: usize>(bed: &Bed<D>, contacts: &Contacts) -> Vec<u32> {
    if let Some(z) = coordination_of_spheres(bed, contacts) {
        return z;
    }
    // Body ids of imported beds need not be dense, so count over sorted, deduplicated
    // body pairs instead of indexing an array by body id.
    let mut links: Vec<(u32, u32)> = Vec::with_capacity(2 * contacts.pairs.len());
    for c in &contacts.pairs {
        let (Some(&a), Some(&b)) = (bed.bodies.get(c.i as usize), bed.bodies.get(c.j as usize))
        else {
            continue;
        };
        if a != b {
            links.push((a, b));
            links.push((b, a));
        }
    }
    links.par_sort_unstable();
    links.dedup();
    bed.bodies
        .iter()
        .map(|&b| {
            let lo = links.partition_point(|&(a, _)| a < b);
            let hi = links.partition_point(|&(a, _)| a <= b);
            (hi - lo) as u32
        })
        .collect()
}

/// The coordination numbers when every body is one particle: a count of the
/// contacts of each (two particles touch at most once in the list). `None` when
/// some body has several beads.
fn coordination_of_spheres<const D: usize>(bed: &Bed<D>, contacts: &Contacts) -> Option<Vec<u32>> {
    let n = bed.len();
    let max_body = bed.bodies.iter().max().map_or(0, |&b| b as usize);
    if max_body > 4 * n + 1024 {
        return None;
    }
    let mut beads = vec![0u8; max_body + 1];
    for &b in &bed.bodies {
        let c = &mut beads[b as usize];
        if *c > 0 {
            return None;
        }
        *c = 1;
    }
    let mut z = vec![0u32; n];
    for c in &contacts.pairs {
        let (i, j) = (c.i as usize, c.j as usize);
        if i < n && j < n && i != j {
            z[i] += 1;
            z[j] += 1;
        }
    }
    Some(z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use crate::math::Vector;
    use proptest::prelude::*;

    #[test]
    fn row_of_touching_discs_between_walls() {
        let bed = Bed::of_discs(
            [8.0, 10.0],
            false,
            &[
                (1.0, 1.0, 1.0),
                (3.0, 1.0, 1.0),
                (5.0, 1.0, 1.0),
                (7.0, 1.0, 1.0),
            ],
        );
        let c = find_contacts(&bed, 1e-9);
        let pairs: Vec<(u32, u32, Real)> = c.pairs.iter().map(|p| (p.i, p.j, p.gap)).collect();
        assert_eq!(pairs, vec![(0, 1, 0.0), (1, 2, 0.0), (2, 3, 0.0)]);
        let walls: Vec<(u32, &str)> = c.walls.iter().map(|w| (w.i, w.wall.name())).collect();
        assert_eq!(
            walls,
            vec![
                (0, "floor"),
                (0, "x0"),
                (1, "floor"),
                (2, "floor"),
                (3, "floor"),
                (3, "x1")
            ]
        );
        assert_eq!(coordination(&bed, &c), vec![1, 2, 2, 1]);
    }

    #[test]
    fn gaps_within_tolerance_and_overlaps_are_contacts() {
        // Gaps 1e-7 (within 1e-6·r), 1e-5 (not), -0.1 (overlap, reported negative).
        let bed = Bed::of_discs(
            [20.0, 10.0],
            false,
            &[
                (1.0, 1.0, 1.0),
                (3.0 + 1e-7, 1.0, 1.0),
                (10.0, 1.0, 1.0),
                (12.0 + 1e-5, 1.0, 1.0),
                (15.0, 1.0, 1.0),
                (16.9, 1.0, 1.0),
            ],
        );
        let c = find_contacts(&bed, 1e-6);
        assert_eq!(c.pairs.len(), 2);
        assert_eq!((c.pairs[0].i, c.pairs[0].j), (0, 1));
        assert!((c.pairs[0].gap - 1e-7).abs() < 1e-15);
        assert_eq!((c.pairs[1].i, c.pairs[1].j), (4, 5));
        assert!((c.pairs[1].gap + 0.1).abs() < 1e-12);
    }

    #[test]
    fn periodic_contact_across_the_boundary() {
        let discs = [(0.5, 1.0, 1.0), (8.5, 1.0, 1.0)];
        let periodic = find_contacts(&Bed::of_discs([10.0, 10.0], true, &discs), 1e-9);
        assert_eq!(
            periodic.pairs,
            vec![Contact {
                i: 0,
                j: 1,
                gap: 0.0
            }]
        );
        // Periodic: no side walls, only the floor.
        assert!(periodic.walls.iter().all(|w| w.wall == Wall::Floor));
        let walled = find_contacts(&Bed::of_discs([10.0, 10.0], false, &discs), 1e-9);
        assert!(walled.pairs.is_empty());
    }

    #[test]
    fn pair_touching_through_two_images_is_listed_once() {
        // Period 4 = two diameters: disc 1 touches disc 0 on both sides.
        let c = find_contacts(
            &Bed::of_discs([4.0, 10.0], true, &[(0.0, 1.0, 1.0), (2.0, 1.0, 1.0)]),
            1e-9,
        );
        assert_eq!(
            c.pairs,
            vec![Contact {
                i: 0,
                j: 1,
                gap: 0.0
            }]
        );
        // Period 3.9: one side overlaps by 0.1, the other touches; the smaller gap wins.
        let c = find_contacts(
            &Bed::of_discs([3.9, 10.0], true, &[(0.0, 1.0, 1.0), (2.0, 1.0, 1.0)]),
            1e-9,
        );
        assert_eq!(c.pairs.len(), 1);
        assert!((c.pairs[0].gap + 0.1).abs() < 1e-12);
    }

    #[test]
    fn beads_of_one_body_are_not_contacts_and_bodies_count_once() {
        let mut bed = Bed::of_discs([20.0, 10.0], false, &[]);
        // A horizontal chain of two touching beads and a disc resting on both.
        bed.push_bead(Vector([5.0, 1.0]), 1.0, 0, 0);
        bed.push_bead(Vector([7.0, 1.0]), 1.0, 0, 0);
        bed.push(Vector([6.0, 1.0 + 3.0f64.sqrt()]), 1.0, 1);
        let c = find_contacts(&bed, 1e-9);
        let pairs: Vec<(u32, u32)> = c.pairs.iter().map(|p| (p.i, p.j)).collect();
        assert_eq!(pairs, vec![(0, 2), (1, 2)]);
        // Two bead contacts, one touching body each way.
        assert_eq!(coordination(&bed, &c), vec![1, 1, 1]);
    }

    #[test]
    fn simple_cubic_lattice_has_six_neighbours_inside() {
        let mut bed = Bed::new(
            Container {
                size: Vector([3.0, 3.0, 3.0]),
                periodic: false,
            },
            Vec::new(),
        );
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    bed.push(
                        Vector([i as Real + 0.5, j as Real + 0.5, k as Real + 0.5]),
                        0.5,
                        0,
                    );
                }
            }
        }
        let c = find_contacts(&bed, 1e-9);
        assert_eq!(c.pairs.len(), 3 * 9 * 2);
        let z = coordination(&bed, &c);
        assert_eq!(z[13], 6); // the centre sphere
        assert_eq!(z[0], 3); // a corner
        assert_eq!(z.iter().sum::<u32>(), 2 * 54);
        // Nine spheres against each of the floor and four side walls; the roof is
        // not a wall.
        assert_eq!(c.walls.len(), 5 * 9);
    }

    #[test]
    fn huge_or_nan_tolerance_does_not_break_the_cell_list() {
        let bed = Bed::of_discs([10.0, 10.0], true, &[(1.0, 1.0, 1.0), (9.0, 9.0, 0.5)]);
        assert_eq!(find_contacts(&bed, 1e300).pairs.len(), 1);
        assert_eq!(find_contacts(&bed, Real::INFINITY).pairs.len(), 1);
        let none = find_contacts(&bed, Real::NAN);
        assert!(none.pairs.is_empty() && none.walls.is_empty());
    }

    #[test]
    fn empty_and_single_beds() {
        let empty = Bed::of_discs([4.0, 4.0], false, &[]);
        assert_eq!(find_contacts(&empty, 1e-6), Contacts::default());
        assert!(coordination(&empty, &Contacts::default()).is_empty());
        let one = Bed::of_discs([4.0, 4.0], true, &[(2.0, 1.0, 1.0)]);
        assert_eq!(find_contacts(&one, 1e-6).pairs.len(), 0);
    }

    /// Brute force over all pairs and the images within two periods.
    fn brute<const D: usize>(bed: &Bed<D>, tol: Real) -> Vec<(u32, u32, Real)> {
        let mut out = Vec::new();
        for i in 0..bed.len() {
            for j in i + 1..bed.len() {
                if bed.bodies[i] == bed.bodies[j] {
                    continue;
                }
                let mut best = Real::INFINITY;
                let span: i32 = if bed.container.periodic { 2 } else { 0 };
                for a in -span..=span {
                    for b in if D == 3 { -span..=span } else { 0..=0 } {
                        let mut d = bed.centres[j] - bed.centres[i];
                        d[0] += a as Real * bed.container.size[0];
                        if D == 3 {
                            d[1] += b as Real * bed.container.size[1];
                        }
                        best = best.min(d.norm());
                    }
                }
                let gap = best - bed.radii[i] - bed.radii[j];
                if gap <= tol * bed.radii[i].min(bed.radii[j]) {
                    out.push((i as u32, j as u32, gap));
                }
            }
        }
        out
    }

    proptest! {
        #[test]
        fn cell_list_finds_exactly_the_brute_force_contacts(
            periodic in any::<bool>(),
            w in 1.5f64..30.0,
            pts in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0, 0.2f64..1.0), 0..400),
            tol in 0.0f64..0.5,
        ) {
            let mut bed = Bed::new(
                Container { size: Vector([w, 0.8 * w, 8.0]), periodic },
                Vec::new(),
            );
            for &(x, y, z, r) in &pts {
                bed.push(Vector([x * w, y * 0.8 * w, z * 8.0]), r, 0);
            }
            let got: Vec<(u32, u32, Real)> =
                find_contacts(&bed, tol).pairs.iter().map(|c| (c.i, c.j, c.gap)).collect();
            let want = brute(&bed, tol);
            prop_assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                prop_assert_eq!((g.0, g.1), (w.0, w.1));
                prop_assert!((g.2 - w.2).abs() < 1e-12);
            }
        }
    }
}
