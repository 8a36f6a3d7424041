//! Files: the tables (`particles.csv`, `contacts.csv`, `wall_contacts.csv`),
//! `summary.json`, exports and readers, and the atomic staging of an output
//! directory. Layouts are in `docs/reference/formats.md`; [`crate::output`] puts a
//! run's files together.

pub mod atomic;
pub mod capture;
pub mod export;
mod finite;
pub mod fragmentation;
pub mod liquid;
pub mod pores;
pub mod psd;
pub mod read;
pub mod solid_bridges;
pub mod summary;
pub mod tables;

pub use atomic::Staging;
pub use summary::{AnalyzeSummary, RunSummary, Timing};
