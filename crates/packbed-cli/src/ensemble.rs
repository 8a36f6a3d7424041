//! `packbed ensemble` and `packbed merge`: replicate beds and their statistics.
//! The work is in `packbed::ensemble`; this file parses, shows progress and
//! prints a short summary.

use crate::parsers::at_least_one;
use crate::run::check_out_dir;
use anyhow::{Context, Result};
use clap::Args;
use indicatif::ProgressDrawTarget;
use packbed::{text, Config, EnsembleOptions, Shard, Tick};
use std::path::PathBuf;

/// The replicates of `packbed ensemble` and `packbed slurm`: the config, its
/// overrides and how many beds.
#[derive(Debug, Args)]
pub struct Replicates {
    /// Config file (TOML); without it, the default bed. A `[sweep]` table runs
    /// every value of one parameter.
    #[arg(value_name = "CONFIG.toml")]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: packbed::Overrides,
    /// Replicate beds (per sweep value); default: `[ensemble] runs` of the config.
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = at_least_one)]
    pub runs: Option<usize>,
}

impl Replicates {
    /// The config, checked for an ensemble (every sweep value), and the
    /// number of replicates.
    pub fn load(&self) -> Result<(Config, u64)> {
        let settings = &self.overrides;
        let config = settings.applied_to_file(self.config.as_deref())?;
        packbed::validate_ensemble(&config)
            .with_context(|| settings.source(self.config.as_deref()))?;
        let runs = packbed::ensemble_runs(self.runs.map(|n| n as u64), &config)?;
        Ok((config, runs))
    }
}

/// Arguments of `packbed ensemble`.
#[derive(Debug, Args)]
pub struct EnsembleArgs {
    #[command(flatten)]
    pub replicates: Replicates,
    /// Worker threads (one bed per thread); default: all cores.
    #[arg(long, short, value_name = "J", allow_negative_numbers = true, value_parser = at_least_one)]
    pub jobs: Option<usize>,
    /// Output directory; rerunning into it resumes an interrupted ensemble.
    #[arg(long, value_name = "DIR", default_value = "packbed-ensemble")]
    pub out: PathBuf,
    /// Run only replicates i with i mod M == K (then `packbed merge` the shards).
    #[arg(long, value_name = "K/M", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Also write every replicate's particles.csv and contact files.
    #[arg(long)]
    pub keep_beds: bool,
    #[command(flatten)]
    pub shown: crate::run::Shown,
}

/// Arguments of `packbed merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Output directories of the shards (`packbed ensemble --shard K/M --out DIR`).
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,
    /// Directory for the joined ensemble.
    #[arg(long, value_name = "DIR", default_value = "packbed-ensemble")]
    pub out: PathBuf,
    #[command(flatten)]
    pub shown: crate::run::Shown,
}

/// Runs `packbed ensemble`.
pub fn ensemble(args: EnsembleArgs) -> Result<()> {
    let (config, runs) = args.replicates.load()?;
    let threads = packbed::worker_threads(args.jobs);
    if let Some(j) = args.jobs.filter(|&j| j > threads) {
        eprintln!("packbed: note: --jobs {j} is more than the {threads} cores here; using {threads} threads");
    }
    let shard = match &args.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::ALL,
    };
    check_out_dir(&args.out)?;
    let opts = EnsembleOptions {
        runs,
        jobs: args.jobs,
        shard,
        keep_beds: args.keep_beds,
        pictures: !args.shown.no_pictures,
        stop: None,
    };
    let bar = crate::progress::terminal_bar(
        args.shown.quiet,
        None,
        ProgressDrawTarget::stderr(),
        "{spinner} {pos}/{len} beds  {per_sec}  ETA {eta}  [{bar:30}]",
    );
    let tick = |t: Tick| {
        if let Some(b) = &bar {
            if b.length() != Some(t.total) {
                b.set_length(t.total);
            }
            b.set_position(t.done);
        }
    };
    let outcome = packbed::run_ensemble(&config, &opts, &args.out, &tick);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let outcome = outcome?;
    if let Some(earlier) = outcome.reduced_from {
        eprintln!(
            "packbed: note: {}",
            text::reduced_note(&args.out, runs, earlier)
        );
    }
    let summary = || text::ensemble_text(&outcome, &args.out, Some(threads));
    args.shown.report(summary, &outcome.warnings);
    Ok(())
}

/// Runs `packbed merge`.
pub fn merge(args: MergeArgs) -> Result<()> {
    check_out_dir(&args.out)?;
    let outcome = packbed::merge_ensembles(&args.dirs, &args.out, !args.shown.no_pictures)?;
    let summary = || text::ensemble_text(&outcome, &args.out, None);
    args.shown.report(summary, &outcome.warnings);
    Ok(())
}
