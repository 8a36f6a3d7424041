//! Ensembles: results independent of threads and shards, resume after
//! interruption, replicates equal to single runs, strict refusals, and every
//! example config valid.

use packbed::Config;
use packbed::{
    ensemble_run_dir, merge_ensembles, replicate_seed, run_ensemble, EnsembleOptions, Outcome,
    Shard, ENSEMBLE_FILES, MANIFEST, SWEEP_FILES,
};
use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};

/// Small, fast beds: 2D, radii 10 and 20, a box of 8 large diameters.
fn small_config() -> Config {
    Config::from_toml(
        "dim = 2\nseed = 3\n[box]\ndiameters = 8\n[[species]]\nradius = 20\nratio = 1\n[[species]]\nradius = 10\nratio = 2\n",
        "test",
    )
    .unwrap()
}

fn sweep_config() -> Config {
    let mut text = String::from(
        "dim = 3\nseed = 9\n[box]\ndiameters = 4\n[[species]]\nradius = 20\nratio = 1\n[[species]]\nradius = 10\nratio = 1\n",
    );
    text.push_str("[sweep]\nparameter = \"ratio\"\nvalues = [[1, 1], [1, 3]]\n");
    Config::from_toml(&text, "test").unwrap()
}

fn opts(runs: u64, jobs: usize, shard: Shard) -> EnsembleOptions {
    EnsembleOptions {
        runs,
        jobs: Some(jobs),
        shard,
        keep_beds: false,
        pictures: true,
        stop: None,
    }
}

fn run(config: &Config, o: &EnsembleOptions, out: &Path) -> Outcome {
    run_ensemble(config, o, out, &|_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// The statistics files (not timing.json) of an ensemble directory, with sweeps.
fn stat_files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    if let Ok(entries) = fs::read_dir(dir.join("sweep")) {
        let mut sub: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
        sub.sort();
        dirs.extend(sub);
    }
    for d in dirs {
        for name in ENSEMBLE_FILES.iter().chain(&SWEEP_FILES) {
            if *name == "timing.json" {
                continue;
            }
            if let Ok(bytes) = fs::read(d.join(name)) {
                files.push((d.strip_prefix(dir).unwrap().join(name), bytes));
            }
        }
    }
    assert!(!files.is_empty());
    files
}

fn assert_same(a: &Path, b: &Path) {
    let (fa, fb) = (stat_files(a), stat_files(b));
    assert_eq!(
        fa.iter().map(|f| &f.0).collect::<Vec<_>>(),
        fb.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((name, x), (_, y)) in fa.iter().zip(&fb) {
        assert!(x == y, "{} differs", name.display());
    }
}

#[test]
fn same_result_for_any_thread_count() {
    let t = tempfile::tempdir().unwrap();
    let c = small_config();
    let one = run(&c, &opts(10, 1, Shard::ALL), &t.path().join("j1"));
    let two = run(&c, &opts(10, 2, Shard::ALL), &t.path().join("j2"));
    let three = run(&c, &opts(10, 3, Shard::ALL), &t.path().join("j3"));
    assert_eq!(one.points[0].aggregate, two.points[0].aggregate);
    assert_eq!(one.points[0].aggregate, three.points[0].aggregate);
    assert_same(&t.path().join("j1"), &t.path().join("j2"));
    assert_same(&t.path().join("j1"), &t.path().join("j3"));
    // The beds differ between replicates (seeds differ), so the sd is real.
    let g = one.points[0]
        .aggregate
        .measures
        .iter()
        .find(|m| m.name == "packing.global")
        .unwrap();
    assert_eq!(g.stats.n, 10);
    assert!(g.stats.sd > 0.0 && g.stats.min < g.stats.max);
}

#[test]
fn shards_merge_into_the_single_run() {
    let t = tempfile::tempdir().unwrap();
    for (name, c) in [("plain", small_config()), ("sweep", sweep_config())] {
        let root = t.path().join(name);
        run(&c, &opts(7, 2, Shard::ALL), &root.join("whole"));
        let mut shards = Vec::new();
        for k in [2, 0, 1] {
            let d = root.join(format!("shard{k}"));
            let o = run(&c, &opts(7, 1, Shard { index: k, count: 3 }), &d);
            // Shard k of 3 holds replicates k, k + 3, …
            let n = (0..7).filter(|i| i % 3 == k).count() as u64;
            assert!(o.points.iter().all(|p| p.aggregate.replicates == n));
            shards.push(d);
        }
        merge_ensembles(&shards, &root.join("merged"), true).unwrap();
        assert_same(&root.join("whole"), &root.join("merged"));
        if name == "sweep" {
            let md = fs::read_to_string(root.join("merged/sweep.md")).unwrap();
            assert!(md.contains("| 1:3 | 7 |"), "{md}");
        }
    }
}

#[test]
fn interrupted_ensemble_resumes_to_the_same_result() {
    let t = tempfile::tempdir().unwrap();
    let c = small_config();
    let whole = t.path().join("whole");
    run(&c, &opts(8, 2, Shard::ALL), &whole);
    // An interrupted ensemble: some replicates missing, one with only a stale
    // temporary file, one with a truncated summary, no statistics yet.
    let part = t.path().join("part");
    run(&c, &opts(8, 2, Shard::ALL), &part);
    fs::remove_dir_all(ensemble_run_dir(&part, 1)).unwrap();
    fs::remove_dir_all(ensemble_run_dir(&part, 6)).unwrap();
    let stale = ensemble_run_dir(&part, 3);
    fs::remove_file(stale.join("summary.json")).unwrap();
    fs::write(stale.join(".summary.json.12345.tmp"), "{\"dim\": 2, \"se").unwrap();
    fs::write(
        ensemble_run_dir(&part, 5).join("summary.json"),
        "{\"dim\": ",
    )
    .unwrap();
    for f in ENSEMBLE_FILES {
        fs::remove_file(part.join(f)).unwrap();
    }
    let o = run(&c, &opts(8, 2, Shard::ALL), &part);
    assert_eq!((o.points[0].built, o.points[0].resumed), (4, 4));
    assert!(!stale.join(".summary.json.12345.tmp").exists());
    assert_same(&whole, &part);
    // A rerun of a complete ensemble builds nothing.
    let o = run(&c, &opts(8, 1, Shard::ALL), &part);
    assert_eq!((o.points[0].built, o.points[0].resumed), (0, 8));
    assert_same(&whole, &part);
}

#[test]
fn more_runs_extend_an_ensemble() {
    let t = tempfile::tempdir().unwrap();
    let c = small_config();
    run(&c, &opts(6, 2, Shard::ALL), &t.path().join("direct"));
    run(&c, &opts(3, 2, Shard::ALL), &t.path().join("grown"));
    let o = run(&c, &opts(6, 2, Shard::ALL), &t.path().join("grown"));
    assert_eq!((o.points[0].built, o.points[0].resumed), (3, 3));
    assert_same(&t.path().join("direct"), &t.path().join("grown"));
}

#[test]
fn a_replicate_is_the_single_run_of_its_seed() {
    let t = tempfile::tempdir().unwrap();
    let c = small_config();
    run(&c, &opts(3, 2, Shard::ALL), t.path());
    for i in 0..3 {
        let text = fs::read_to_string(ensemble_run_dir(t.path(), i).join("summary.json")).unwrap();
        let mut from_ensemble: Value = serde_json::from_str(&text).unwrap();
        let mut single = c.clone();
        single.seed = replicate_seed(c.seed, i);
        let finished = packbed::run_bed(&single, &mut |_| {}).unwrap();
        let mut direct: Value = serde_json::from_str(&finished.summary.to_json().unwrap()).unwrap();
        assert_eq!(from_ensemble["seed"], single.seed);
        from_ensemble.as_object_mut().unwrap().remove("timing");
        direct.as_object_mut().unwrap().remove("timing");
        // A replicate adds only the proof that it belongs to its ensemble.
        let proof = from_ensemble.as_object_mut().unwrap().remove("proof");
        assert!(proof.is_some_and(|p| p["config_hash"].is_string()));
        assert_eq!(from_ensemble, direct);
    }
}

#[test]
fn statistics_match_the_replicates() {
    // The ensemble's numbers recomputed by hand from the runs' summaries.
    let t = tempfile::tempdir().unwrap();
    let c = small_config();
    let o = run(&c, &opts(5, 2, Shard::ALL), t.path());
    let xs: Vec<f64> = (0..5)
        .map(|i| {
            let text =
                fs::read_to_string(ensemble_run_dir(t.path(), i).join("summary.json")).unwrap();
            let v: Value = serde_json::from_str(&text).unwrap();
            v["packing"]["global"].as_f64().unwrap()
        })
        .collect();
    let mean = xs.iter().sum::<f64>() / 5.0;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 4.0;
    let m = o.points[0]
        .aggregate
        .measures
        .iter()
        .find(|m| m.name == "packing.global")
        .unwrap();
    assert!((m.stats.mean - mean).abs() < 1e-15);
    assert!((m.stats.sd - var.sqrt()).abs() < 1e-15);
    assert_eq!(
        m.stats.min,
        xs.iter().copied().fold(f64::INFINITY, f64::min)
    );
    let json: Value =
        serde_json::from_str(&fs::read_to_string(t.path().join("ensemble.json")).unwrap()).unwrap();
    assert_eq!(json["measures"]["packing.global"]["n"], 5);
    assert_eq!(json["replicates"], 5);
    // The coordination histogram is summed and normalised, if present.
    if let Some(h) = json["histograms"]
        .as_object()
        .and_then(|h| h.values().next())
    {
        let total: f64 = h["fraction"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
    }
    assert!(json["measures"].get("timing.deposit_seconds").is_none());
    assert!(json.get("timing").is_none());
}

#[test]
fn refusals() {
    let t = tempfile::tempdir().unwrap();
    let c = small_config();
    let err = |r: packbed::Result<Outcome>| r.err().map(|e| e.to_string()).unwrap_or_default();
    let e = err(run_ensemble(
        &c,
        &opts(0, 1, Shard::ALL),
        &t.path().join("a"),
        &|_| {},
    ));
    assert!(e.starts_with("runs: must be at least 1"), "{e}");
    assert!(!t.path().join("a").exists());
    for bad in ["3/2", "1", "a/b", "0/0", "-1/2"] {
        assert!(Shard::parse(bad).is_err(), "{bad}");
    }
    assert_eq!(Shard::parse("1/4").unwrap(), Shard { index: 1, count: 4 });
    // A different config into the same directory.
    let out = t.path().join("b");
    run(&c, &opts(2, 1, Shard::ALL), &out);
    let mut other = c.clone();
    other.species[1].ratio = 3.0;
    let e = err(run_ensemble(&other, &opts(2, 1, Shard::ALL), &out, &|_| {}));
    assert!(
        e.contains("different config") && e.contains("species[1].ratio"),
        "{e}"
    );
    let e = err(run_ensemble(
        &c,
        &opts(2, 1, Shard { index: 0, count: 2 }),
        &out,
        &|_| {},
    ));
    assert!(e.contains("shard"), "{e}");
    // A non-empty directory that is not an ensemble.
    let junk = t.path().join("junk");
    fs::create_dir(&junk).unwrap();
    fs::write(junk.join("notes.txt"), "mine").unwrap();
    let e = err(run_ensemble(&c, &opts(2, 1, Shard::ALL), &junk, &|_| {}));
    assert!(e.contains("not empty"), "{e}");
    // Merges of incompatible or incomplete shards.
    let s0 = t.path().join("s0");
    let s1 = t.path().join("s1");
    run(&c, &opts(4, 1, Shard { index: 0, count: 2 }), &s0);
    let e = err(merge_ensembles(
        std::slice::from_ref(&s0),
        &t.path().join("m1"),
        true,
    ));
    assert!(e.contains("1/2") && e.contains("missing"), "{e}");
    let e = err(merge_ensembles(
        &[s0.clone(), s0.clone()],
        &t.path().join("m2"),
        true,
    ));
    assert!(e.contains("twice"), "{e}");
    run(&other, &opts(4, 1, Shard { index: 1, count: 2 }), &s1);
    let e = err(merge_ensembles(
        &[s0.clone(), s1.clone()],
        &t.path().join("m3"),
        true,
    ));
    assert!(e.contains("different configs"), "{e}");
    let s1b = t.path().join("s1b");
    run(&c, &opts(5, 1, Shard { index: 1, count: 2 }), &s1b);
    let e = err(merge_ensembles(
        &[s0.clone(), s1b],
        &t.path().join("m4"),
        true,
    ));
    assert!(e.contains("different replicate counts"), "{e}");
    let s1c = t.path().join("s1c");
    run(&c, &opts(4, 1, Shard { index: 1, count: 2 }), &s1c);
    fs::remove_dir_all(ensemble_run_dir(&s1c, 3)).unwrap();
    let e = err(merge_ensembles(
        &[s0.clone(), s1c],
        &t.path().join("m5"),
        true,
    ));
    assert!(e.contains("incomplete") && e.contains("replicate 3"), "{e}");
    let e = err(merge_ensembles(
        &[t.path().join("nothing")],
        &t.path().join("m6"),
        true,
    ));
    assert!(e.contains(MANIFEST), "{e}");
}

#[test]
fn sweep_configs_are_refused_by_run() {
    let e = sweep_config().validate().unwrap_err().to_string();
    assert!(e.contains("packbed ensemble"), "{e}");
    packbed::validate_ensemble(&sweep_config()).unwrap();
}

#[test]
fn every_example_config_is_valid() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut seen = 0;
    for dir in [
        root.clone(),
        root.join("thesis"),
        root.join("thesis/chains"),
        root.join("drying"),
        root.join("feeds"),
        root.join("filtration"),
        root.join("settling"),
    ] {
        for e in fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "toml") {
                let c = Config::from_file(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                // Chains are refused by the engine until their issue lands, not by
                // validation; both examples kinds must validate.
                packbed::validate_ensemble(&c).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                if dir.ends_with("thesis") {
                    let runs = c.ensemble.as_ref().map(|e| e.runs);
                    // The study's 500 replicates; percolation and breakage
                    // sweeps (several ratios, each bed broken bond by bond) 100.
                    let name = p.to_string_lossy();
                    let fewer = name.contains("percolation") || name.contains("fragmentation");
                    assert_eq!(runs, Some(if fewer { 100 } else { 500 }), "{}", p.display());
                }
                seen += 1;
            }
        }
    }
    assert!(seen >= 60, "{seen} example configs");
}

/// A stop asked for from outside (Ctrl-C in Python) ends the build and the
/// ensemble with `Interrupted`, for deposition and RSA alike; the replicates
/// finished before it stay and a rerun completes the ensemble as if never
/// stopped.
#[test]
fn stop_interrupts_builds_and_ensembles() {
    use packbed::{Mode, Overrides};
    use std::ops::ControlFlow;
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;
    for mode in [Mode::Deposit, Mode::Rsa] {
        let mut c = Config::default();
        Overrides {
            dim: Some(2),
            radii: Some(vec![1.0]),
            count: Some(10_000),
            container: Some("400,400".parse().unwrap()),
            periodic: true,
            ..Overrides::default()
        }
        .apply(&mut c)
        .unwrap();
        c.mode = mode;
        let mut calls = 0;
        let stopped = packbed::run_bed_or_stop(&c, &mut |n| {
            calls += 1;
            assert!(n < 10_000, "{mode:?}: stopped only at the end");
            ControlFlow::Break(())
        });
        assert!(
            matches!(stopped, Err(packbed::Error::Interrupted)),
            "{mode:?}"
        );
        assert_eq!(calls, 1, "{mode:?}");
    }
    let mut c = Config::default();
    Overrides {
        dim: Some(2),
        radii: Some(vec![10.0]),
        count: Some(30),
        ..Overrides::default()
    }
    .apply(&mut c)
    .unwrap();
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let stop = Arc::new(AtomicBool::new(true));
    let o = EnsembleOptions {
        stop: Some(stop.clone()),
        ..opts(3, 1, Shard::ALL)
    };
    let e = run_ensemble(&c, &o, &dir.join("a"), &|_| {}).unwrap_err();
    assert!(matches!(e, packbed::Error::Interrupted), "{e}");
    stop.store(false, std::sync::atomic::Ordering::Relaxed);
    let resumed = run(&c, &o, &dir.join("a"));
    let fresh = run(&c, &opts(3, 1, Shard::ALL), &dir.join("b"));
    assert_eq!(resumed.points[0].built, 3);
    let csv = |d: &str| std::fs::read(dir.join(d).join("ensemble.csv")).unwrap();
    assert_eq!(csv("a"), csv("b"));
    assert_eq!(fresh.points[0].built, 3);
}
