//! The arguments every command reading a bed file shares (`analyze`,
//! `fragment`, `render`): the file, its box when the file has none, and the
//! contact tolerance.

use anyhow::{bail, Result};
use clap::Args;
use packbed::BoxHint;
use std::path::PathBuf;

/// A bed file and how to read it.
#[derive(Debug, Args)]
pub struct BedFileArgs {
    /// The bed file: packbed particles.csv, plain `x y [z] r` table, LAMMPS
    /// dump, extended XYZ or bed.vtu.
    pub path: PathBuf,
    /// Box: W,H (2D) or W,D,H (3D); wins over a box in the file or in the
    /// summary.json beside it.
    #[arg(long = "box", value_name = "W,[D,]H", allow_hyphen_values = true, value_parser = packbed::parse_numbers)]
    pub container: Option<packbed::Numbers>,
    /// Periodic side boundaries (with --box).
    #[arg(long)]
    pub periodic: bool,
    /// Contact tolerance relative to the smaller radius of each pair (0 to 1).
    #[arg(long, value_name = "T", default_value_t = packbed::DEFAULT_CONTACT_TOL,
          allow_hyphen_values = true)]
    pub contact_tol: f64,
}

impl BedFileArgs {
    /// The box of `--box` and `--periodic`, checked; `None` without `--box`.
    pub fn hint(&self) -> Result<Option<BoxHint>> {
        let hint = match (&self.container, self.periodic) {
            (Some(size), periodic) => BoxHint {
                size: size.clone(),
                periodic,
            },
            (None, true) => bail!("--periodic needs --box W,H or W,D,H"),
            (None, false) => return Ok(None),
        };
        packbed::check_box_hint(&hint)
            .map_err(|e| anyhow::anyhow!("{}", e.within("--box").message()))?;
        Ok(Some(hint))
    }

    /// Refuses a contact tolerance outside 0..=1 before any work.
    pub fn check_contact_tol(&self) -> Result<()> {
        match packbed::contact_tol_problem(self.contact_tol, "--contact-tol") {
            Some(why) => bail!("{why}"),
            None => Ok(()),
        }
    }
}
