//! `packbed run`: config (file and overrides) → deposition → analysis → files.

use crate::overrides::Overrides;
use crate::progress::Progress;
use crate::report;
use anyhow::{Context, Result};
use clap::Args;
use packbed::bed::{AnyBed, Bed};
use packbed::config::Config;
use packbed::deposit::DepositReport;
use packbed::io::{self, RunSummary, Timing};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `packbed run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Config file (TOML); without it, the default bed (see `packbed example`).
    #[arg(value_name = "CONFIG.toml")]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: Overrides,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-out")]
    pub out: PathBuf,
    /// Also write these exports: a comma-separated list of vtk, dump, xyz.
    #[arg(long, value_name = "LIST")]
    pub export: Option<String>,
    /// No pictures or plots (bed.png, bed.svg, plot_*.png|svg).
    #[arg(long)]
    pub no_pictures: bool,
    /// No progress bar and no summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Runs `packbed run`.
pub fn run(args: RunArgs) -> Result<()> {
    let start = Instant::now();
    let config = load(&args)?;
    check_out_dir(&args.out)?;
    let extras = io::RunExtras {
        pictures: !args.no_pictures,
        exports: match &args.export {
            Some(list) => io::export::Format::parse_list(list)?,
            None => Vec::new(),
        },
    };
    let mut progress = Progress::new(&config, args.quiet);
    let built = packbed::deposit::build(&config, &mut |n| progress.update(n));
    progress.finish();
    let (bed, deposit) = built?;
    let written = match &bed {
        AnyBed::D2(b) => finish(&config, b, &deposit, &args.out, &extras, start)?,
        AnyBed::D3(b) => finish(&config, b, &deposit, &args.out, &extras, start)?,
    };
    if !args.quiet {
        print!("{}", report::run_text(&written.0, &args.out));
    }
    Ok(())
}

/// The config file (or the default) with the overrides applied, validated.
fn load(args: &RunArgs) -> Result<Config> {
    let mut config = match &args.config {
        Some(path) => Config::from_file(path)?,
        None => Config::default(),
    };
    args.overrides.apply(&mut config)?;
    // Validate now, so that a bad config fails before any work or output.
    match config.dim {
        2 => config.plan::<2>().map(drop),
        3 => config.plan::<3>().map(drop),
        d => Err(packbed::Error::config(format!(
            "dim must be 2 or 3, got {d}"
        ))),
    }
    .with_context(|| source_name(args))?;
    Ok(config)
}

/// Where the settings came from, to say where to look when they are wrong.
fn source_name(args: &RunArgs) -> String {
    let file = args.config.as_ref().map(|p| p.display().to_string());
    match (file, args.overrides.is_empty()) {
        (Some(f), true) => f,
        (Some(f), false) => format!("{f} with command-line options"),
        (None, false) => "command-line options".into(),
        (None, true) => "default config".into(),
    }
}

/// Refuses an output path that can never become a directory before the run, so
/// that a long run does not fail at its very end.
fn check_out_dir(out: &Path) -> Result<()> {
    let existing = out
        .ancestors()
        .find(|a| a.as_os_str().is_empty() || a.exists());
    match existing {
        Some(a) if !a.as_os_str().is_empty() && !a.is_dir() => anyhow::bail!(
            "--out {}: {} exists and is not a directory",
            out.display(),
            a.display()
        ),
        _ => Ok(()),
    }
}

/// Analyses the bed and writes the files; returns the summary and file paths.
fn finish<const D: usize>(
    config: &Config,
    bed: &Bed<D>,
    deposit: &DepositReport,
    out: &Path,
    extras: &io::RunExtras,
    start: Instant,
) -> Result<(RunSummary, Vec<PathBuf>)> {
    let t = Instant::now();
    let (contacts, analysis) = packbed::analysis::analyze(bed, config.analysis.contact_tol);
    let analysis_seconds = t.elapsed().as_secs_f64();
    let timing = Timing {
        deposit_seconds: deposit.deposit_seconds,
        analysis_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
    };
    let summary = RunSummary::new(config, bed, deposit, &analysis, timing);
    let files = io::write_run_with(out, bed, &contacts, &summary, extras)?;
    Ok((summary, files))
}
