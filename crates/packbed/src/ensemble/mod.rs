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
//!   statistics ([`stats`], [`tables`]), which depend only on the replicates'
//!   summaries, folded in replicate order: the same for any thread count, and
//!   for shards joined by [`merge`];
//! - `timing.json`: wall times, kept apart because they differ between runs;
//! - `plot_*.png` and `plot_*.svg` ([`plots`]), unless pictures are off;
//! - with a sweep, the per-value files are under `sweep/NN-label/`, and
//!   `sweep.csv`, `sweep.md` and the `plot_sweep_*` plots compare the values.

pub mod plots;
pub mod seeds;
pub mod stats;
pub mod sweep;
pub mod tables;
pub mod text;

use crate::config::Config;
use crate::error::{Error, Result};
use crate::io::Staging;
use rayon::prelude::*;
use serde_json::{json, Value};
use stats::Aggregate;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Largest `--runs`: every replicate's summary (a few kB) is held in memory
/// while the statistics are folded.
pub const MAX_RUNS: u64 = 1_000_000;
/// Name of the file that identifies an ensemble directory.
pub const MANIFEST: &str = "manifest.json";
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

/// One shard of an ensemble: the replicates `i` with `i mod count == index`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// `K`, from 0.
    pub index: u64,
    /// `M`, at least 1.
    pub count: u64,
}

impl Shard {
    /// The whole ensemble.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `K/M` with `0 <= K < M`.
    pub fn parse(text: &str) -> Result<Shard> {
        let bad = || {
            Error::config(format!(
                "--shard: `{text}` is not K/M with 0 <= K < M (e.g. 0/4 for the first of four shards)"
            ))
        };
        let (k, m) = text.split_once('/').ok_or_else(bad)?;
        let k: u64 = k.trim().parse().map_err(|_| bad())?;
        let m: u64 = m.trim().parse().map_err(|_| bad())?;
        if m == 0 || k >= m {
            return Err(bad());
        }
        Ok(Shard { index: k, count: m })
    }

    /// True if replicate `i` belongs to this shard.
    pub fn has(&self, i: u64) -> bool {
        i % self.count == self.index
    }

    fn as_pair(&self) -> Option<(u64, u64)> {
        (self.count > 1).then_some((self.index, self.count))
    }
}

/// How to run an ensemble.
#[derive(Clone, Debug)]
pub struct Options {
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

/// The points of a config: its sweep values, or itself (validated).
fn points(config: &Config) -> Result<Vec<Point>> {
    let mut base = config.clone();
    base.ensemble = None;
    match &config.sweep {
        None => {
            base.validate()?;
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

/// Validates a config for an ensemble (every sweep value) without running it.
pub fn validate(config: &Config) -> Result<()> {
    points(config).map(drop)
}

/// Directory of replicate `i` under an ensemble directory.
pub fn run_dir(dir: &Path, i: u64) -> PathBuf {
    dir.join("runs").join(format!("{i:04}"))
}

fn io_err(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn read_json(path: &Path) -> Result<Value> {
    let text = fs::read_to_string(path).map_err(|e| io_err(path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::Data {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!("not valid JSON: {e}"),
    })
}

/// The config as stored in the manifest: what makes two ensembles the same.
fn config_key(config: &Config) -> Value {
    let mut c = config.clone();
    c.ensemble = None;
    serde_json::to_value(&c).unwrap_or(Value::Null)
}

/// 64-bit FNV-1a of the text: a short fingerprint to show, not a security hash.
pub fn fingerprint(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The first key where two JSON documents differ, e.g. `species[1].ratio`.
fn first_difference(a: &Value, b: &Value, path: &str) -> Option<String> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, v) in x {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                match y.get(k) {
                    Some(w) => {
                        if let Some(d) = first_difference(v, w, &p) {
                            return Some(d);
                        }
                    }
                    None => return Some(p),
                }
            }
            y.keys().find(|k| !x.contains_key(*k)).map(|k| {
                if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                }
            })
        }
        (Value::Array(x), Value::Array(y)) => {
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                if let Some(d) = first_difference(v, w, &format!("{path}[{i}]")) {
                    return Some(d);
                }
            }
            (x.len() != y.len()).then(|| format!("{path} (length)"))
        }
        _ => (a != b).then(|| {
            if path.is_empty() {
                "(top)".into()
            } else {
                path.to_string()
            }
        }),
    }
}

/// The contents of `manifest.json`.
#[derive(Clone, Debug)]
pub struct Manifest {
    /// Version of packbed that made the ensemble.
    pub packbed_version: String,
    /// Replicates requested.
    pub runs: u64,
    /// The shard.
    pub shard: Shard,
    /// The config (`ensemble` table left out), as JSON.
    pub config: Value,
}

impl Manifest {
    fn to_json(&self) -> String {
        let text = serde_json::to_string(&self.config).unwrap_or_default();
        let v = json!({
            "format": "packbed-ensemble-manifest",
            "packbed_version": self.packbed_version,
            "fingerprint": fingerprint(&text),
            "runs": self.runs,
            "shard": self.shard.as_pair().map(|(k, m)| json!({"index": k, "count": m})),
            "config": self.config,
        });
        let mut s = serde_json::to_string_pretty(&v).unwrap_or_default();
        s.push('\n');
        s
    }

    /// Reads the manifest of an ensemble directory.
    pub fn read(dir: &Path) -> Result<Manifest> {
        let path = dir.join(MANIFEST);
        if !path.exists() {
            return Err(Error::Impossible(format!(
                "{}: not a packbed ensemble directory (no {MANIFEST})",
                dir.display()
            )));
        }
        let v = read_json(&path)?;
        let bad = |what: &str| Error::Data {
            path: path.clone(),
            line: 1,
            message: format!("{what} missing or malformed"),
        };
        let runs = v["runs"].as_u64().ok_or_else(|| bad("`runs`"))?;
        let shard = match &v["shard"] {
            Value::Null => Shard::ALL,
            s => Shard {
                index: s["index"].as_u64().ok_or_else(|| bad("`shard.index`"))?,
                count: s["count"].as_u64().ok_or_else(|| bad("`shard.count`"))?,
            },
        };
        if shard.count == 0 || shard.index >= shard.count {
            return Err(bad("`shard`"));
        }
        Ok(Manifest {
            packbed_version: v["packbed_version"].as_str().unwrap_or("?").to_string(),
            runs,
            shard,
            config: v["config"].clone(),
        })
    }

    fn config(&self, dir: &Path) -> Result<Config> {
        serde_json::from_value(self.config.clone()).map_err(|e| Error::Data {
            path: dir.join(MANIFEST),
            line: 1,
            message: format!("`config` is not a packbed config: {e}"),
        })
    }
}

/// Checks that `out` can hold this ensemble: new, empty, or the same ensemble
/// (same config, shard and packbed version) to resume, whose manifest it returns.
fn check_out(out: &Path, wanted: &Manifest) -> Result<Option<Manifest>> {
    if !out.exists() {
        return Ok(None);
    }
    if !out.is_dir() {
        return Err(Error::Impossible(format!(
            "--out {}: exists and is not a directory",
            out.display()
        )));
    }
    if !out.join(MANIFEST).exists() {
        let empty = fs::read_dir(out)
            .map_err(|e| io_err(out, e))?
            .next()
            .is_none();
        return if empty {
            Ok(None)
        } else {
            Err(Error::Impossible(format!(
                "--out {}: the directory is not empty and holds no ensemble ({MANIFEST}); choose a new or empty directory",
                out.display()
            )))
        };
    }
    let have = Manifest::read(out)?;
    if have.config != wanted.config {
        let key = first_difference(&have.config, &wanted.config, "").unwrap_or_default();
        return Err(Error::Impossible(format!(
            "--out {} holds an ensemble of a different config (fingerprint {} there, {} here; first difference at `{key}`): use another --out, or delete it to start over",
            out.display(),
            fingerprint(&serde_json::to_string(&have.config).unwrap_or_default()),
            fingerprint(&serde_json::to_string(&wanted.config).unwrap_or_default()),
        )));
    }
    if have.shard != wanted.shard {
        let show = |s: Shard| match s.as_pair() {
            Some((k, m)) => format!("shard {k}/{m}"),
            None => "the whole ensemble".to_string(),
        };
        return Err(Error::Impossible(format!(
            "--out {} holds {}, but this run is {}: use another --out",
            out.display(),
            show(have.shard),
            show(wanted.shard)
        )));
    }
    if have.packbed_version != wanted.packbed_version {
        return Err(Error::Impossible(format!(
            "--out {} was made by packbed {}, this is {}: replicates could differ; use another --out",
            out.display(),
            have.packbed_version,
            wanted.packbed_version
        )));
    }
    Ok(Some(have))
}

fn write_manifest(out: &Path, m: &Manifest) -> Result<()> {
    let mut s = Staging::new(out)?;
    let text = m.to_json();
    s.stage(MANIFEST, |w| w.write_all(text.as_bytes()))?;
    s.commit().map(drop)
}

/// A replicate's summary if it is already done: present, valid JSON, and of
/// the expected seed.
fn done_summary(dir: &Path, seed: u64) -> Option<(Value, String)> {
    let text = fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    (v.get("seed").and_then(Value::as_u64) == Some(seed)).then_some((v, text))
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
fn replicate(config: &Config, dir: &Path, i: u64, keep_beds: bool) -> Result<(Value, bool)> {
    let seed = seeds::replicate_seed(config.seed, i);
    let rd = run_dir(dir, i);
    if let Some((v, _)) = done_summary(&rd, seed) {
        return Ok((v, false));
    }
    clear_leftovers(&rd);
    let mut c = config.clone();
    c.seed = seed;
    let finished = crate::pipeline::run_bed(&c, &mut |_| {})
        .map_err(|e| Error::Impossible(format!("replicate {i} (seed {seed}): {e}")))?;
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
    opts: &Options,
    out: &Path,
    progress: &(dyn Fn(Tick) + Sync),
) -> Result<Outcome> {
    let start = Instant::now();
    if opts.runs == 0 {
        return Err(Error::config("--runs must be at least 1"));
    }
    if opts.runs > MAX_RUNS {
        return Err(Error::Impossible(format!(
            "--runs {}: at most {MAX_RUNS} replicates per ensemble (their summaries are held in memory for the statistics)",
            opts.runs
        )));
    }
    if opts.jobs == Some(0) {
        return Err(Error::config("--jobs must be at least 1"));
    }
    if opts.shard.count == 0 || opts.shard.index >= opts.shard.count {
        return Err(Error::config("--shard: K must be smaller than M"));
    }
    let pts = points(config)?;
    let manifest = Manifest {
        packbed_version: env!("CARGO_PKG_VERSION").into(),
        runs: opts.runs,
        shard: opts.shard,
        config: config_key(config),
    };
    let earlier = check_out(out, &manifest)?;
    write_manifest(out, &manifest)?;
    let mine: Vec<u64> = (0..opts.runs).filter(|&i| opts.shard.has(i)).collect();
    let total = mine.len() as u64 * pts.len() as u64;
    let done = AtomicU64::new(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(worker_threads(opts.jobs))
        .build()
        .map_err(|e| Error::Impossible(format!("cannot start worker threads: {e}")))?;
    let mut results = Vec::with_capacity(pts.len());
    for p in &pts {
        let dir = out.join(&p.dir);
        // Made here, once, rather than by the first replicates racing for it.
        let runs_dir = dir.join("runs");
        fs::create_dir_all(&runs_dir).map_err(|e| io_err(&runs_dir, e))?;
        let summaries: Vec<Result<(Value, bool)>> = pool.install(|| {
            mine.par_iter()
                .map(|&i| {
                    let r = replicate(&p.config, &dir, i, opts.keep_beds);
                    let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                    progress(Tick { done: d, total });
                    r
                })
                .collect()
        });
        // The first failure in replicate order is the one reported; the
        // replicates done are on disk and a rerun resumes from them.
        let mut values = Vec::with_capacity(summaries.len());
        let mut built = 0;
        for s in summaries {
            let (v, b) = s?;
            built += u64::from(b);
            values.push(v);
        }
        results.push((p, dir, values, built));
    }
    let wall = start.elapsed().as_secs_f64();
    let mut outcome = Outcome {
        points: Vec::new(),
        wall_seconds: wall,
        files: Vec::new(),
        reduced_from: earlier.map(|m| m.runs).filter(|&r| r > opts.runs),
    };
    for (p, dir, values, built) in results {
        let resumed = values.len() as u64 - built;
        let (aggregate, files) = write_point(
            p,
            &dir,
            opts.runs,
            opts.shard,
            &values,
            (built, resumed),
            wall,
            opts.pictures,
        )?;
        outcome.points.push(PointResult {
            label: p.label.clone(),
            dir,
            aggregate,
            built,
            resumed,
            files,
        });
    }
    outcome.files = vec![out.join(MANIFEST)];
    outcome
        .files
        .extend(write_sweep(config, out, &outcome.points, opts.pictures)?);
    Ok(outcome)
}

/// Stages every plot as `stem.png` and `stem.svg`.
fn stage_plots(s: &mut Staging, plots: &[(String, crate::render::plot::Plot)]) -> Result<()> {
    use crate::render::run_files::PLOT_SIZE;
    // Rasterising is most of the cost; the files are written in order after.
    let files: Vec<(String, Vec<u8>)> = plots
        .par_iter()
        .flat_map_iter(|(stem, plot)| {
            [
                plot.to_png(PLOT_SIZE.0, PLOT_SIZE.1)
                    .map(|b| (format!("{stem}.png"), b)),
                plot.to_svg(PLOT_SIZE.0, PLOT_SIZE.1)
                    .map(|t| (format!("{stem}.svg"), t.into_bytes())),
            ]
        })
        .collect::<Result<_>>()?;
    for (name, bytes) in &files {
        s.stage(name, |w| w.write_all(bytes))?;
    }
    Ok(())
}

/// Writes the statistics files of one point; returns its aggregate and the
/// files written.
#[allow(clippy::too_many_arguments)]
fn write_point(
    p: &Point,
    dir: &Path,
    runs: u64,
    shard: Shard,
    values: &[Value],
    (built, resumed): (u64, u64),
    wall: f64,
    pictures: bool,
) -> Result<(Aggregate, Vec<PathBuf>)> {
    let aggregate = stats::measures_of(values)?;
    let timing = stats::timings_of(values)?;
    let header = tables::Header {
        config: &p.config,
        runs,
        shard: shard.as_pair(),
        sweep: p
            .sweep
            .as_ref()
            .map(|(a, b, c)| (a.as_str(), b.as_str(), c.clone())),
    };
    let mut timing_json = json!({
        "note": "wall times: they depend on the machine and its load, so they are kept out of the ensemble statistics",
        "invocation_wall_seconds": wall,
        "replicates_built": built,
        "replicates_resumed": resumed,
    });
    let t = &mut timing_json;
    for m in &timing.measures {
        t[m.name.as_str()] = json!({
            "n": m.stats.n, "mean": m.stats.mean, "sd": m.stats.sd,
            "min": m.stats.min, "max": m.stats.max,
        });
    }
    let texts = [
        tables::ensemble_json(&header, &aggregate),
        tables::ensemble_csv(&aggregate),
        tables::histograms_csv(&aggregate),
        tables::ensemble_md(&header, &aggregate),
        format!(
            "{}\n",
            serde_json::to_string_pretty(&timing_json).unwrap_or_default()
        ),
    ];
    let mut s = Staging::new(dir)?;
    for (name, text) in ENSEMBLE_FILES.iter().zip(&texts) {
        s.stage(name, |w| w.write_all(text.as_bytes()))?;
    }
    if pictures {
        stage_plots(
            &mut s,
            &plots::ensemble_plots(
                &aggregate,
                p.config.dim as usize,
                p.config.analysis.chain_angle_from,
            ),
        )?;
    }
    let files = s.commit()?;
    Ok((aggregate, files))
}

fn write_sweep(
    config: &Config,
    out: &Path,
    points: &[PointResult],
    pictures: bool,
) -> Result<Vec<PathBuf>> {
    let Some(sw) = &config.sweep else {
        return Ok(points.iter().flat_map(|p| p.files.clone()).collect());
    };
    let rows: Vec<tables::SweepRow> = points
        .iter()
        .map(|p| tables::SweepRow {
            label: p.label.as_deref().unwrap_or(""),
            aggregate: &p.aggregate,
        })
        .collect();
    let mut base = config.clone();
    base.sweep = None;
    let texts = [
        tables::sweep_csv(&rows),
        tables::sweep_md(&sw.parameter, &base, &rows),
    ];
    let mut s = Staging::new(out)?;
    for (name, text) in SWEEP_FILES.iter().zip(&texts) {
        s.stage(name, |w| w.write_all(text.as_bytes()))?;
    }
    if pictures {
        let labelled: Vec<(&str, &Aggregate)> = points
            .iter()
            .map(|p| (p.label.as_deref().unwrap_or(""), &p.aggregate))
            .collect();
        stage_plots(&mut s, &plots::sweep_plots(sw, &labelled))?;
    }
    s.commit()
}

/// Joins the output directories of the shards of one ensemble into `out`: the
/// same `ensemble.*` and `sweep.*` files as a single run of the whole ensemble
/// (byte for byte), and copies of every replicate's `summary.json`.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Outcome> {
    merge_with(dirs, out, true)
}

/// [`merge`], writing the plots only if `pictures`.
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
                "merge: {} have different --runs ({} and {})",
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
            return Err(Error::Impossible(format!(
                "merge: --out {} is one of the shard directories; choose another",
                out.display()
            )));
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
        let mut values = Vec::with_capacity(first.runs as usize);
        for i in 0..first.runs {
            let k = owner[(i % count) as usize].unwrap_or(0);
            let seed = seeds::replicate_seed(config.seed, i);
            let src = run_dir(&dirs[k].join(&p.dir), i);
            let Some(found) = done_summary(&src, seed) else {
                return Err(Error::Impossible(format!(
                    "merge: {} is incomplete: replicate {i} has no summary ({}); rerun its `packbed ensemble … --shard {}/{count} --out {}` to finish it",
                    dirs[k].display(),
                    src.join("summary.json").display(),
                    i % count,
                    dirs[k].display()
                )));
            };
            values.push(found);
        }
        gathered.push((p, values));
    }
    write_manifest(out, &manifest)?;
    let mut outcome = Outcome {
        points: Vec::new(),
        wall_seconds: 0.0,
        files: Vec::new(),
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
        merged.push((p, values));
    }
    let wall = start.elapsed().as_secs_f64();
    outcome.wall_seconds = wall;
    for (p, values) in merged {
        let dir = out.join(&p.dir);
        let (aggregate, files) = write_point(
            p,
            &dir,
            first.runs,
            Shard::ALL,
            &values,
            (0, values.len() as u64),
            wall,
            pictures,
        )?;
        outcome.points.push(PointResult {
            label: p.label.clone(),
            dir,
            aggregate,
            built: 0,
            resumed: values.len() as u64,
            files,
        });
    }
    outcome.files = vec![out.join(MANIFEST)];
    outcome
        .files
        .extend(write_sweep(&config, out, &outcome.points, pictures)?);
    Ok(outcome)
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
