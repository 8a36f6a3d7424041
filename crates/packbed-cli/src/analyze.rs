//! `packbed analyze PATH`: analyse an existing bed file and write the run's
//! outputs minus the bed files (summary.json, contacts.csv, wall_contacts.csv).
//! `--config FILE` takes the analysis of a config file's `[analysis]` table
//! (its drainage, drying and flow, which have no options), the options given
//! on the command line winning over it.

use crate::bed_file::BedFileArgs;
use anyhow::{bail, Context, Result};
use clap::parser::ValueSource;
use clap::{ArgMatches, Args};
use packbed::{text, AnalysisConfig};
use std::path::{Path, PathBuf};

/// Arguments of `packbed analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub bed: BedFileArgs,
    #[command(flatten)]
    pub analysis: AnalysisConfig,
    /// Config file (TOML) whose `[analysis]` table sets the analysis, with
    /// `[analysis.drainage]`, `[analysis.drying]` and `[analysis.flow]`
    /// (the rest of the file is not used); options given here win over it.
    #[arg(long, value_name = "CONFIG.toml")]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub files: crate::run::FileArgs,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-analysis")]
    pub out: PathBuf,
}

/// The option of an `[analysis]` key.
fn option_of(key: &str) -> String {
    match key {
        "large_radius" => "--large".into(),
        key => format!("--{}", key.replace('_', "-")),
    }
}

/// The analysis: the options' over the `[analysis]` of `--config`, and the
/// keys the options set. `matches` are the command's, to tell an option given
/// from its default.
fn settings(
    args: &AnalyzeArgs,
    matches: Option<&ArgMatches>,
) -> Result<(AnalysisConfig, Vec<&'static str>)> {
    let options = AnalysisConfig {
        contact_tol: args.bed.contact_tol,
        ..args.analysis.clone()
    };
    let Some(path) = &args.config else {
        return Ok((options, Vec::new()));
    };
    // An id the command does not have is never given (no panic).
    let given = |id: &str| {
        matches.is_some_and(|m| {
            matches!(m.try_get_raw(id), Ok(Some(_)))
                && m.value_source(id) == Some(ValueSource::CommandLine)
        })
    };
    let mut s = packbed::Config::from_file(path)
        .map_err(|e| anyhow::anyhow!("--config: {}", e.message()))?
        .analysis;
    let mut set = Vec::new();
    macro_rules! take {
        ($($key:ident),*) => {$(
            if given(stringify!($key)) {
                s.$key = options.$key.clone();
                set.push(stringify!($key));
            }
        )*};
    }
    take!(
        contact_tol,
        large_radius,
        bulk_min_bodies,
        chain_angle_from,
        measures,
        solid_density,
        length_unit
    );
    Ok((s, set))
}

/// Runs `packbed analyze`.
pub fn analyze(args: AnalyzeArgs, matches: Option<&ArgMatches>) -> Result<()> {
    let (settings, from_options) = settings(&args, matches)?;
    // The library names the settings as the command's options, or as the
    // keys of the config file they came from (the file named first).
    let file = args.config.as_deref().map(Path::display);
    if let Err(e) = settings.check_naming(&|key| match &file {
        Some(_) if !from_options.contains(&key) => format!("analysis.{key}"),
        _ => option_of(key),
    }) {
        match &file {
            Some(f) if e.message().starts_with("analysis.") => bail!("{f}: {}", e.message()),
            _ => bail!("{}", e.message()),
        }
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
