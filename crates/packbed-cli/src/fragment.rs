//! `packbed fragment BED`: contact forces of a bed under load and the order
//! its bonds break (`docs/reference/fragmentation.md`).

use crate::bed_file::BedFileArgs;
use crate::parsers::parsed;
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::text;
use packbed::{Breaks, FragmentationConfig, Load};
use std::path::PathBuf;

/// Arguments of `packbed fragment`.
#[derive(Debug, Args)]
pub struct FragmentArgs {
    #[command(flatten)]
    pub bed: BedFileArgs,
    /// The load: shear (the source study's), compression or gravity.
    #[arg(long, value_name = "LOAD", default_value = "shear", value_parser = parsed::<Load>)]
    pub load: Load,
    /// Bonds to break: a number, or `failure` (until the bed fails).
    #[arg(long, value_name = "N|failure", default_value = "failure", value_parser = parsed::<Breaks>)]
    pub breaks: Breaks,
    /// Tangential over normal spring stiffness (k_n = 1).
    #[arg(
        long,
        value_name = "R",
        default_value_t = 1.0,
        allow_hyphen_values = true
    )]
    pub kt_kn: f64,
    #[command(flatten)]
    pub shown: crate::run::Shown,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-fragment")]
    pub out: PathBuf,
}

/// Runs `packbed fragment`.
pub fn fragment(args: FragmentArgs) -> Result<()> {
    let options = FragmentationConfig {
        load: args.load,
        breaks: args.breaks,
        kt_over_kn: args.kt_kn,
    };
    let option = |key: &str| match key {
        "kt_over_kn" => "--kt-kn".to_string(),
        key => format!("--{key}"),
    };
    if let Err(e) = options.check_naming(&option) {
        bail!("{}", e.message());
    }
    args.bed.check_contact_tol()?;
    let hint = args.bed.hint()?;
    crate::run::check_out_dir(&args.out)?;
    // Each break re-solves the bed: thousands of them take minutes.
    let mut progress = crate::progress::Progress::breaks(args.breaks, args.shown.quiet);
    let done = packbed::fragment_file_with(
        &args.bed.path,
        hint.as_ref(),
        &options,
        args.bed.contact_tol,
        &mut |n| progress.update(n),
    );
    progress.finish();
    let done = done?;
    let written = done
        .write(&args.out, !args.shown.no_pictures)
        .with_context(|| format!("--out {}", args.out.display()))?;
    let summary = || text::fragment_text(&done.summary, &args.out, &written.files);
    args.shown.report(summary, &written.warnings);
    Ok(())
}
