//! An independent checker of the deposition model's invariants, from positions
//! only: no overlap between bodies, every particle inside the box, and every body
//! at rest (gravity balanced by compressive contact forces).
//!
//! It shares no code with the deposition engine (its own cell list, its own
//! non-negative least squares), so that a test using it checks the engine rather
//! than repeating it.

// `!(a > b)` is meant: NaN inputs must take the safe branch (nothing, or a
// reported violation), which `a <= b` would not.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::cells::CellList;
use crate::bed::Bed;
use crate::config::Settling;
use crate::math::{Real, Vector};
use std::fmt;

/// Which contacts of a body may hold it up in the rest test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Supports {
    /// Walls, and particles of bodies deposited earlier (lower index in the bed).
    /// This is exactly the model's invariant: a body came to rest on what was
    /// there when it arrived; bodies that arrived later cannot have held it up,
    /// and counting them could hide a body left hanging by the engine. It still
    /// accepts a body wedged under an earlier overhang (a support with a downward
    /// normal), which sequential deposition can produce.
    Earlier,
    /// Walls, and contacts whose normal on the body does not point down. For beds
    /// of unknown deposition order (imported data); rejects wedged bodies.
    Below,
    /// Every contact: the weakest test, static equilibrium of the final packing
    /// with any compressive forces.
    All,
}

/// What [`check_bed_with`] checks, and with which tolerances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InvariantChecks {
    /// Gap tolerance, relative to the (smaller) radius: pairs with `gap ≤ tol·r`
    /// touch, overlaps beyond `tol·r` are violations, and so are particles sticking
    /// out of a wall by more than `tol·r`. An overlapping pair still counts as a
    /// support in the rest test, so that one fault is reported once (as an overlap).
    pub tol: Real,
    /// Largest allowed distance between "up" and the cone of contact normals (the
    /// NNLS residual; "up" has length 1).
    pub rest_tol: Real,
    /// Also check that no particle sticks out above the roof.
    pub roof: bool,
    /// Which contacts can support a body.
    pub supports: Supports,
    /// Run the rest test at all (off for RSA beds, which are not at rest).
    pub rest: bool,
}

impl InvariantChecks {
    /// The model's invariants with gap tolerance `tol`: no roof check, supports
    /// from earlier bodies, rest residual 1e-7.
    pub fn new(tol: Real) -> Self {
        InvariantChecks {
            tol,
            rest_tol: 1e-7,
            roof: false,
            supports: Supports::Earlier,
            rest: true,
        }
    }

    /// The rest test of beds settled by `rule`: a body stopped by its contacts
    /// or by sticking need only touch a support (the residual of a body with
    /// none is the whole weight, 1); one held by friction may be left with an
    /// unbalanced share of its weight up to the sine of the friction angle
    /// (for a sphere, the slope it stopped on).
    pub fn held_by(self, rule: &Settling) -> Self {
        let rest_tol = if rule.contacts.is_some() || rule.sticks() {
            1.0 - 1e-9
        } else if let Some(s) = rule.slope {
            s + self.rest_tol
        } else {
            self.rest_tol
        };
        InvariantChecks { rest_tol, ..self }
    }
}

/// One broken invariant, with what is needed to find and understand it.
#[derive(Clone, Debug, PartialEq)]
pub enum Violation {
    /// A particle with a non-finite centre or a non-positive radius.
    Invalid {
        /// Particle id.
        i: u32,
    },
    /// Two particles of different bodies overlap beyond the tolerance.
    Overlap {
        /// First particle.
        i: u32,
        /// Second particle.
        j: u32,
        /// Overlap depth relative to the smaller radius.
        overlap: Real,
    },
    /// A particle sticks out of the box.
    Outside {
        /// Particle id.
        i: u32,
        /// `floor`, `x0`, `x1`, `y0`, `y1` or `roof`.
        wall: &'static str,
        /// How far it sticks out, relative to its radius.
        by: Real,
    },
    /// A body that is not held up by compressive contact forces.
    NotAtRest {
        /// Body id.
        body: u32,
        /// Its first particle.
        i: u32,
        /// Distance from "up" to the cone of support normals.
        residual: Real,
        /// Number of supporting contacts found.
        supports: usize,
        /// Height of its first particle's centre.
        height: Real,
    },
}

/// The result of [`check_bed`]: counts of each kind of violation, the worst
/// values, and the first few violations of each kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// Particles checked.
    pub particles: usize,
    /// Bodies checked.
    pub bodies: usize,
    /// Particles with a non-finite centre or a non-positive radius.
    pub invalid: usize,
    /// Largest overlap between different bodies, relative to the smaller radius
    /// (0 when nothing overlaps).
    pub max_overlap: Real,
    /// Pairs overlapping by more than the tolerance.
    pub overlaps: usize,
    /// Particles sticking out of the box by more than the tolerance.
    pub outside: usize,
    /// Bodies failing the rest test.
    pub not_at_rest: usize,
    /// Largest rest residual over all bodies.
    pub max_rest_residual: Real,
    /// The first few violations of each kind.
    pub examples: Vec<Violation>,
}

/// How many violations of each kind are kept as examples.
const EXAMPLES: usize = 5;

impl Report {
    /// True when no invariant is broken.
    pub fn is_ok(&self) -> bool {
        self.invalid == 0 && self.overlaps == 0 && self.outside == 0 && self.not_at_rest == 0
    }

    /// Keeps `v` as an example if fewer than [`EXAMPLES`] of its kind are kept.
    fn example(&mut self, v: Violation) {
        let kind = std::mem::discriminant(&v);
        let n = self
            .examples
            .iter()
            .filter(|e| std::mem::discriminant(*e) == kind)
            .count();
        if n < EXAMPLES {
            self.examples.push(v);
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} particles, {} bodies: {} invalid, {} overlaps (max {:.3e} r), \
             {} outside, {} not at rest (max residual {:.3e})",
            self.particles,
            self.bodies,
            self.invalid,
            self.overlaps,
            self.max_overlap,
            self.outside,
            self.not_at_rest,
            self.max_rest_residual
        )?;
        for e in &self.examples {
            writeln!(f, "  {e:?}")?;
        }
        Ok(())
    }
}

/// Checks the model's invariants (see [`InvariantChecks::new`]) with gap tolerance `tol`.
pub fn check_bed<const D: usize>(bed: &Bed<D>, tol: Real) -> Report {
    check_bed_with(bed, &InvariantChecks::new(tol))
}

/// A contact seen from one particle: its normal (from the contact point towards
/// the particle's centre), the contact point relative to the centre, and the
/// other particle (`None` for a wall).
#[derive(Clone, Copy)]
struct Touch<const D: usize> {
    normal: Vector<D>,
    arm: Vector<D>,
    other: Option<usize>,
}

/// Checks `bed` as configured by `checks`.
pub fn check_bed_with<const D: usize>(bed: &Bed<D>, checks: &InvariantChecks) -> Report {
    let n = bed.len();
    let tol = checks.tol;
    let mut report = Report {
        particles: n,
        ..Report::default()
    };
    let valid: Vec<bool> = (0..n)
        .map(|i| bed.centres[i].is_finite() && bed.radii[i] > 0.0 && bed.radii[i].is_finite())
        .collect();
    for i in 0..n {
        if !valid[i] {
            report.invalid += 1;
            report.example(Violation::Invalid { i: i as u32 });
        }
    }

    let mut touches: Vec<Vec<Touch<D>>> = vec![Vec::new(); n];
    let periods: Vec<Vector<D>> = periodic_shifts(bed);
    let cells = CellList::new(bed, tol);
    let other_bodies = |i: usize, j: usize| valid[i] && valid[j] && bed.bodies[i] != bed.bodies[j];
    cells.for_each_pair_where(other_bodies, |i, j| {
        let (ri, rj) = (bed.radii[i], bed.radii[j]);
        let r_min = ri.min(rj);
        let d0 = bed.container.displacement(&bed.centres[i], &bed.centres[j]);
        let gap0 = d0.norm() - ri - rj;
        if gap0 < -tol * r_min {
            report.overlaps += 1;
            report.example(Violation::Overlap {
                i: i as u32,
                j: j as u32,
                overlap: -gap0 / r_min,
            });
        }
        if -gap0 / r_min > report.max_overlap {
            report.max_overlap = -gap0 / r_min;
        }
        // In a box one or two diameters wide a pair can touch through two images;
        // each is a separate contact force.
        for s in &periods {
            let d = d0 + *s;
            let dist = d.norm();
            if dist - ri - rj <= tol * r_min && dist > 0.0 {
                let u = d / dist;
                touches[i].push(Touch {
                    normal: -u,
                    arm: u * ri,
                    other: Some(j),
                });
                touches[j].push(Touch {
                    normal: u,
                    arm: -u * rj,
                    other: Some(i),
                });
            }
        }
    });

    let walls = bed.container.walls();
    for i in 0..n {
        if !valid[i] {
            continue;
        }
        let (c, r) = (bed.centres[i], bed.radii[i]);
        for &wall in &walls {
            let gap = bed.container.wall_distance(wall, &c) - r;
            if gap < -tol * r {
                report.outside += 1;
                report.example(Violation::Outside {
                    i: i as u32,
                    wall: wall.name(),
                    by: -gap / r,
                });
            }
            if gap <= tol * r {
                let normal = bed.container.wall_normal(wall);
                touches[i].push(Touch {
                    normal,
                    arm: -normal * r,
                    other: None,
                });
            }
        }
        let above = c.height() + r - bed.container.height();
        if checks.roof && above > tol * r {
            report.outside += 1;
            report.example(Violation::Outside {
                i: i as u32,
                wall: "roof",
                by: above / r,
            });
        }
    }

    // Bodies: particle ids grouped by body, in order of first appearance.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| (bed.bodies[i], i));
    let mut first = vec![0usize; n];
    let mut groups: Vec<&[usize]> = Vec::new();
    let mut s = 0;
    while s < n {
        let mut e = s + 1;
        while e < n && bed.bodies[order[e]] == bed.bodies[order[s]] {
            e += 1;
        }
        for &i in &order[s..e] {
            first[i] = order[s];
        }
        groups.push(&order[s..e]);
        s = e;
    }
    report.bodies = groups.len();
    if !checks.rest {
        return report;
    }
    for beads in groups {
        if beads.iter().any(|&i| !valid[i]) {
            continue;
        }
        let (residual, supports) = rest_residual(bed, beads, &touches, &first, checks.supports);
        report.max_rest_residual = report.max_rest_residual.max(residual);
        if !(residual <= checks.rest_tol) {
            report.not_at_rest += 1;
            let i = beads[0];
            report.example(Violation::NotAtRest {
                body: bed.bodies[i],
                i: i as u32,
                residual,
                supports,
                height: bed.centres[i].height(),
            });
        }
    }
    report
}

/// The image shifts to try for a pair on top of the minimum image: none for a
/// walled box, every combination of ±1 period on the periodic axes otherwise.
fn periodic_shifts<const D: usize>(bed: &Bed<D>) -> Vec<Vector<D>> {
    let mut shifts = vec![Vector::zero()];
    if bed.container.periodic {
        for k in 0..D - 1 {
            let w = bed.container.size[k];
            let mut next = Vec::with_capacity(3 * shifts.len());
            for s in &shifts {
                for m in [-1.0, 0.0, 1.0] {
                    let mut t = *s;
                    t[k] += m * w;
                    next.push(t);
                }
            }
            shifts = next;
        }
    }
    shifts
}

/// Rest test of one body: the distance from the wrench of gravity (force up, no
/// torque about the centre of mass) to the cone of its support wrenches, and the
/// number of supports. A single sphere needs only the force part: its normals all
/// pass through its centre.
fn rest_residual<const D: usize>(
    bed: &Bed<D>,
    beads: &[usize],
    touches: &[Vec<Touch<D>>],
    first: &[usize],
    supports: Supports,
) -> (Real, usize) {
    let own = first[beads[0]];
    // Unwrap the beads around the first one, so that a chain crossing a periodic
    // side has a sensible centre of mass.
    let base = bed.centres[beads[0]];
    let pos: Vec<Vector<D>> = beads
        .iter()
        .map(|&i| base + bed.container.displacement(&base, &bed.centres[i]))
        .collect();
    let mut com = Vector::zero();
    let mut mass = 0.0;
    for (k, &i) in beads.iter().enumerate() {
        let m = bed.radii[i].powi(D as i32);
        com += pos[k] * m;
        mass += m;
    }
    com = com / mass;
    let mut length: Real = 0.0;
    for (k, &i) in beads.iter().enumerate() {
        length = length.max((pos[k] - com).norm() + bed.radii[i]);
    }
    let rigid = beads.len() > 1;
    let torque_dims = if D == 2 { 1 } else { 3 };
    let q = if rigid { D + torque_dims } else { D };
    let mut cols: Vec<[Real; 6]> = Vec::new();
    for (k, &i) in beads.iter().enumerate() {
        for t in &touches[i] {
            let keep = match supports {
                Supports::All => true,
                Supports::Earlier => t.other.is_none_or(|j| first[j] < own),
                Supports::Below => t.other.is_none() || t.normal.height() >= 0.0,
            };
            if !keep {
                continue;
            }
            let mut col = [0.0; 6];
            col[..D].copy_from_slice(&t.normal.0);
            if rigid {
                // Torque about the centre of mass, scaled by the body's size so that
                // force and torque parts are comparable (dimensionless residual).
                let arm = (pos[k] - com + t.arm) / length;
                let (a, nv) = (arm.0, t.normal.0);
                if D == 2 {
                    col[2] = a[0] * nv[1] - a[1] * nv[0];
                } else {
                    col[3] = a[1] * nv[2] - a[2] * nv[1];
                    col[4] = a[2] * nv[0] - a[0] * nv[2];
                    col[5] = a[0] * nv[1] - a[1] * nv[0];
                }
            }
            cols.push(col);
        }
    }
    let mut target = [0.0; 6];
    target[D - 1] = 1.0;
    (nnls_residual(&cols, q, &target), cols.len())
}

/// Distance from `b` to the cone `{Σ λ_k a_k : λ ≥ 0}` in `q ≤ 6` dimensions
/// (Lawson–Hanson active set, [`crate::math::nnls_qr`], which the chain
/// settling's rare path shares). Any number of columns, unlike the fast solver,
/// since a large sphere among small ones can have many supports.
fn nnls_residual(a: &[[Real; 6]], q: usize, b: &[Real; 6]) -> Real {
    let (r, _) = crate::math::nnls_qr(a, q, b);
    r[..q].iter().map(|x| x * x).sum::<Real>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;

    /// The support wrenches of a 5-bead chain lying in the groove between two
    /// parallel chains, from a deposited 3D bed (body 7686 of the 10^4-chain
    /// throughput bed): ten nearly dependent columns. A reference NNLS (SciPy)
    /// balances gravity with them to 2e-17.
    #[test]
    fn chain_in_a_groove_of_nearly_parallel_supports_balances() {
        const COLS: [[Real; 6]; 10] = [
            [
                -0.4927874850543268,
                -0.36704409018248174,
                0.7889481164410913,
                -0.5589587824351661,
                0.07599485635314736,
                -0.3137778322524824,
            ],
            [
                -0.4725997745571843,
                0.1255478716342477,
                0.8722884758017896,
                -0.27947939121762844,
                0.03799742817657785,
                -0.1568889161262654,
            ],
            [
                -0.49278786246061157,
                -0.3670440388709656,
                0.7889479045797577,
                -0.27947931879257465,
                0.037997446294025225,
                -0.15688904075501725,
            ],
            [
                0.7804882348811952,
                -0.1456555419544583,
                0.6079659351559009,
                2.8799051920974747e-16,
                0.0,
                -3.6971349709403715e-16,
            ],
            [
                -0.47260015196342486,
                0.1255479229458455,
                0.8722882639403855,
                4.13198726287753e-16,
                -0.0,
                2.238684032644872e-16,
            ],
            [
                -0.49278823986680714,
                -0.367043987559383,
                0.7889476927182699,
                3.73720701303772e-16,
                -0.0,
                2.334314027369103e-16,
            ],
            [
                -0.4726005293695757,
                0.1255479742574195,
                0.872288052078816,
                0.2794792463675074,
                -0.03799746441147067,
                0.15688916538376158,
            ],
            [
                -0.4927886172729092,
                -0.3670439362477307,
                0.7889474808566324,
                0.2794791739424001,
                -0.03799748252891079,
                0.15688929001248347,
            ],
            [
                -0.47260090677563205,
                0.1255480255689684,
                0.8722878402170834,
                0.5589583478847341,
                -0.07599496505781564,
                0.31377858002492615,
            ],
            [
                -0.49278899467891296,
                -0.3670438849360059,
                0.7889472689948488,
                0.5589582030344704,
                -0.07599500129268882,
                0.3137788292823401,
            ],
        ];
        let target = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        let r = nnls_residual(&COLS, 6, &target);
        assert!(r < 1e-9, "residual {r}");
        // Without the groove's far side (column 3) no balance: the chain
        // would roll off.
        let one_side: Vec<[Real; 6]> = COLS
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != 3)
            .map(|(_, c)| *c)
            .collect();
        assert!(nnls_residual(&one_side, 6, &target) > 0.1);
    }

    fn bed2(size: [Real; 2], periodic: bool) -> Bed<2> {
        Bed::new(
            Container {
                size: Vector(size),
                periodic,
            },
            Vec::new(),
        )
    }

    fn v2(x: Real, y: Real) -> Vector<2> {
        Vector([x, y])
    }

    const S3: Real = 1.732_050_807_568_877_2;

    fn not_at_rest(report: &Report) -> Vec<u32> {
        report
            .examples
            .iter()
            .filter_map(|v| match v {
                Violation::NotAtRest { body, .. } => Some(*body),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn disc_on_two_discs_rests_and_on_one_does_not() {
        let mut bed = bed2([10.0, 10.0], false);
        bed.push(v2(4.0, 1.0), 1.0, 0);
        bed.push(v2(6.0, 1.0), 1.0, 0);
        bed.push(v2(5.0, 1.0 + S3), 1.0, 0);
        let report = check_bed(&bed, 1e-9);
        assert!(report.is_ok(), "{report}");
        assert_eq!(report.bodies, 3);
        assert!(report.max_rest_residual < 1e-15);

        // On one disc, 30° off its top: it would roll off.
        let mut bed = bed2([10.0, 10.0], false);
        bed.push(v2(4.0, 1.0), 1.0, 0);
        bed.push(v2(5.0, 1.0 + S3), 1.0, 0);
        let report = check_bed(&bed, 1e-9);
        assert_eq!(report.not_at_rest, 1, "{report}");
        assert_eq!(not_at_rest(&report), vec![1]);
        // The single support balances the part of "up" along its normal and leaves
        // the tangential part, sin 30° = 1/2.
        assert!((report.max_rest_residual - 0.5).abs() < 1e-12);
        assert_eq!((report.overlaps, report.outside), (0, 0));
    }

    #[test]
    fn disc_straight_on_top_of_another_rests() {
        let mut bed = bed2([10.0, 10.0], false);
        bed.push(v2(4.0, 1.0), 1.0, 0);
        bed.push(v2(4.0, 3.0), 1.0, 0);
        assert!(check_bed(&bed, 1e-9).is_ok());
    }

    #[test]
    fn disc_against_a_wall_with_a_support_on_the_other_side_rests() {
        let mut bed = bed2([10.0, 10.0], false);
        let s2 = 2f64.sqrt();
        bed.push(v2(1.0 + s2, 1.0), 1.0, 0);
        bed.push(v2(1.0, 1.0 + s2), 1.0, 0);
        let report = check_bed(&bed, 1e-9);
        assert!(report.is_ok(), "{report}");
        // Without the wall (periodic sides) it slides off.
        bed.container.periodic = true;
        let report = check_bed(&bed, 1e-9);
        assert_eq!(not_at_rest(&report), vec![1], "{report}");
    }

    #[test]
    fn sphere_on_three_touching_spheres_rests_on_two_does_not() {
        let mut bed: Bed<3> = Bed::new(
            Container {
                size: Vector([10.0, 10.0, 10.0]),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push(Vector([4.0, 4.0, 1.0]), 1.0, 0);
        bed.push(Vector([6.0, 4.0, 1.0]), 1.0, 0);
        // In the groove between two spheres, off their vertical plane: it rolls
        // along the groove.
        let groove = Vector([5.0, 4.5, 1.0 + (3.0f64 - 0.25).sqrt()]);
        let mut two = bed.clone();
        two.push(groove, 1.0, 0);
        let report = check_bed(&two, 1e-9);
        assert_eq!(not_at_rest(&report), vec![2], "{report}");

        bed.push(Vector([5.0, 4.0 + S3, 1.0]), 1.0, 0);
        // Above the centroid of the triangle, at height 1 + 2 sqrt(2/3).
        bed.push(
            Vector([5.0, 4.0 + S3 / 3.0, 1.0 + 2.0 * (2.0f64 / 3.0).sqrt()]),
            1.0,
            0,
        );
        let report = check_bed(&bed, 1e-9);
        assert!(report.is_ok(), "{report}");
        let c = super::super::contacts::find_contacts(&bed, 1e-9);
        assert_eq!(c.pairs.len(), 6);
    }

    #[test]
    fn sphere_on_the_floor_rests_and_a_floating_one_does_not() {
        let mut bed: Bed<3> = Bed::new(
            Container {
                size: Vector([10.0, 10.0, 10.0]),
                periodic: true,
            },
            Vec::new(),
        );
        bed.push(Vector([5.0, 5.0, 2.0]), 2.0, 0);
        assert!(check_bed(&bed, 1e-9).is_ok());
        bed.push(Vector([1.0, 1.0, 5.0]), 1.0, 0);
        let report = check_bed(&bed, 1e-9);
        assert_eq!(not_at_rest(&report), vec![1]);
        // No support at all: the residual is "up" itself.
        assert_eq!(report.max_rest_residual, 1.0);
    }

    #[test]
    fn overlaps_and_particles_outside_are_reported() {
        let mut bed = bed2([10.0, 5.0], false);
        bed.push(v2(3.0, 1.0), 1.0, 0);
        bed.push(v2(4.9, 1.0), 1.0, 0);
        bed.push(v2(0.5, 1.0), 1.0, 0); // 0.5 r through the x0 wall
        bed.push(v2(8.0, 4.5), 1.0, 0); // above the roof, resting on nothing
        let report = check_bed(&bed, 1e-9);
        assert_eq!(report.overlaps, 1, "{report}");
        assert!((report.max_overlap - 0.1).abs() < 1e-12);
        assert!(report.examples.iter().any(
            |v| matches!(v, Violation::Overlap { i: 0, j: 1, overlap } if (overlap - 0.1).abs() < 1e-12)
        ));
        assert_eq!(report.outside, 1);
        assert!(report.examples.contains(&Violation::Outside {
            i: 2,
            wall: "x0",
            by: 0.5
        }));
        let roof = check_bed_with(
            &bed,
            &InvariantChecks {
                roof: true,
                ..InvariantChecks::new(1e-9)
            },
        );
        assert_eq!(roof.outside, 2);
        assert!(roof.examples.iter().any(
            |v| matches!(v, Violation::Outside { i: 3, wall: "roof", by } if (by - 0.5).abs() < 1e-12)
        ));
    }

    #[test]
    fn a_later_neighbour_cannot_hold_a_body_up() {
        // Disc 1 sits 30° off the top of disc 0; disc 2, placed later, props it
        // from the side. Statically balanced, but not how it came to rest.
        let mut bed = bed2([20.0, 10.0], false);
        bed.push(v2(5.0, 1.0), 1.0, 0);
        bed.push(v2(6.0, 1.0 + S3), 1.0, 0);
        bed.push(v2(8.0, 1.0 + S3), 1.0, 0);
        let earlier = check_bed(&bed, 1e-9);
        assert_eq!(not_at_rest(&earlier), vec![1, 2], "{earlier}");
        let all = check_bed_with(
            &bed,
            &InvariantChecks {
                supports: Supports::All,
                ..InvariantChecks::new(1e-9)
            },
        );
        assert_eq!(not_at_rest(&all), vec![2], "{all}");
    }

    #[test]
    fn wedged_under_an_earlier_overhang_is_at_rest() {
        // Disc 1 rests 30° off the top of disc 0 and is stopped by disc 2, an earlier
        // disc above and to its right (normal on disc 1 points down-left).
        let d1 = v2(6.0, 1.0 + S3);
        let d2 = d1 + v2(2.0 * 0.6, 2.0 * 0.8);
        let mut wedge = bed2([20.0, 10.0], false);
        wedge.push(v2(5.0, 1.0), 1.0, 0);
        wedge.push(d2, 1.0, 0); // held by something not modelled here
        wedge.push(d1, 1.0, 0);
        let r = check_bed(&wedge, 1e-9);
        assert!(!not_at_rest(&r).contains(&2), "{r}");
        let below = check_bed_with(
            &wedge,
            &InvariantChecks {
                supports: Supports::Below,
                ..InvariantChecks::new(1e-9)
            },
        );
        assert!(not_at_rest(&below).contains(&2), "{below}");
    }

    #[test]
    fn chains_are_tested_as_rigid_bodies() {
        // A horizontal three-bead chain on the floor rests.
        let mut bed = bed2([20.0, 10.0], false);
        for k in 0..3 {
            bed.push_bead(v2(3.0 + 2.0 * k as Real, 1.0), 1.0, 0, 0);
        }
        let report = check_bed(&bed, 1e-9);
        assert!(report.is_ok(), "{report}");

        // Bridging two discs under its end beads: rests. On one end only: it tips.
        let mut bridge = bed2([20.0, 10.0], false);
        bridge.push(v2(3.0, 1.0), 1.0, 0);
        bridge.push(v2(7.0, 1.0), 1.0, 0);
        for k in 0..3 {
            bridge.push_bead(v2(3.0 + 2.0 * k as Real, 3.0), 1.0, 0, 2);
        }
        let report = check_bed(&bridge, 1e-9);
        assert!(report.is_ok(), "{report}");
        bridge.centres[1] = v2(15.0, 1.0);
        let report = check_bed(&bridge, 1e-9);
        assert_eq!(not_at_rest(&report), vec![2], "{report}");

        // A frictionless ladder against a wall slides down.
        let mut ladder = bed2([20.0, 20.0], false);
        let (c, s) = (0.6, 0.8);
        for k in 0..4 {
            let t = 2.0 * k as Real;
            ladder.push_bead(v2(1.0 + 6.0 * c - t * c, 1.0 + t * s), 1.0, 0, 0);
        }
        let report = check_bed(&ladder, 1e-9);
        assert_eq!(report.outside, 0, "{report}");
        assert_eq!(not_at_rest(&report), vec![0], "{report}");
        // Upright on its end bead it balances (torque-free floor force under its
        // centre of mass), however unstably.
        let mut upright = bed2([20.0, 20.0], false);
        for k in 0..4 {
            upright.push_bead(v2(5.0, 1.0 + 2.0 * k as Real), 1.0, 0, 0);
        }
        assert!(check_bed(&upright, 1e-9).is_ok());
    }

    #[test]
    fn pair_touching_through_two_images_gets_both_forces() {
        // Period 2√3: disc 1 rests on disc 0 and on disc 0's image one period to the
        // right, 30° either side of its vertical.
        let w = 2.0 * S3;
        let mut bed = bed2([w, 10.0], true);
        bed.push(v2(0.0, 1.0), 1.0, 0);
        bed.push(v2(S3, 2.0), 1.0, 0);
        let report = check_bed(&bed, 1e-9);
        assert!(report.is_ok(), "{report}");
        // The contact list still has the pair once.
        assert_eq!(
            super::super::contacts::find_contacts(&bed, 1e-9)
                .pairs
                .len(),
            1
        );
        // Shifted sideways it keeps only one of the two contacts and rolls.
        bed.centres[1] = v2(1.0, 1.0 + S3);
        let report = check_bed(&bed, 1e-9);
        assert_eq!(not_at_rest(&report), vec![1], "{report}");
    }

    #[test]
    fn invalid_particles_are_reported_not_propagated() {
        let mut bed = bed2([10.0, 10.0], false);
        bed.push(v2(Real::NAN, 1.0), 1.0, 0);
        bed.push(v2(5.0, 1.0), 0.0, 0);
        bed.push(v2(8.0, 1.0), 1.0, 0);
        let report = check_bed(&bed, 1e-9);
        assert_eq!(report.invalid, 2);
        assert_eq!(report.not_at_rest, 0);
        assert!(report.max_overlap.is_finite());
    }

    #[test]
    fn many_supports_are_fine() {
        // A large sphere resting on a ring of 20 small ones (more than the engine's
        // NNLS takes).
        let mut bed: Bed<3> = Bed::new(
            Container {
                size: Vector([20.0, 20.0, 20.0]),
                periodic: false,
            },
            Vec::new(),
        );
        let (big, small): (Real, Real) = (6.0, 0.5);
        let ring: Real = 3.3;
        let h = ((big + small) * (big + small) - ring * ring).sqrt();
        for k in 0..20 {
            let a = 2.0 * std::f64::consts::PI * k as Real / 20.0;
            bed.push(
                Vector([10.0 + ring * a.cos(), 10.0 + ring * a.sin(), small]),
                small,
                0,
            );
        }
        bed.push(Vector([10.0, 10.0, small + h]), big, 0);
        let report = check_bed(&bed, 1e-9);
        assert!(report.is_ok(), "{report}");
    }
}
