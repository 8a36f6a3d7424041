//! Measures of a bed's structure. Every measure takes a [`Bed`] (built by packbed
//! or read from a file) and never reaches back into the deposition engine.

mod cells;
pub mod contacts;
pub mod packing;
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
