//! `packbed analyze PATH`: analyse an existing bed file.

use anyhow::{bail, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `packbed analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// The bed file.
    pub path: PathBuf,
}

/// Runs `packbed analyze`.
pub fn analyze(args: AnalyzeArgs) -> Result<()> {
    bail!("analyze {}: not implemented yet", args.path.display())
}
