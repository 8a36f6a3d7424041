//! Ensembles and merges from Python: the library's, off the GIL, with
//! Ctrl-C and progress. The Dask path (python/packbed/_dask.py) runs shards
//! of the same ensemble as tasks and joins them with [`merge`], which gives
//! the files of a single local run byte for byte.

use crate::config::load;
use crate::detached::{self, Shared};
use crate::errors::to_py;
use packbed::{EnsembleOptions, Shard, Tick};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::Ordering;

/// What an ensemble or merge made: the output folder of each point (one for a
/// plain ensemble, one per sweep value) with its label, the files written, and
/// the warnings the command prints (replicates that warned, plots not drawn),
/// which Python raises as `PackbedWarning`s.
type Made = (Vec<(Option<String>, PathBuf)>, Vec<PathBuf>, Vec<String>);

fn made(outcome: &packbed::Outcome) -> Made {
    let points = outcome
        .points
        .iter()
        .map(|p| (p.label.clone(), p.dir.clone()))
        .collect();
    let mut files = outcome.files.clone();
    for p in &outcome.points {
        files.extend(p.files.iter().cloned());
    }
    (points, files, outcome.warnings.clone())
}

/// Runs replicates `0..runs` of a resolved config (canonical JSON) into
/// `out` (resuming what is there), or shard `(K, M)` of them.
#[pyfunction]
#[pyo3(signature = (config_json, runs, out, jobs=None, shard=None, pictures=true, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn ensemble(
    py: Python<'_>,
    config_json: &str,
    runs: u64,
    out: PathBuf,
    jobs: Option<usize>,
    shard: Option<(u64, u64)>,
    pictures: bool,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Made> {
    let config = load(config_json)?;
    let shard = match shard {
        Some((index, count)) => Shard { index, count },
        None => Shard::ALL,
    };
    packbed::check_out_dir(&out).map_err(|e| to_py(e.within("out")))?;
    detached::run(py, progress, |shared: &Shared| {
        let options = EnsembleOptions {
            runs,
            jobs,
            shard,
            keep_beds: false,
            pictures,
            stop: Some(shared.stop.clone()),
        };
        let tick = |t: Tick| {
            shared.done.store(t.done, Ordering::Relaxed);
            shared.total.store(t.total, Ordering::Relaxed);
        };
        packbed::run_ensemble(&config, &options, &out, &tick)
            .map(|o| made(&o))
            .map_err(to_py)
    })
}

/// Joins the output folders of shards into `out` (`packbed merge`).
#[pyfunction]
#[pyo3(signature = (dirs, out, pictures=true))]
pub fn merge(py: Python<'_>, dirs: Vec<PathBuf>, out: PathBuf, pictures: bool) -> PyResult<Made> {
    detached::run(py, None, |_| {
        packbed::merge_ensembles(&dirs, &out, pictures)
            .map(|o| made(&o))
            .map_err(to_py)
    })
}

/// Compares runs, ensembles or sweeps (`packbed compare`): the files are
/// written into `out`; returns `compare.csv`'s text and the files.
#[pyfunction]
#[pyo3(signature = (dirs, out, pictures=true))]
pub fn compare(
    py: Python<'_>,
    dirs: Vec<PathBuf>,
    out: PathBuf,
    pictures: bool,
) -> PyResult<(String, Vec<PathBuf>)> {
    use packbed::compare as library;
    packbed::check_out_dir(&out).map_err(|e| to_py(e.within("out")))?;
    detached::run(py, None, |_| {
        let groups = library::read_groups(&dirs).map_err(to_py)?;
        let c = library::compare(&groups).map_err(to_py)?;
        let files = library::write_comparison(&out, &groups, &c, pictures).map_err(to_py)?;
        Ok((c.to_csv().map_err(to_py)?, files))
    })
}
