//! The run configuration: the TOML schema (strict: unknown keys are errors;
//! `docs/reference/formats.md`, "The config file") and its validation into a [`Plan`] the engine can run.

mod compaction;
mod edit;
mod feed;
mod feeds;
pub mod filtration;
pub mod fragmentation;
mod measures;
mod medium_file;
mod mesh;
mod plan;
mod schema;
mod settling;

#[cfg(feature = "cli")]
pub use edit::named;
pub(crate) use edit::{feed_parameter, species_parameter};
pub use edit::{parse_numbers, BoxSpec, Edit, MeasureList, Numbers, Overrides, SWEEP_PARAMETERS};

pub use compaction::{Compaction, CompactionConfig};
pub use feed::Feed;
pub use feeds::{FeedStage, FeedStageConfig};
pub use filtration::{Drive, FiltrationConfig};
pub use measures::*;
pub(crate) use mesh::Mesh;
pub use plan::*;
pub use schema::*;
pub use settling::{Momentum, Settling, SettlingConfig};

use crate::error::{Error, Result};
use crate::math::Real;

/// `v` if it is a positive number, else the error naming `what`.
fn positive(v: Real, what: &str) -> Result<Real> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::config(format!(
            "{what} must be a positive number, got {v}"
        )))
    }
}
