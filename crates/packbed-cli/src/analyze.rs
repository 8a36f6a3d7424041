//! `packbed analyze PATH`: analyse an existing bed file and write the run's
//! outputs minus the bed files (summary.json, contacts.csv, wall_contacts.csv).

use crate::bed_file::BedFileArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::{text, AnalysisConfig};
use std::path::PathBuf;

/// Arguments of `packbed analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub bed: BedFileArgs,
    #[command(flatten)]
    pub analysis: AnalysisConfig,
    #[command(flatten)]
    pub files: crate::run::FileArgs,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-analysis")]
    pub out: PathBuf,
}

/// Runs `packbed analyze`.
pub fn analyze(args: AnalyzeArgs) -> Result<()> {
    let settings = AnalysisConfig {
        contact_tol: args.bed.contact_tol,
        ..args.analysis.clone()
    };
    // The library names the settings as the command's options.
    if let Err(e) = settings.check_naming(&|key| match key {
        "large_radius" => "--large".into(),
        key => format!("--{}", key.replace('_', "-")),
    }) {
        bail!("{}", e.message());
    }
    // Refuse a bad export list or output folder before any work.
    let extras = args.files.extras();
    let hint = args.bed.hint()?;
    crate::run::check_out_dir(&args.out)?;
    let analyzed = packbed::analyze_file(&args.bed.path, hint.as_ref(), &settings)?;
    let written = analyzed
        .write_with(&args.out, &extras)
        .with_context(|| format!("--out {}", args.out.display()))?;
    let overlap = text::overlap_warning(&analyzed.summary);
    let summary = || text::analyze_text(&analyzed.summary, &args.out, &written.files);
    args.files
        .shown
        .report(summary, overlap.iter().chain(&written.warnings));
    Ok(())
}
