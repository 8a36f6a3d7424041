//! `packbed ensemble` and `packbed merge`: replicate beds and their statistics.

use anyhow::{bail, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `packbed ensemble`.
#[derive(Debug, Args)]
pub struct EnsembleArgs {
    /// Config file (TOML).
    pub config: Option<PathBuf>,
}

/// Arguments of `packbed merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard output directories.
    pub dirs: Vec<PathBuf>,
}

/// Runs `packbed ensemble`.
pub fn ensemble(_args: EnsembleArgs) -> Result<()> {
    bail!("ensemble: not implemented yet")
}

/// Runs `packbed merge`.
pub fn merge(_args: MergeArgs) -> Result<()> {
    bail!("merge: not implemented yet")
}
