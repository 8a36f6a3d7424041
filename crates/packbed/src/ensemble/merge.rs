//! Joining the shards of one ensemble into the files of a single run.

use super::manifest::{check_out, first_difference, write_manifest, Manifest, Shard, MANIFEST};
use super::proof::{config_hash, not_belonging};
use super::write::{write_point, write_sweep};
use super::{points, replicates_warned, run_dir, seeds, Outcome};
use crate::error::{Error, Result};
use crate::io::Staging;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Joins the output directories of the shards of one ensemble into `out`: the
/// same `ensemble.*` and `sweep.*` files as a single run of the whole ensemble
/// (byte for byte), and copies of every replicate's `summary.json`; the plots
/// only if `pictures`.
pub fn merge_with(dirs: &[PathBuf], out: &Path, pictures: bool) -> Result<Outcome> {
    let start = Instant::now();
    if dirs.is_empty() {
        return Err(Error::config("merge: give the shard directories to join"));
    }
    let manifests = dirs
        .iter()
        .map(|d| Manifest::read(d))
        .collect::<Result<Vec<_>>>()?;
    let first = &manifests[0];
    let count = first.shard.count;
    let mut owner: Vec<Option<usize>> = vec![None; count as usize];
    for (k, (m, d)) in manifests.iter().zip(dirs).enumerate() {
        let other = || format!("{} and {}", dirs[0].display(), d.display());
        if m.config != first.config {
            let key = first_difference(&first.config, &m.config, "").unwrap_or_default();
            return Err(Error::Impossible(format!(
                "merge: {} are ensembles of different configs (first difference at `{key}`)",
                other()
            )));
        }
        if m.runs != first.runs {
            return Err(Error::Impossible(format!(
                "merge: {} have different replicate counts ({} and {})",
                other(),
                first.runs,
                m.runs
            )));
        }
        if m.shard.count != count {
            return Err(Error::Impossible(format!(
                "merge: {} are shards of different splits (/{} and /{})",
                other(),
                count,
                m.shard.count
            )));
        }
        if m.packbed_version != first.packbed_version {
            return Err(Error::Impossible(format!(
                "merge: {} were made by different packbed versions ({} and {})",
                other(),
                first.packbed_version,
                m.packbed_version
            )));
        }
        let slot = &mut owner[m.shard.index as usize];
        if let Some(j) = *slot {
            return Err(Error::Impossible(format!(
                "merge: shard {}/{count} is given twice ({} and {})",
                m.shard.index,
                dirs[j].display(),
                d.display()
            )));
        }
        *slot = Some(k);
        if out.exists() && same_dir(out, d) {
            return Err(Error::setting(
                "out",
                format!(
                    "{} is one of the shard directories; choose another",
                    out.display()
                ),
            ));
        }
    }
    let missing: Vec<String> = owner
        .iter()
        .enumerate()
        .filter(|(_, o)| o.is_none())
        .map(|(k, _)| format!("{k}/{count}"))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Impossible(format!(
            "merge: shard{} {} missing",
            if missing.len() > 1 { "s" } else { "" },
            missing.join(", ")
        )));
    }
    let config = first.config(&dirs[0])?;
    let pts = points(&config)?;
    let manifest = Manifest {
        packbed_version: first.packbed_version.clone(),
        runs: first.runs,
        shard: Shard::ALL,
        config: first.config.clone(),
    };
    check_out(out, &manifest)?;
    // Every summary is read before anything is written, so that an incomplete
    // shard leaves no half-merged output.
    let mut gathered = Vec::new();
    for p in &pts {
        let hash = config_hash(&p.config);
        let mut values = Vec::with_capacity(first.runs as usize);
        for i in 0..first.runs {
            let k = owner[(i % count) as usize].unwrap_or(0);
            let seed = seeds::replicate_seed(config.seed, i);
            let src = run_dir(&dirs[k].join(&p.dir), i);
            let file = src.join("summary.json");
            let found = match fs::read_to_string(&file) {
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    return Err(Error::Impossible(format!(
                        "merge: {} is incomplete: replicate {i} has no summary ({}); rerun shard {}/{count} of the ensemble into {} to finish it",
                        dirs[k].display(),
                        file.display(),
                        i % count,
                        dirs[k].display()
                    )));
                }
                Err(e) => return Err(unreadable(&file, &e.to_string())),
                Ok(text) => {
                    let v: serde_json::Value = serde_json::from_str(&text)
                        .map_err(|e| unreadable(&file, &format!("not valid JSON: {e}")))?;
                    if v.get("seed").and_then(serde_json::Value::as_u64) != Some(seed) {
                        return Err(unreadable(
                            &file,
                            &format!("its seed is not {seed}, the seed of replicate {i}"),
                        ));
                    }
                    if let Some(why) = not_belonging(&v, &hash, &first.packbed_version) {
                        return Err(Error::Impossible(format!(
                            "merge: {} does not belong to this ensemble: {why}; remove it and \
                             rerun shard {}/{count} into {} to build it again",
                            file.display(),
                            i % count,
                            dirs[k].display()
                        )));
                    }
                    (v, text)
                }
            };
            values.push(found);
        }
        let summaries: Vec<serde_json::Value> = values.iter().map(|v| v.0.clone()).collect();
        if let Some((i, key, kind, usual)) = super::stats::odd_replicate(&summaries) {
            let k = owner[(i as u64 % count) as usize].unwrap_or(0);
            let file = run_dir(&dirs[k].join(&p.dir), i as u64).join("summary.json");
            return Err(unreadable(
                &file,
                &format!("`{key}` is {kind}, but {usual} in the other replicates"),
            ));
        }
        gathered.push((p, values));
    }
    write_manifest(out, &manifest)?;
    let mut outcome = Outcome {
        points: Vec::new(),
        wall_seconds: 0.0,
        files: Vec::new(),
        warnings: Vec::new(),
        reduced_from: None,
    };
    let mut merged = Vec::new();
    for (p, found) in gathered {
        let mut values = Vec::with_capacity(found.len());
        for (i, (v, text)) in found.into_iter().enumerate() {
            let dst = run_dir(&out.join(&p.dir), i as u64);
            let mut s = Staging::new(&dst)?.without_sync();
            s.stage("summary.json", |w| w.write_all(text.as_bytes()))?;
            s.commit()?;
            values.push(v);
        }
        let runs: Vec<u64> = (0..values.len() as u64).collect();
        let dir = out.join(&p.dir);
        outcome
            .warnings
            .extend(replicates_warned(&dir, &runs, &values));
        merged.push((p, values));
    }
    let wall = start.elapsed().as_secs_f64();
    outcome.wall_seconds = wall;
    for (p, values) in merged {
        let dir = out.join(&p.dir);
        let point = write_point(
            p,
            dir,
            first.runs,
            Shard::ALL,
            &values,
            (0, values.len() as u64),
            wall,
            pictures,
            &mut outcome.warnings,
        )?;
        outcome.points.push(point);
    }
    outcome.files = vec![out.join(MANIFEST)];
    outcome.files.extend(write_sweep(
        &config,
        out,
        &outcome.points,
        pictures,
        &mut outcome.warnings,
    )?);
    Ok(outcome)
}

/// A replicate summary that is there but cannot be merged.
fn unreadable(file: &Path, why: &str) -> Error {
    Error::Impossible(format!(
        "merge: {} is unreadable: {why}; remove it and rerun its shard to rebuild it",
        file.display()
    ))
}

/// Whether `a` and `b` are the same existing directory.
fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
