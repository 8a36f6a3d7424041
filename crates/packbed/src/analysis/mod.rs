//! Measures of a bed's structure. Every measure takes a [`Bed`] (built by packbed
//! or read from a file) and never reaches back into the deposition engine.

mod cells;
pub mod contacts;
pub mod packing;
pub mod profile;
pub mod validate;

use crate::bed::Bed;
use crate::math::Real;
use serde::Serialize;

pub use contacts::{coordination, find_contacts, Contact, Contacts, WallContact};
pub use packing::{ball_box_volume, bulk_region, Region};

/// The scalar measures known so far, laid out as in `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Summary {
    /// Packing fractions.
    pub packing: PackingSummary,
    /// Coordination numbers.
    pub coordination: CoordinationSummary,
}

/// `packing.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct PackingSummary {
    /// Solid volume ÷ box volume (box up to the roof).
    pub global: Real,
    /// Solid fraction of the bulk region (see `spec/analysis.md`); 0 if the bed
    /// is too small to have a bulk region.
    pub bulk: Real,
    /// True when the bed has no bulk region (then `bulk` is 0, not a measurement).
    pub bulk_region_empty: bool,
}

/// `coordination.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CoordinationSummary {
    /// Mean number of touching bodies per body, over the whole bed.
    pub mean: Real,
    /// The same over particles whose centre lies in the bulk region (each with its
    /// body's number, so a chain counts once per bead inside).
    pub mean_bulk: Real,
    /// Number of particles whose centre lies in the bulk region.
    pub bulk_particles: u64,
}

/// Runs the measures of this module on a bed. `contact_tol` is relative to the
/// smaller radius of each pair.
pub fn analyze<const D: usize>(bed: &Bed<D>, contact_tol: Real) -> (Contacts, Summary) {
    let contacts = contacts::find_contacts(bed, contact_tol);
    let z = contacts::coordination(bed, &contacts);
    let volumes = packing::particle_volumes(bed);
    let region = packing::bulk_region(bed);

    // The mean over bodies: one entry per body, whatever its number of beads.
    let mut per_body: Vec<(u32, u32)> = bed.bodies.iter().copied().zip(z.iter().copied()).collect();
    per_body.sort_unstable();
    per_body.dedup_by_key(|e| e.0);
    let mean = mean_of(per_body.iter().map(|e| e.1));

    let (bulk, mean_bulk, bulk_particles) = match &region {
        Some(reg) => {
            let inside: Vec<u32> = (0..bed.len())
                .filter(|&i| reg.contains(&bed.centres[i]))
                .map(|i| z[i])
                .collect();
            (
                reg.fraction_of(bed, &volumes),
                mean_of(inside.iter().copied()),
                inside.len() as u64,
            )
        }
        None => (0.0, 0.0, 0),
    };
    let summary = Summary {
        packing: PackingSummary {
            global: packing::global_fraction_of(bed, &volumes),
            bulk,
            bulk_region_empty: region.is_none(),
        },
        coordination: CoordinationSummary {
            mean,
            mean_bulk,
            bulk_particles,
        },
    };
    (contacts, summary)
}

/// Mean of counts, 0 for none (never NaN).
fn mean_of(values: impl Iterator<Item = u32>) -> Real {
    let (mut sum, mut n) = (0.0, 0usize);
    for v in values {
        sum += Real::from(v);
        n += 1;
    }
    if n == 0 {
        0.0
    } else {
        sum / n as Real
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use crate::math::Vector;
    use std::f64::consts::PI;

    /// Discs of diameter 1 on the unit square lattice filling a 10 × 10 box.
    fn square_lattice(periodic: bool) -> Bed<2> {
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 10.0]),
                periodic,
            },
            Vec::new(),
        );
        for j in 0..10 {
            for i in 0..10 {
                bed.push(Vector([i as Real + 0.5, j as Real + 0.5]), 0.5, 0);
            }
        }
        bed
    }

    #[test]
    fn square_lattice_summary() {
        let (contacts, s) = analyze(&square_lattice(false), 1e-6);
        assert_eq!(contacts.pairs.len(), 2 * 10 * 9);
        assert!((s.packing.global - PI / 4.0).abs() < 1e-14);
        // Bulk: [2, 8] × [2, 7]: centres 2.5..7.5 by 2.5..6.5, all with 4 neighbours.
        assert!((s.packing.bulk - PI / 4.0).abs() < 1e-14);
        assert!(!s.packing.bulk_region_empty);
        assert_eq!(s.coordination.bulk_particles, 30);
        assert_eq!(s.coordination.mean_bulk, 4.0);
        // Corners 2, edges 3, inside 4: 2 × 180 contacts / 100 discs.
        assert!((s.coordination.mean - 3.6).abs() < 1e-14);
        // Periodic: every disc has four neighbours.
        let (contacts, s) = analyze(&square_lattice(true), 1e-6);
        assert_eq!(contacts.pairs.len(), 2 * 10 * 9 + 10);
        assert_eq!(s.coordination.bulk_particles, 50);
        assert_eq!(s.coordination.mean_bulk, 4.0);
    }

    #[test]
    fn chains_count_once_per_body() {
        let mut bed = Bed::new(
            Container {
                size: Vector([20.0, 20.0]),
                periodic: false,
            },
            Vec::new(),
        );
        // A three-bead chain on the floor and two discs on it, one over each joint.
        for k in 0..3 {
            bed.push_bead(Vector([3.0 + 2.0 * k as Real, 1.0]), 1.0, 0, 0);
        }
        let h = 1.0 + 3f64.sqrt();
        bed.push(Vector([4.0, h]), 1.0, 0);
        bed.push(Vector([6.0, h]), 1.0, 0);
        let (contacts, s) = analyze(&bed, 1e-9);
        // Bead pairs: 2 per disc; the discs also touch each other.
        assert_eq!(contacts.pairs.len(), 5);
        // Bodies: the chain touches 2 bodies, each disc touches the chain and the
        // other disc.
        assert!((s.coordination.mean - 2.0).abs() < 1e-15);
        assert!(s.packing.bulk_region_empty);
        assert_eq!(s.packing.bulk, 0.0);
    }

    #[test]
    fn empty_bed_gives_zeros_not_nan() {
        let bed: Bed<3> = Bed::new(
            Container {
                size: Vector([10.0, 10.0, 10.0]),
                periodic: true,
            },
            Vec::new(),
        );
        let (contacts, s) = analyze(&bed, 1e-6);
        assert_eq!(contacts, Contacts::default());
        assert_eq!(s.packing.global, 0.0);
        assert_eq!(s.packing.bulk, 0.0);
        assert!(s.packing.bulk_region_empty);
        assert_eq!(s.coordination.mean, 0.0);
        assert_eq!(s.coordination.mean_bulk, 0.0);
        assert_eq!(s.coordination.bulk_particles, 0);
    }
}
