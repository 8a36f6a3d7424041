//! Fuzz targets of packbed's input layers: each takes arbitrary bytes and
//! gives them to the library the way `packbed` gives it a user's file. An
//! error is the expected answer to bad input; a panic, an abort (an
//! allocation the memory limit refuses) or a broken invariant is a bug.
//!
//! The AFL++ entry points are `src/bin/*` (built by `scripts/fuzz.sh` with
//! `cargo afl`); `tests/replay.rs` runs every seed and every regression input
//! through the same functions on a plain `cargo test`, so a crash once found
//! stays fixed without AFL++ installed.
//!
//! Targets, one per input layer a user controls:
//! - [`bed`]: every bed reader (packbed's CSV with or without its
//!   `summary.json`, plain tables, LAMMPS dumps, extended XYZ, VTU), then,
//!   for small beds, every measure (the pore space included);
//! - [`config`]: the TOML config with the command-line overrides, sweeps and
//!   the plan, then, for small beds, the deposition itself;
//! - [`psd_table`]: measured size distributions, then sampling from them;
//! - [`merge`]: a shard's manifest and replicate summary, as `merge` reads them;
//! - [`resume`]: a replicate summary, as a rerun of its ensemble reads it;
//! - [`compare`]: two runs' `summary.json`, as `compare` reads and sets them
//!   side by side (units converted, tests and ratios, its files and plots).
//!
//! Each returns whether the input was accepted (read, or planned), so that
//! the replay test can tell a seed that still reaches deep from one that a
//! format change has made a refusal.

use packbed::Shard;
use packbed::{parse_numbers, BoxSpec, Measure, Mode, Overrides};
use packbed::{AnalysisConfig, AnyBed, BoxHint, Config};
use packbed::{SizeTable, Within};
use rand::SeedableRng;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Beds with at most this many particles are also analysed (every measure),
/// and configs planning at most this many are also deposited: enough for the
/// analysis and the engine to meet odd geometry, few enough for thousands of
/// inputs a second.
const SMALL: usize = 200;

/// This process' scratch directory (in memory where the machine has
/// `/dev/shm`): AFL++ runs one process per core, each with its own files.
fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let shm = Path::new("/dev/shm");
        let base = if shm.is_dir() {
            shm.to_path_buf()
        } else {
            std::env::temp_dir()
        };
        let dir = base.join(format!("packbed-fuzz-{}", std::process::id()));
        fs::create_dir_all(&dir).expect("scratch directory");
        dir
    })
}

/// Removes this process' scratch directory (AFL++'s processes leave theirs
/// to `scripts/fuzz.sh`).
pub fn remove_scratch() {
    let _ = fs::remove_dir_all(scratch());
}

/// Splits `data` at its first NUL byte: the file, then what goes beside it.
fn split_nul(data: &[u8]) -> (&[u8], Option<&[u8]>) {
    match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], Some(&data[i + 1..])),
        None => (data, None),
    }
}

/// Writes `bytes` to `dir/name` (replacing what an earlier input left).
fn put(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, bytes).expect("write scratch file");
    path
}

/// Every measure, the pore space and flow included.
fn all_measures() -> AnalysisConfig {
    AnalysisConfig {
        measures: Some(Measure::parse_list("all").expect("`all` is a measure list")),
        ..AnalysisConfig::default()
    }
}

/// A bed file. The first byte chooses how it is presented: bits 0–2 the file
/// name (`particles.csv`, `bed.dump`, `bed.xyz`, `bed.vtu`, `bed.txt`), bit 3
/// whether a box is given (as `--box`), bit 4 its dimension (2 or 3), bit 5
/// periodic sides. The rest is the file; after a NUL byte, the `summary.json`
/// beside it.
pub fn bed(data: &[u8]) -> bool {
    let Some((&how, rest)) = data.split_first() else {
        return false;
    };
    let names = ["particles.csv", "bed.dump", "bed.xyz", "bed.vtu", "bed.txt"];
    let name = names[(how & 7) as usize % names.len()];
    let dir = scratch().join("bed");
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("scratch bed directory");
    let (file, beside) = split_nul(rest);
    let path = put(&dir, name, file);
    if let Some(summary) = beside {
        put(&dir, "summary.json", summary);
    }
    let hint = (how & 8 != 0).then(|| BoxHint {
        size: if how & 16 != 0 {
            vec![100.0, 100.0, 100.0]
        } else {
            vec![100.0, 100.0]
        },
        periodic: how & 32 != 0,
    });
    let Ok((bed, read)) = packbed::read_bed_report(&path, hint.as_ref()) else {
        return false;
    };
    let n = match &bed {
        AnyBed::D2(b) => b.len(),
        AnyBed::D3(b) => b.len(),
    };
    if n <= SMALL {
        let _ = packbed::analyze_read_bed(name, bed, &read, &all_measures(), 0.0);
    }
    true
}

/// One `NAME=VALUE` line of overrides, as the command line would give it;
/// `None` when the command line itself would refuse it (clap's parsers).
fn override_line(o: &mut Overrides, line: &str) -> Option<()> {
    let (name, value) = line.split_once('=')?;
    match name.trim() {
        "dim" => o.dim = Some(value.trim().parse().ok().filter(|d| (2..=3).contains(d))?),
        "radii" => o.radii = Some(parse_numbers(value).ok()?),
        "ratio" => o.ratio = Some(parse_numbers(value).ok()?),
        "beads" => o.beads = Some(value.trim().parse().ok()?),
        "box" => o.container = Some(value.parse::<BoxSpec>().ok()?),
        "periodic" => o.periodic = true,
        "count" => o.count = Some(value.trim().parse().ok()?),
        "seed" => o.seed = Some(value.trim().parse().ok()?),
        "mode" => {
            o.mode = Some(match value.trim() {
                "deposit" => Mode::Deposit,
                "rsa" => Mode::Rsa,
                _ => return None,
            })
        }
        "large" => o.large = Some(value.trim().parse().ok()?),
        "measures" => o.measures = Some(Measure::parse_list(value).ok()?),
        _ => return None,
    }
    Some(())
}

/// A directory for configs, holding the size tables of `examples/` that the
/// example configs name.
fn config_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = scratch().join("config");
        fs::create_dir_all(&dir).expect("scratch config directory");
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
        for entry in fs::read_dir(examples).expect("examples/").flatten() {
            let path = entry.path();
            if path.extension().is_some_and(|e| e == "csv") {
                fs::copy(&path, dir.join(entry.file_name())).expect("copy a size table");
            }
        }
        dir
    })
}

/// A config file, then, after a NUL byte, overrides as `NAME=VALUE` lines
/// (`radii=10,20`, `box=200,200`, ...). Read, overridden, validated and
/// planned as `packbed run` and `packbed ensemble` do (a sweep resolved into
/// its points); a config that plans a small bed is also deposited and
/// analysed.
pub fn config(data: &[u8]) -> bool {
    let (file, overrides) = split_nul(data);
    let Ok(mut config) = Config::from_file(&put(config_dir(), "fuzz.toml", file)) else {
        return false;
    };
    if let Some(lines) = overrides {
        let mut o = Overrides::default();
        for line in String::from_utf8_lossy(lines).lines() {
            if override_line(&mut o, line).is_none() {
                return false;
            }
        }
        if o.apply(&mut config).is_err() {
            return false;
        }
    }
    // `run` refuses a sweep, `ensemble` resolves it into its points.
    let points = match &config.sweep {
        Some(sweep) => match packbed::validate_ensemble(&config).and(sweep.points(&config)) {
            Ok(p) => p.into_iter().map(|p| p.config).collect(),
            Err(_) => return false,
        },
        None if config.validate().is_ok() => vec![config],
        None => return false,
    };
    let mut accepted = true;
    for c in &points {
        let plan = c.planned();
        // A deposited bed holds what is drawn, so the guess is close; RSA
        // rejects large sizes and fills gaps with small ones, so only the
        // bound keeps its beds small.
        let small = plan.as_ref().is_ok_and(|p| match c.mode {
            Mode::Rsa => p.particles_at_most(),
            Mode::Deposit => p.estimated_particles(),
        } <= SMALL as u64);
        if small {
            let _ = packbed::run_bed(c, &mut |_| {});
        }
        accepted &= plan.is_ok();
    }
    accepted
}

/// A measured size distribution (`packbed`'s PSD tables). The first byte
/// chooses the sampling within classes (bit 0) and the bed's length unit
/// (bits 1–2: none, µm, mm, m); the rest is the table. A table that is read
/// must sample within its bounds and give passing curves from 0 to 100 %.
pub fn psd_table(data: &[u8]) -> bool {
    let Some((&how, file)) = data.split_first() else {
        return false;
    };
    let within = if how & 1 == 0 {
        Within::LogUniform
    } else {
        Within::Uniform
    };
    let unit = [None, Some(1e-6), Some(1e-3), Some(1.0)][((how >> 1) & 3) as usize];
    let path = put(scratch(), "table.csv", file);
    let Ok(table) = SizeTable::read(&path, within, unit) else {
        return false;
    };
    let (lo, hi) = table.bounds();
    assert!(0.0 < lo && lo <= hi && hi.is_finite(), "bounds {lo} {hi}");
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(u64::from(how));
    for _ in 0..64 {
        let r = table.sample(&mut rng);
        assert!(lo <= r && r <= hi, "draw {r} outside [{lo}, {hi}]");
        if let Some(r) = table.sample_at_most(0.5 * (lo + hi), &mut rng) {
            assert!(r <= 0.5 * (lo + hi) && r >= lo, "bounded draw {r}");
        }
    }
    let median = table.median();
    assert!(lo <= median && median <= hi, "median {median}");
    assert!(table.mean_cube().is_finite() && table.mean_cube() > 0.0);
    for x in [lo, median, hi] {
        for p in [table.number_passing(x), table.volume_passing(x)] {
            assert!((0.0..=1.0).contains(&p), "passing {p} at {x}");
        }
    }
    assert!(
        table.number_passing(hi) > 1.0 - 1e-9,
        "not all passing at the top"
    );
    let _ = table.describe();
    true
}

/// The config of the small ensemble of the `merge` and `resume` targets.
fn ensemble_config() -> Config {
    Config::from_toml(
        "dim = 2\n[box]\nwidth = 120.0\nheight = 120.0\n[[species]]\nradius = 10.0\n[[species]]\nradius = 20.0\n",
        "fuzz-merge.toml",
    )
    .expect("the merge target's config")
}

/// The options of shard `k` (`K/M`) of that ensemble: 3 replicates.
fn shard_options(k: &str) -> packbed::EnsembleOptions {
    packbed::EnsembleOptions {
        runs: 3,
        jobs: Some(1),
        shard: Shard::parse(k).expect("shard"),
        pictures: false,
        ..Default::default()
    }
}

/// Two shards of a small ensemble, made once per process with the library
/// (so that they always match its format).
fn shards() -> &'static (PathBuf, PathBuf) {
    static SHARDS: OnceLock<(PathBuf, PathBuf)> = OnceLock::new();
    SHARDS.get_or_init(|| {
        let config = ensemble_config();
        let make = |k: &str| {
            let out = scratch().join(format!("shard-{k}"));
            let _ = fs::remove_dir_all(&out);
            packbed::run_ensemble(&config, &shard_options(k), &out, &|_| {})
                .expect("the template shard");
            out
        };
        (make("0/2"), make("1/2"))
    })
}

/// Copies the directory tree `from` to `to`.
fn copy_tree(from: &Path, to: &Path) {
    fs::create_dir_all(to).expect("scratch directory");
    for e in fs::read_dir(from).expect("template directory") {
        let e = e.expect("directory entry");
        let dst = to.join(e.file_name());
        if e.file_type().expect("file type").is_dir() {
            copy_tree(&e.path(), &dst);
        } else {
            fs::copy(e.path(), &dst).expect("copy template file");
        }
    }
}

/// The first shard of a small ensemble as a rerun into it finds it, with its
/// replicate 0's `summary.json` replaced by the input: resume reads it and
/// reuses it (it belongs), rebuilds it (not JSON, another seed) or refuses
/// it by path (another config, version or measures). Accepted: the rerun
/// ended with the ensemble's files.
pub fn resume(data: &[u8]) -> bool {
    let (first, _) = shards();
    let dir = scratch().join("resume");
    let _ = fs::remove_dir_all(&dir);
    copy_tree(first, &dir);
    put(&dir.join("runs").join("0000"), "summary.json", data);
    packbed::run_ensemble(&ensemble_config(), &shard_options("0/2"), &dir, &|_| {}).is_ok()
}

/// The second shard of a small ensemble as `merge` finds it, with its
/// `manifest.json` replaced by the input up to its first NUL byte and, when
/// one follows, its replicate's `summary.json` by the rest.
pub fn merge(data: &[u8]) -> bool {
    let (first, second) = shards();
    let (manifest, summary) = split_nul(data);
    let shard = scratch().join("merge-shard");
    let _ = fs::remove_dir_all(&shard);
    let run = shard.join("runs").join("0001");
    fs::create_dir_all(&run).expect("scratch shard");
    put(&shard, "manifest.json", manifest);
    let summary = match summary {
        Some(s) => s.to_vec(),
        None => fs::read(second.join("runs/0001/summary.json")).expect("template summary"),
    };
    put(&run, "summary.json", &summary);
    let out = scratch().join("merge-out");
    let _ = fs::remove_dir_all(&out);
    packbed::merge_ensembles(&[first.clone(), shard], &out, false).is_ok()
}

/// Two runs as `compare` finds them: the first's `summary.json` is the input
/// up to its first NUL byte, the second's the rest (or, without a NUL, a
/// replicate summary of the small ensemble of [`merge`]). The comparison is
/// computed and written with its files; with its plots when the input's
/// length is even (drawing is the slow half: half the inputs skip it).
pub fn compare(data: &[u8]) -> bool {
    let (a, b) = split_nul(data);
    let b = match b {
        Some(b) => b.to_vec(),
        None => fs::read(shards().1.join("runs/0001/summary.json")).expect("template summary"),
    };
    let dirs = [scratch().join("compare-a"), scratch().join("compare-b")];
    for (dir, summary) in dirs.iter().zip([a, &b[..]]) {
        let _ = fs::remove_dir_all(dir);
        fs::create_dir_all(dir).expect("scratch run");
        put(dir, "summary.json", summary);
    }
    let out = scratch().join("compare-out");
    let _ = fs::remove_dir_all(&out);
    let Ok(groups) = packbed::compare::read_groups(&dirs) else {
        return false;
    };
    let Ok(c) = packbed::compare::compare(&groups) else {
        return false;
    };
    // Every text of the comparison, as the command prints and writes them.
    let _ = (c.to_text(&out), c.report(), c.permeability_lines());
    let pictures = data.len() % 2 == 0;
    c.to_csv().is_ok()
        && c.to_json().is_ok()
        && packbed::compare::write_comparison(&out, &groups, &c, pictures).is_ok()
}
