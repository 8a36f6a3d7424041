//! `packbed analyze PATH`: analyse an existing bed file and write the run's
//! outputs minus the bed files (summary.json, contacts.csv, wall_contacts.csv).

use crate::bed_file::BedFileArgs;
use crate::overrides::named;
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::{text, AnalysisConfig, AngleFrom, LengthUnit};
use std::path::PathBuf;

/// Arguments of `packbed analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub bed: BedFileArgs,
    /// Percolation threshold: particles with radius >= R count as large
    /// (default: the largest of the species' volume-median radii).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub large: Option<f64>,
    /// Bulk measures are null when the bulk region holds fewer bodies.
    #[arg(long, value_name = "N", default_value_t = packbed::BULK_MIN_BODIES)]
    pub bulk_min_bodies: u64,
    /// Measure chain angles from the vertical (default) or from the horizontal
    /// (as the source study did).
    #[arg(long, value_name = "FROM", default_value = "vertical",
          value_parser = named::<AngleFrom>(&["vertical", "horizontal"]))]
    pub chain_angle_from: AngleFrom,
    /// Density of the solid in kg/m³ (with --length-unit): the specific cake
    /// resistance and the solids' mass per area.
    #[arg(long, value_name = "KG_PER_M3")]
    pub solid_density: Option<f64>,
    /// The length of one unit of the bed file's lengths: permeabilities in m².
    #[arg(long, value_name = "UNIT", value_parser = named::<LengthUnit>(&["m", "mm", "um", "nm"]))]
    pub length_unit: Option<LengthUnit>,
    #[command(flatten)]
    pub measures: crate::overrides::MeasuresArg,
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
        large_radius: args.large,
        bulk_min_bodies: args.bulk_min_bodies,
        chain_angle_from: args.chain_angle_from,
        measures: args.measures.list.clone(),
        solid_density: args.solid_density,
        length_unit: args.length_unit,
        flow: Default::default(),
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
    eprint!(
        "{}",
        text::warning_lines(overlap.iter().chain(&written.warnings))
    );
    if !args.files.shown.quiet {
        print!(
            "{}",
            text::analyze_text(&analyzed.summary, &args.out, &written.files)
        );
    }
    Ok(())
}
