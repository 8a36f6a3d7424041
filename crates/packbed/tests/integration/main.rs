//! The library's integration tests, one binary (one link, one run): physics
//! and invariants of deposition, the analysis, ensembles, pictures and files.
//! Shared helpers live in [`common`].

mod common;

mod analysis;
mod chain_orientation;
mod chains;
mod compaction;
mod ensemble;
mod feeds;
mod fibres;
mod filtration;
mod fragmentation;
mod length_scale;
mod medium;
mod medium_file;
mod mesh;
mod physics;
mod regressions;
#[cfg(feature = "render")]
mod render;
mod rsa;
mod settling;
mod sizes;
