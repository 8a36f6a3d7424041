//! Measures of a bed's structure. Every measure takes a [`Bed`] (built by packbed
//! or read from a file) and never reaches back into the deposition engine.

pub mod contacts;
pub mod packing;
pub mod validate;

use crate::bed::Bed;
use crate::math::Real;
use serde::Serialize;

pub use contacts::{Contact, Contacts, WallContact};

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
}

/// `coordination.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CoordinationSummary {
    /// Mean number of touching bodies per body, over the whole bed.
    pub mean: Real,
    /// The same over bodies whose centre lies in the bulk region.
    pub mean_bulk: Real,
    /// Number of particles whose centre lies in the bulk region.
    pub bulk_particles: u64,
}

/// Runs the measures of this module on a bed. `contact_tol` is relative to the
/// smaller radius of each pair.
pub fn analyze<const D: usize>(bed: &Bed<D>, contact_tol: Real) -> (Contacts, Summary) {
    let _ = (bed, contact_tol);
    todo!("analysis")
}
