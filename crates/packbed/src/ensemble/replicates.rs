//! Running an ensemble: its replicates in parallel, each written as it
//! finishes, those already done reused (resume).

use super::manifest::{check_out, config_key, io_err, write_manifest, Manifest, MANIFEST};
use super::proof::{config_hash, not_belonging, ReplicateProof};
use super::write::{write_point, write_sweep};
use super::{
    points, replicates_warned, run_dir, seeds, worker_threads, EnsembleOptions, Outcome, Tick,
};
use crate::config::Config;
use crate::error::{Error, Result};
use crate::io::Staging;
use rayon::prelude::*;
use serde_json::Value;
use std::fs;
use std::ops::ControlFlow;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// A replicate's summary if it is already done: present, valid JSON, and of
/// the expected seed.
pub(super) fn done_summary(dir: &Path, seed: u64) -> Option<(Value, String)> {
    let text = fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    (v.get("seed").and_then(Value::as_u64) == Some(seed)).then_some((v, text))
}

/// Refuses, by path, a finished replicate of `replicates` under `dir` that
/// does not belong to an ensemble of `config` ([`not_belonging`]): a summary
/// copied from another ensemble, another config or another packbed version
/// would otherwise enter the statistics. A summary of another seed, or one
/// that is not valid JSON, is not finished: it is rebuilt.
fn check_finished(config: &Config, dir: &Path, replicates: &[u64]) -> Result<()> {
    let hash = config_hash(config);
    for &i in replicates {
        let rd = run_dir(dir, i);
        let Some((v, _)) = done_summary(&rd, seeds::replicate_seed(config.seed, i)) else {
            continue;
        };
        if let Some(why) = not_belonging(&v, &hash, env!("CARGO_PKG_VERSION")) {
            return Err(Error::Impossible(format!(
                "{} does not belong to this ensemble: {why}; remove it and rerun to build that \
                 replicate again",
                rd.join("summary.json").display()
            )));
        }
    }
    Ok(())
}

/// Removes temporary files an interrupted replicate left behind.
fn clear_leftovers(dir: &Path) {
    if let Ok(entries) = fs::read_dir(dir) {
        for e in entries.flatten() {
            let name = e.file_name();
            let name = name.to_string_lossy();
            if name.starts_with('.') && name.ends_with(".tmp") {
                let _ = fs::remove_file(e.path());
            }
        }
    }
}

/// Builds replicate `i` (or finds it done) and returns its summary.
fn replicate(
    config: &Config,
    dir: &Path,
    i: u64,
    keep_beds: bool,
    stop: Option<&AtomicBool>,
) -> Result<(Value, bool)> {
    let seed = seeds::replicate_seed(config.seed, i);
    let rd = run_dir(dir, i);
    if let Some((v, _)) = done_summary(&rd, seed) {
        return Ok((v, false));
    }
    clear_leftovers(&rd);
    let mut c = config.clone();
    c.seed = seed;
    let stopped = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
    if stopped() {
        return Err(Error::Interrupted);
    }
    let on_progress = &mut |_| match stopped() {
        true => ControlFlow::Break(()),
        false => ControlFlow::Continue(()),
    };
    let finished = crate::pipeline::run_bed_or_stop(&c, on_progress).map_err(|e| match e {
        Error::Interrupted => e,
        e => Error::Impossible(format!("replicate {i} (seed {seed}): {e}")),
    })?;
    let mut finished = finished;
    finished.summary.proof = Some(ReplicateProof::of(&c, &finished.summary.analysis));
    let text = finished.summary.to_json()?;
    if keep_beds {
        finished.write(&rd)?;
    } else {
        let mut s = Staging::new(&rd)?.without_sync();
        s.stage("summary.json", |w| w.write_all(text.as_bytes()))?;
        s.commit()?;
    }
    // Statistics always come from the JSON text, as a resumed replicate's do,
    // so a resumed ensemble equals an uninterrupted one bit for bit.
    let v = serde_json::from_str(&text).map_err(|e| Error::Impossible(format!("summary: {e}")))?;
    Ok((v, true))
}

/// Runs an ensemble of `config` into `out`; `progress` is called from the
/// worker threads as replicates finish.
pub fn run(
    config: &Config,
    opts: &EnsembleOptions,
    out: &Path,
    progress: &(dyn Fn(Tick) + Sync),
) -> Result<Outcome> {
    let start = Instant::now();
    super::check_runs(opts.runs)?;
    if opts.jobs == Some(0) {
        return Err(Error::setting("jobs", "must be at least 1"));
    }
    if opts.shard.count == 0 || opts.shard.index >= opts.shard.count {
        return Err(Error::setting("shard", "K must be smaller than M"));
    }
    let pts = points(config)?;
    let manifest = Manifest {
        packbed_version: env!("CARGO_PKG_VERSION").into(),
        runs: opts.runs,
        shard: opts.shard,
        config: config_key(config),
    };
    let earlier = check_out(out, &manifest)?;
    let mine: Vec<u64> = (0..opts.runs).filter(|&i| opts.shard.has(i)).collect();
    // Every replicate found finished is checked before any work.
    if earlier.is_some() {
        for p in &pts {
            check_finished(&p.config, &out.join(&p.dir), &mine)?;
        }
    }
    write_manifest(out, &manifest)?;
    let total = mine.len() as u64 * pts.len() as u64;
    let done = AtomicU64::new(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(worker_threads(opts.jobs))
        .build()
        .map_err(|e| Error::Impossible(format!("cannot start worker threads: {e}")))?;
    let mut results = Vec::with_capacity(pts.len());
    let mut warned = Vec::new();
    for p in &pts {
        let dir = out.join(&p.dir);
        // Made here, once, rather than by the first replicates racing for it.
        let runs_dir = dir.join("runs");
        fs::create_dir_all(&runs_dir).map_err(|e| io_err(&runs_dir, e))?;
        let summaries: Vec<Result<(Value, bool)>> = pool.install(|| {
            mine.par_iter()
                .map(|&i| {
                    let r = replicate(&p.config, &dir, i, opts.keep_beds, opts.stop.as_deref());
                    let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                    progress(Tick { done: d, total });
                    r
                })
                .collect()
        });
        // The first failure in replicate order is the one reported; the
        // replicates done are on disk and a rerun resumes from them.
        if summaries
            .iter()
            .any(|s| matches!(s, Err(Error::Interrupted)))
        {
            return Err(Error::Interrupted);
        }
        let mut values = Vec::with_capacity(summaries.len());
        let mut built = 0;
        for s in summaries {
            let (v, b) = s?;
            built += u64::from(b);
            values.push(v);
        }
        // A resumed summary that parses but holds a measure of the wrong
        // kind (text for a number) would be dropped from the statistics
        // without a word; a truncated one is rebuilt by `done_summary`.
        if let Some((k, key, kind, usual)) = super::stats::odd_replicate(&values) {
            return Err(Error::Impossible(format!(
                "{} is damaged: `{key}` is {kind}, but {usual} in the other replicates; \
                 remove it and rerun to build that replicate again",
                run_dir(&dir, mine[k]).join("summary.json").display()
            )));
        }
        warned.extend(replicates_warned(&dir, &mine, &values));
        results.push((p, dir, values, built));
    }
    let wall = start.elapsed().as_secs_f64();
    let mut outcome = Outcome {
        points: Vec::new(),
        wall_seconds: wall,
        files: Vec::new(),
        warnings: warned,
        reduced_from: earlier.map(|m| m.runs).filter(|&r| r > opts.runs),
    };
    for (p, dir, values, built) in results {
        let resumed = values.len() as u64 - built;
        let point = write_point(
            p,
            dir,
            opts.runs,
            opts.shard,
            &values,
            (built, resumed),
            wall,
            opts.pictures,
            &mut outcome.warnings,
        )?;
        outcome.points.push(point);
    }
    outcome.files = vec![out.join(MANIFEST)];
    outcome.files.extend(write_sweep(
        config,
        out,
        &outcome.points,
        opts.pictures,
        &mut outcome.warnings,
    )?);
    Ok(outcome)
}
