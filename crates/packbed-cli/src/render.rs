//! `packbed render PATH`: draw a bed file.

use anyhow::{bail, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `packbed render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The bed file.
    pub path: PathBuf,
}

/// Runs `packbed render`.
pub fn render(args: RenderArgs) -> Result<()> {
    bail!("render {}: not implemented yet", args.path.display())
}
