//! Ensembles of replicate beds: parallel runs, statistics, shards, resume.
//!
//! An ensemble runs replicates `0..runs` of one config (or of every value of a
//! [`sweep`]); replicate `i` uses the seed [`seeds::replicate_seed`]`(master, i)`.
//! Replicates run in parallel, one bed per thread, on a local rayon pool.
//!
//! Layout of an output directory `OUT`:
//! - `manifest.json`: the config (with the master seed), `runs`, the shard; a
//!   rerun into the same `OUT` must have the same config and shard, and skips
//!   the replicates already done (resume); `runs` may change (more replicates
//!   extend the ensemble).
//! - `runs/NNNN/summary.json`: replicate `NNNN`'s summary, written atomically
//!   (with `--keep-beds`, also its `particles.csv` and contact files);
//! - `ensemble.json`, `ensemble.csv`, `histograms.csv`, `ensemble.md`: the
//!   statistics ([`stats`], [`reports`]), which depend only on the replicates'
//!   summaries, folded in replicate order: the same for any thread count, and
//!   for shards joined by [`merge`];
//! - `timing.json`: wall times, kept apart because they differ between runs;
//! - `plot_*.png` and `plot_*.svg` (`render::ensemble_plots`, beside the run
//!   plots), unless pictures are off;
//! - with a sweep, the per-value files are under `sweep/NN-label/`, and
//!   `sweep.csv`, `sweep.md` and the `plot_sweep_*` plots compare the values.
//!
//! Modules: `replicates` (running them, resume), `manifest` (what
//! identifies an ensemble directory, shards), [`merge`] (joining shards),
//! [`write`] (the statistics files and plots), [`slurm`] (job scripts for a
//! Slurm cluster), and [`stats`] (from `analysis`), [`reports`], [`seeds`], [`sweep`].

pub mod compare;
pub(crate) mod manifest;
pub(crate) mod merge;
pub mod proof;
pub(crate) mod replicates;
pub mod seeds;
pub mod slurm;
pub use crate::analysis::stats;
pub mod reports;
pub mod sweep;
mod write;

pub use manifest::{fingerprint, Shard, MANIFEST};
pub use merge::merge_with;
pub use replicates::run;

use crate::config::Config;
use crate::error::{Error, Result};
use serde_json::Value;
use stats::Aggregate;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Largest `--runs`: every replicate's summary (a few kB) is held in memory
/// while the statistics are folded.
pub const MAX_RUNS: u64 = 1_000_000;
/// Files of the statistics of one ensemble (or one sweep value).
pub const ENSEMBLE_FILES: [&str; 5] = [
    "ensemble.json",
    "ensemble.csv",
    "histograms.csv",
    "ensemble.md",
    "timing.json",
];
/// Files of a sweep's comparison.
pub const SWEEP_FILES: [&str; 2] = ["sweep.csv", "sweep.md"];

/// How to run an ensemble.
#[derive(Clone, Debug)]
pub struct EnsembleOptions {
    /// Replicates per config (per sweep value), at least 1.
    pub runs: u64,
    /// Threads; `None`: all cores.
    pub jobs: Option<usize>,
    /// The part of the ensemble to run.
    pub shard: Shard,
    /// Write every replicate's bed files, not only its summary.
    pub keep_beds: bool,
    /// Write the plots (PNG and SVG) of the statistics.
    pub pictures: bool,
    /// Set from another thread to stop the ensemble (Ctrl-C in Python): no
    /// replicate starts after it, running ones stop within 4096 particles,
    /// and the run fails with [`Error::Interrupted`].
    /// The replicates finished before are on disk, and a rerun resumes.
    pub stop: Option<Arc<AtomicBool>>,
}

impl Default for EnsembleOptions {
    /// One replicate, all cores, the whole ensemble, summaries only, with plots.
    fn default() -> Self {
        EnsembleOptions {
            runs: 1,
            jobs: None,
            shard: Shard::ALL,
            keep_beds: false,
            pictures: true,
            stop: None,
        }
    }
}

/// Progress of an ensemble: replicates finished (resumed ones included) of all.
#[derive(Clone, Copy, Debug)]
pub struct Tick {
    /// Replicates done.
    pub done: u64,
    /// Replicates in this run (all sweep values, this shard).
    pub total: u64,
}

/// The statistics of one config (or sweep value) and where they were written.
#[derive(Clone, Debug)]
pub struct PointResult {
    /// Sweep label, or `None` for a plain ensemble.
    pub label: Option<String>,
    /// Directory of its files.
    pub dir: PathBuf,
    /// The config lists percolation in `[analysis] measures` itself, rather
    /// than getting it with the default set: then its details go on screen.
    pub percolation_asked: bool,
    /// The statistics.
    pub aggregate: Aggregate,
    /// Replicates built by this invocation.
    pub built: u64,
    /// Replicates found done in the directory (resumed).
    pub resumed: u64,
    /// The statistics files and plots written into `dir`.
    pub files: Vec<PathBuf>,
}

/// What an ensemble (or a merge) produced.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// One entry per sweep value, or one for a plain ensemble.
    pub points: Vec<PointResult>,
    /// Wall time of the invocation in seconds.
    pub wall_seconds: f64,
    /// The files written at the top of the output directory (the manifest, and
    /// the statistics and plots of a plain ensemble or the sweep's comparison).
    pub files: Vec<PathBuf>,
    /// The replicate count of the ensemble found in the output directory when
    /// it was larger than this run's: only the first `runs` were reused and
    /// the statistics cover those alone.
    pub reduced_from: Option<u64>,
    /// Plots that could not be drawn, the statistics written all the same.
    pub warnings: Vec<String>,
}

/// Worker threads for `jobs` (`None`: all cores), never more than the cores:
/// one bed per thread is CPU-bound, and extra threads only thrash the caches
/// (measured 70 × slower with `--jobs` far above the core count).
pub fn worker_threads(jobs: Option<usize>) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    jobs.map_or(cores, |j| j.clamp(1, cores))
}

/// One config of the ensemble: the whole config, or one sweep value.
struct Point {
    label: Option<String>,
    /// Subdirectory (`sweep/NN-label`) or empty.
    dir: PathBuf,
    sweep: Option<(String, String, Value)>,
    config: Config,
}

impl Point {
    /// Whether the config lists percolation among its measures (`all` does);
    /// the default set computes it without the user asking.
    fn asks_for_percolation(&self) -> bool {
        self.config
            .analysis
            .measures
            .as_ref()
            .is_some_and(|m| m.contains(&crate::config::Measure::Percolation))
    }
}

/// The points of a config: its sweep values, or itself (validated).
fn points(config: &Config) -> Result<Vec<Point>> {
    let mut base = config.clone();
    base.ensemble = None;
    match &config.sweep {
        None => {
            // Planned as a run plans it: a medium's bed file read too.
            crate::pipeline::planned(&base)?;
            Ok(vec![Point {
                label: None,
                dir: PathBuf::new(),
                sweep: None,
                config: base,
            }])
        }
        Some(sw) => Ok(sw
            .points(&base)?
            .into_iter()
            .map(|p| Point {
                label: Some(p.label.clone()),
                dir: Path::new("sweep").join(&p.dir),
                sweep: Some((
                    sw.parameter.clone(),
                    p.label,
                    serde_json::to_value(&p.value).unwrap_or(Value::Null),
                )),
                config: p.config,
            })
            .collect()),
    }
}

/// Refuses a replicate count of 0 or above [`MAX_RUNS`].
pub fn check_runs(runs: u64) -> Result<()> {
    if runs == 0 {
        return Err(crate::error::Error::setting("runs", "must be at least 1"));
    }
    if runs > MAX_RUNS {
        return Err(crate::error::Error::setting(
            "runs",
            format!(
                "at most {MAX_RUNS} replicates per ensemble, got {runs} (their summaries are held in memory for the statistics)"
            ),
        ));
    }
    Ok(())
}

/// Validates a config for an ensemble (every sweep value) without running it.
pub fn validate(config: &Config) -> Result<()> {
    points(config).map(drop)
}

/// The replicate beds (per sweep value) of an ensemble: those asked for, or
/// the config's `[ensemble] runs`.
pub fn runs_of(asked: Option<u64>, config: &Config) -> Result<u64> {
    match (asked, &config.ensemble) {
        (Some(n), _) => Ok(n),
        (None, Some(e)) => Ok(e.runs),
        (None, None) => Err(Error::setting(
            "runs",
            "give the number of replicate beds (the config has no `[ensemble] runs`)",
        )),
    }
}

/// Directory of replicate `i` under an ensemble directory.
pub fn run_dir(dir: &Path, i: u64) -> PathBuf {
    dir.join("runs").join(format!("{i:04}"))
}

/// One warning line for a point under `dir` whose replicates (numbered
/// `runs`, their summaries `values`) warned: how many did, and the first
/// warning of the first that did. A replicate's warning (a compaction cut
/// short, sizes far from those requested) would otherwise stay in its own
/// `summary.json`, unseen behind the statistics.
fn replicates_warned(dir: &Path, runs: &[u64], values: &[serde_json::Value]) -> Option<String> {
    let warned = |v: &serde_json::Value| {
        v.get("warnings")
            .and_then(serde_json::Value::as_array)
            .and_then(|w| w.first())
            .and_then(serde_json::Value::as_str)
            .map(str::to_owned)
    };
    let mut all = runs
        .iter()
        .zip(values)
        .filter_map(|(&i, v)| Some((i, warned(v)?)));
    let (first, text) = all.next()?;
    Some(format!(
        "{} of {} replicates warned; the first, {}: {text}",
        1 + all.count(),
        runs.len(),
        run_dir(dir, first).join("summary.json").display()
    ))
}
