//! Integration tests of `packbed ensemble` and `packbed merge`: each runs the
//! built binary in a fresh temporary directory.

use crate::common::{
    assert_contains, assert_user_error, png_size, svg_texts, words, Scratch, SMALL, STAT_FILES,
};
use serde_json::Value;

fn args<'a>(head: &[&'a str], tail: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["ensemble"];
    v.extend_from_slice(head);
    v.extend_from_slice(tail);
    v
}

fn assert_same_stats(s: &Scratch, a: &str, b: &str, files: &[&str]) {
    for f in files {
        assert!(
            s.bytes(&format!("{a}/{f}")) == s.bytes(&format!("{b}/{f}")),
            "{a}/{f} and {b}/{f} differ"
        );
    }
}

#[test]
fn ensemble_writes_its_files_and_table() {
    let s = Scratch::new();
    let o = s.ok(&args(SMALL, &["--runs", "6", "--out", "e"]));
    assert_contains(&o.stdout, "ensemble of 6 beds");
    assert_contains(&o.stdout, "packing.global");
    for f in STAT_FILES.iter().chain(&["timing.json", "manifest.json"]) {
        assert!(s.path("e").join(f).exists(), "{f}");
    }
    for i in 0..6 {
        let run = s.path(&format!("e/runs/{i:04}"));
        let names: Vec<_> = std::fs::read_dir(&run)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(
            names,
            ["summary.json"],
            "only the summary without --keep-beds"
        );
    }
    let csv = s.read("e/ensemble.csv");
    assert!(csv.starts_with("name,n,mean,sd,min,max,kind\n"), "{csv}");
    assert!(
        csv.lines().any(|l| l.starts_with("packing.global,6,")),
        "{csv}"
    );
    let md = s.read("e/ensemble.md");
    assert!(md.contains("| measure | min | mean ± sd | max |"), "{md}");
    assert!(md.contains("| packing.global | "), "{md}");
    let json: Value = serde_json::from_str(&s.read("e/ensemble.json")).unwrap();
    assert_eq!(json["replicates"], 6);
    assert_eq!(json["master_seed"], 1);
    // --keep-beds writes the beds too.
    s.ok(&args(
        SMALL,
        &["--runs", "2", "--out", "k", "--keep-beds", "-q"],
    ));
    assert!(s.path("k/runs/0001/particles.csv").exists());
    assert!(s.path("k/runs/0001/contacts.csv").exists());
}

const PLOTS: [&str; 4] = [
    "plot_packing",
    "plot_coordination",
    "plot_coordination_means",
    "plot_profile",
];

#[test]
fn ensembles_and_sweeps_plot_their_statistics() {
    let s = Scratch::new();
    // A box wide enough for a bulk of at least 50 bodies (else its bar is left out).
    let wide = ["--dim", "2", "--radii", "20,10", "--box", "diameters=16"];
    s.ok(&args(&wide, &["--runs", "4", "--out", "e", "-q"]));
    for p in PLOTS {
        assert_eq!(
            png_size(&s.bytes(&format!("e/{p}.png"))),
            (1000, 700),
            "{p}"
        );
    }
    let svg = s.read("e/plot_coordination.svg");
    let texts = svg_texts(&svg);
    for want in [
        "Coordination numbers, summed over 4 beds",
        "all particles",
        "large",
        "small",
        "particles (%)",
    ] {
        assert!(texts.iter().any(|t| t == want), "no `{want}` in {texts:?}");
    }
    // Bars: three groups per coordination number shown, plus the background.
    let bins = texts.iter().filter(|t| t.parse::<u32>().is_ok()).count();
    assert!(bins >= 3, "{texts:?}");
    let svg = s.read("e/plot_packing.svg");
    for want in ["global", "bulk", "floor", "roof", "wall", "centre"] {
        assert!(svg_texts(&svg).iter().any(|t| t == want), "no {want} dot");
    }
    // One dot (mean ± sd) per region, and no bars but the background.
    assert_eq!(svg.matches("class=\"marker\"").count(), 6, "{svg}");
    assert_eq!(svg.matches("<rect").count(), 1, "{svg}");
    // The axis spans the fractions, not 0–1.
    let ticks: Vec<f64> = svg_texts(&svg)
        .iter()
        .filter_map(|t| t.parse().ok())
        .collect();
    assert!(ticks.len() >= 3, "{ticks:?}");
    assert!(ticks.iter().all(|&t| t > 0.2 && t < 1.0), "{ticks:?}");
    // A sweep over a number draws lines: one marker per value.
    let cfg = s.input(
        "sweep.toml",
        "dim = 2\n[box]\ndiameters = 6\n[[species]]\nradius = 20\n[[species]]\nradius = 10\n[sweep]\nparameter = \"box.diameters\"\nvalues = [5, 7, 9]\n",
    )
    .display()
    .to_string();
    s.ok(&["ensemble", &cfg, "--runs", "3", "--out", "sw", "-q"]);
    let svg = s.read("sw/plot_sweep_packing_global.svg");
    assert_eq!(svg.matches("class=\"marker\"").count(), 3, "{svg}");
    let texts = svg_texts(&svg);
    assert!(
        texts
            .iter()
            .any(|t| t == "box.diameters: box width (largest particle diameters)"),
        "{texts:?}"
    );
    let svg = s.read("sw/plot_sweep_percolation.svg");
    assert!(svg_texts(&svg)
        .iter()
        .any(|t| t == "Beds with a percolation chain, per box.diameters"));
    assert!(svg_texts(&svg).iter().any(|t| t == "beds with a chain (%)"));
    for d in ["00-diameters-5", "02-diameters-9"] {
        for p in PLOTS {
            assert!(s.path(&format!("sw/sweep/{d}/{p}.svg")).exists(), "{d}/{p}");
        }
    }
    // --no-pictures: statistics only.
    s.ok(&args(
        SMALL,
        &["--runs", "2", "--out", "np", "-q", "--no-pictures"],
    ));
    let names: Vec<String> = std::fs::read_dir(s.path("np"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!names.iter().any(|n| n.starts_with("plot_")), "{names:?}");
}

#[test]
fn jobs_and_shards_give_the_same_files() {
    let s = Scratch::new();
    s.ok(&args(
        SMALL,
        &["--runs", "9", "--jobs", "1", "--out", "j1", "-q"],
    ));
    s.ok(&args(
        SMALL,
        &["--runs", "9", "--jobs", "2", "--out", "j2", "-q"],
    ));
    assert_same_stats(&s, "j1", "j2", &STAT_FILES);
    for k in 0..3 {
        let shard = format!("{k}/3");
        let out = format!("s{k}");
        s.ok(&args(
            SMALL,
            &["--runs", "9", "--shard", &shard, "--out", &out, "-q"],
        ));
    }
    let o = s.ok(&["merge", "s2", "s0", "s1", "--out", "merged"]);
    assert_contains(&o.stdout, "ensemble of 9 beds");
    assert_same_stats(&s, "j1", "merged", &STAT_FILES);
    let plots: Vec<String> = PLOTS
        .iter()
        .flat_map(|p| [format!("{p}.png"), format!("{p}.svg")])
        .collect();
    let plots: Vec<&str> = plots.iter().map(String::as_str).collect();
    assert_same_stats(&s, "j1", "j2", &plots);
    assert_same_stats(&s, "j1", "merged", &plots);
    let shard_json: Value = serde_json::from_str(&s.read("s1/ensemble.json")).unwrap();
    assert_eq!(shard_json["shard"]["index"], 1);
    assert_eq!(shard_json["replicates"], 3);
}

#[test]
fn interrupted_ensemble_resumes() {
    let s = Scratch::new();
    s.ok(&args(SMALL, &["--runs", "6", "--out", "full", "-q"]));
    s.ok(&args(SMALL, &["--runs", "6", "--out", "cut", "-q"]));
    // As if killed: two replicates never finished, statistics not written.
    std::fs::remove_dir_all(s.path("cut/runs/0002")).unwrap();
    std::fs::remove_dir_all(s.path("cut/runs/0005")).unwrap();
    std::fs::remove_file(s.path("cut/ensemble.json")).unwrap();
    let o = s.ok(&args(SMALL, &["--runs", "6", "--out", "cut"]));
    assert_contains(&o.stdout, "2 built, 4 resumed");
    assert_same_stats(&s, "full", "cut", &STAT_FILES);
    // Another config into the same directory is refused.
    assert_user_error(
        &s,
        &[
            "ensemble",
            "--dim",
            "2",
            "--radii",
            "20,10",
            "--box",
            "diameters=9",
            "--runs",
            "6",
            "--out",
            "cut",
        ],
        &["different config", "box.diameters"],
    );
}

#[test]
fn sweeps_write_one_row_per_value() {
    let s = Scratch::new();
    let cfg = s.input(
        "sweep.toml",
        "dim = 2\n[box]\ndiameters = 8\n[[species]]\nradius = 20\n[[species]]\nradius = 10\n[ensemble]\nruns = 3\n[sweep]\nparameter = \"ratio\"\nvalues = [[1, 1], [1, 2.5]]\n",
    )
    .display()
    .to_string();
    let o = s.ok(&["ensemble", &cfg, "--out", "sw"]);
    assert_contains(&o.stdout, "1:2.5");
    for d in ["00-ratio-1-1", "01-ratio-1-2.5"] {
        assert!(s.path(&format!("sw/sweep/{d}/ensemble.md")).exists(), "{d}");
        assert!(
            s.path(&format!("sw/sweep/{d}/runs/0002/summary.json"))
                .exists(),
            "{d}"
        );
    }
    let md = s.read("sw/sweep.md");
    assert!(
        md.contains("| 1:1 | 3 |") && md.contains("| 1:2.5 | 3 |"),
        "{md}"
    );
    let csv = s.read("sw/sweep.csv");
    assert!(
        csv.starts_with("index,label,name,n,mean,sd,min,max,kind\n"),
        "{csv}"
    );
    assert!(csv.contains("\n1,1:2.5,packing.global,3,"), "{csv}");
    // The ratio really changed: the second value has more small discs.
    let small = |d: &str| -> f64 {
        let v: Value =
            serde_json::from_str(&s.read(&format!("sw/sweep/{d}/ensemble.json"))).unwrap();
        v["measures"]["species.small.placed"]["mean"]
            .as_f64()
            .unwrap()
            / v["measures"]["species.large.placed"]["mean"]
                .as_f64()
                .unwrap()
    };
    assert!(small("01-ratio-1-2.5") > small("00-ratio-1-1") * 1.5);
    // `run` refuses a sweep config.
    assert_user_error(
        &s,
        &["run", &cfg, "--out", "one"],
        &["[sweep]", "packbed ensemble"],
    );
}

/// A sweep over `compaction.steps` runs from the settled bed (0 steps) toward
/// the compacted one; the same statistics on one thread and on two, and the
/// compaction's wall time is not among them.
#[test]
fn a_sweep_over_compaction_steps_densifies_the_bed() {
    let s = Scratch::new();
    let cfg = s
        .input(
            "compact.toml",
            "dim = 2\n[box]\nwidth = 12.3\nheight = 400\nperiodic = true\n[fill]\ncount = 150\n\
             base_layer = \"none\"\n[[species]]\nradius = 0.5\n[ensemble]\nruns = 2\n\
             [sweep]\nparameter = \"compaction.steps\"\nvalues = [0, 60]\n",
        )
        .display()
        .to_string();
    s.ok(&["ensemble", &cfg, "--out", "one", "--jobs", "1", "-q"]);
    s.ok(&["ensemble", &cfg, "--out", "two", "--jobs", "2", "-q"]);
    assert_same_stats(&s, "one", "two", &["sweep.csv", "sweep.md"]);
    let mean = |d: &str, m: &str| -> f64 {
        let v: Value =
            serde_json::from_str(&s.read(&format!("one/sweep/{d}/ensemble.json"))).unwrap();
        v["measures"][m]["mean"].as_f64().unwrap()
    };
    let (settled, compacted) = ("00-steps-0", "01-steps-60");
    assert_eq!(mean(settled, "compaction.steps"), 0.0);
    assert!(mean(compacted, "compaction.steps") > 0.0);
    // Settled discs at φ ≈ 0.82, Z ≈ 4.2; 60 steps take them to ≈ 0.895,
    // Z ≈ 5.6 (hexagonal order is 0.907, 6).
    let (p0, p1) = (
        mean(settled, "packing.bulk"),
        mean(compacted, "packing.bulk"),
    );
    assert!(p0 < 0.84 && p1 > 0.88, "φ {p0} → {p1}");
    let (z0, z1) = (
        mean(settled, "coordination.mean_bulk"),
        mean(compacted, "coordination.mean_bulk"),
    );
    assert!(z1 > z0 + 1.0, "Z {z0} → {z1}");
    assert!(!s.read("one/sweep.csv").contains("compaction.seconds"));
}

/// A compaction cut short by its step budget is a warning: `run` prints it
/// on stderr and keeps it in `summary.json`, and its summary names the
/// steps and the stop; an ensemble says how many replicates warned (a
/// compaction needs at least six steps to reach its finest step and stop).
#[test]
fn a_compaction_cut_short_is_a_warning() {
    let s = Scratch::new();
    let bed = "dim = 2\n[box]\nwidth = 12.3\nheight = 400\nperiodic = true\n[fill]\ncount = 150\n\
               base_layer = \"none\"\n[[species]]\nradius = 0.5\n[compaction]\nsteps = 2\n";
    let one = s.input("short.toml", bed).display().to_string();
    let o = s.ok(&["run", &one, "--out", "bed", "--no-pictures"]);
    let says = "packbed: warning: compaction: stopped at its budget of 2 steps";
    assert!(o.stderr.contains(says), "{}", o.stderr);
    assert_contains(
        &o.stdout,
        "compaction: 2 steps (stopped by the step budget)",
    );
    let v: Value = serde_json::from_str(&s.read("bed/summary.json")).unwrap();
    assert_eq!(v["compaction"]["stopped_by"], "steps");
    let kept = v["warnings"].as_array().expect("warnings in summary.json");
    assert!(
        kept.iter()
            .any(|w| w.as_str().unwrap().starts_with("compaction: stopped")),
        "{kept:?}"
    );
    let many = s
        .input(
            "short-ensemble.toml",
            &format!("{bed}[ensemble]\nruns = 2\n"),
        )
        .display()
        .to_string();
    let o = s.ok(&["ensemble", &many, "--out", "ens", "-q"]);
    let count = "2 of 2 replicates warned; the first, ens/runs/0000/summary.json: compaction:";
    assert!(o.stderr.contains(count), "{}", o.stderr);
    assert!(
        o.stderr
            .contains("compaction: stopped at its budget of 2 steps"),
        "{}",
        o.stderr
    );
    // Without the cut, no such warning.
    let whole = s
        .input("whole.toml", &bed.replace("steps = 2", "steps = 0"))
        .display()
        .to_string();
    let o = s.ok(&["run", &whole, "--out", "settled", "--no-pictures", "-q"]);
    assert!(!o.stderr.contains("compaction"), "{}", o.stderr);
    // The descent is a length: a bed in um says so.
    let in_um = s
        .input(
            "short-um.toml",
            &format!("{bed}[analysis]\nlength_unit = \"um\"\n"),
        )
        .display()
        .to_string();
    let o = s.ok(&["run", &in_um, "--out", "in-um", "--no-pictures"]);
    let line = o
        .stdout
        .lines()
        .find(|l| l.contains("compaction: 2 steps"))
        .unwrap_or_else(|| panic!("{}", o.stdout));
    let down = line.split("centre of mass down ").nth(1).expect(line);
    let (number, rest) = down.split_once(' ').expect(line);
    assert!(
        number.parse::<f64>().is_ok() && rest.starts_with("um,"),
        "{line}"
    );
}

#[test]
fn bad_inputs_are_refused() {
    let s = Scratch::new();
    assert_user_error(
        &s,
        &args(SMALL, &["--runs", "0"]),
        &["--runs", "at least 1"],
    );
    assert_user_error(&s, &args(SMALL, &[]), &["--runs"]);
    assert_user_error(&s, &args(SMALL, &["--runs", "-3"]), &["-3"]);
    assert_user_error(
        &s,
        &args(SMALL, &["--runs", "1000000000000"]),
        &["--runs", "at most"],
    );
    assert_user_error(
        &s,
        &args(SMALL, &["--runs", "2", "--jobs", "0"]),
        &["--jobs"],
    );
    for bad in ["3/2", "2/2", "1", "x/4", "1/0"] {
        assert_user_error(
            &s,
            &args(SMALL, &["--runs", "2", "--shard", bad]),
            &["--shard", bad],
        );
    }
    let bad_sweep = s
        .input(
            "bad.toml",
            "[sweep]\nparameter = \"ratio\"\nvalues = [[1, 2, 3]]\n",
        )
        .display()
        .to_string();
    assert_user_error(
        &s,
        &["ensemble", &bad_sweep, "--runs", "2"],
        &["bad.toml", "sweep.values[0]"],
    );
    let typo = s
        .input(
            "typo.toml",
            "[sweep]\nparameter = \"ratio\"\nvalue = [[1, 1]]\n",
        )
        .display()
        .to_string();
    assert_user_error(
        &s,
        &["ensemble", &typo, "--runs", "2"],
        &["typo.toml", "value"],
    );
    assert_user_error(&s, &["merge", "nowhere"], &["nowhere", "manifest.json"]);
    // Shards of different configs, and an incomplete set.
    s.ok(&args(
        SMALL,
        &["--runs", "4", "--shard", "0/2", "--out", "a", "-q"],
    ));
    let other = words("--dim 2 --radii 20,10 --ratio 1,3 --box diameters=8");
    s.ok(&args(
        &other,
        &["--runs", "4", "--shard", "1/2", "--out", "b", "-q"],
    ));
    assert_user_error(
        &s,
        &["merge", "a", "b", "--out", "m"],
        &["different configs"],
    );
    assert_user_error(&s, &["merge", "a", "--out", "m"], &["shard 1/2 missing"]);
    assert_user_error(&s, &["merge", "a", "a", "--out", "m"], &["twice"]);
}

#[test]
fn replicate_seeds_rebuild_with_run() {
    // A replicate's summary names its seed; `run --seed` with it builds the same bed.
    let s = Scratch::new();
    s.ok(&args(SMALL, &["--runs", "2", "--out", "e", "-q"]));
    let v: Value = serde_json::from_str(&s.read("e/runs/0001/summary.json")).unwrap();
    let seed = v["seed"].as_u64().unwrap().to_string();
    let mut run = vec!["run"];
    run.extend_from_slice(SMALL);
    run.extend_from_slice(&["--seed", &seed, "--out", "one", "-q"]);
    s.ok(&run);
    let w: Value = serde_json::from_str(&s.read("one/summary.json")).unwrap();
    assert_eq!(v["packing"], w["packing"]);
    assert_eq!(v["counts"], w["counts"]);
}

/// `--jobs` far above the cores is capped at them, with one note on stderr.
#[test]
fn jobs_above_the_cores_are_capped_with_a_note() {
    let s = Scratch::new();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let o = s.ok(&args(
        SMALL,
        &["--runs", "2", "--jobs", "1000", "--out", "e"],
    ));
    let notes: Vec<&str> = o.stderr.lines().collect();
    assert_eq!(notes.len(), 1, "{}", o.stderr);
    assert!(
        notes[0].contains("--jobs 1000") && notes[0].contains(&format!("using {cores} threads")),
        "{}",
        o.stderr
    );
    assert_contains(&o.stdout, &format!("{cores} threads"));
    let o = s.ok(&args(SMALL, &["--runs", "2", "--jobs", "1", "--out", "f"]));
    assert!(o.stderr.is_empty(), "{}", o.stderr);
}

/// A smaller `--runs` into an existing ensemble says which replicates it reuses
/// and that the statistics are over the runs requested.
#[test]
fn fewer_runs_than_the_directory_holds_are_announced() {
    let s = Scratch::new();
    s.ok(&args(SMALL, &["--runs", "4", "--out", "e"]));
    let o = s.ok(&args(SMALL, &["--runs", "2", "--out", "e"]));
    let notes: Vec<&str> = o.stderr.lines().collect();
    assert_eq!(notes.len(), 1, "{}", o.stderr);
    for n in [
        "4 replicates",
        "replicates 0–1",
        "over the 2 requested",
        "replicates 2–3",
    ] {
        assert!(notes[0].contains(n), "`{n}` not in {}", notes[0]);
    }
    assert!(
        o.stdout.contains("ensemble of 2 beds (0 built, 2 resumed"),
        "{}",
        o.stdout
    );
    let csv = s.read("e/ensemble.csv");
    assert!(
        csv.lines().any(|l| l.starts_with("packing.global,2,")),
        "{csv}"
    );
    // Growing again, or the same count, is the ordinary resume: no note.
    let o = s.ok(&args(SMALL, &["--runs", "4", "--out", "e"]));
    assert!(o.stderr.is_empty(), "{}", o.stderr);
}

/// One replicate is `1 bed`, on screen and in ensemble.md.
#[test]
fn one_bed_is_singular() {
    let s = Scratch::new();
    let o = s.ok(&args(SMALL, &["--runs", "1", "--jobs", "1", "--out", "e"]));
    assert!(
        o.stdout.starts_with("packbed: ensemble of 1 bed ("),
        "{}",
        o.stdout
    );
    assert!(o.stdout.contains("1 thread)"), "{}", o.stdout);
    let md = s.read("e/ensemble.md");
    assert!(md.starts_with("# Ensemble of 1 bed\n"), "{md}");
    assert!(!md.contains("1 beds"), "{md}");
}

#[test]
fn a_resume_never_reuses_a_damaged_replicate_summary() {
    let s = Scratch::new();
    s.ok(&args(SMALL, &["--runs", "4", "--out", "full", "-q"]));
    s.ok(&args(SMALL, &["--runs", "4", "--out", "e", "-q"]));
    // Cut short: not JSON, so the replicate is built again.
    let cut = "e/runs/0001/summary.json";
    let good = s.read(cut);
    std::fs::write(s.path(cut), &good[..good.len() / 2]).unwrap();
    let o = s.ok(&args(SMALL, &["--runs", "4", "--out", "e"]));
    assert_contains(&o.stdout, "1 built, 3 resumed");
    let mut v: Value = serde_json::from_str(&good).unwrap();
    let rebuilt: Value = serde_json::from_str(&s.read(cut)).unwrap();
    assert_eq!(rebuilt["packing"], v["packing"]);
    assert_same_stats(&s, "full", "e", &STAT_FILES);
    // JSON, but a measure of the wrong kind: it was dropped from the
    // statistics without a word ("3 of 4 beds"); now refused, named.
    v["packing"]["global"] = Value::String("0.6".into());
    std::fs::write(s.path(cut), serde_json::to_string(&v).unwrap()).unwrap();
    assert_user_error(
        &s,
        &args(SMALL, &["--runs", "4", "--out", "e"]),
        &[
            cut,
            "is damaged",
            "`packing.global` is text",
            "remove it and rerun",
        ],
    );
    std::fs::remove_file(s.path(cut)).unwrap();
    s.ok(&args(SMALL, &["--runs", "4", "--out", "e", "-q"]));
    assert_same_stats(&s, "full", "e", &STAT_FILES);
}

/// A replicate summary proves it belongs to its ensemble (`proof` in the
/// file: the config's hash and the measures it holds, beside its
/// `packbed_version`); `merge` and a resume refuse one that does not, by path,
/// instead of mixing it into the statistics.
#[test]
fn a_replicate_that_does_not_belong_is_refused_by_merge_and_resume() {
    let s = Scratch::new();
    s.ok(&args(
        SMALL,
        &["--runs", "4", "--shard", "0/2", "--out", "s0", "-q"],
    ));
    s.ok(&args(
        SMALL,
        &["--runs", "4", "--shard", "1/2", "--out", "s1", "-q"],
    ));
    // The same replicate (same seed) of another config: radii 20,15.
    let other = ["--dim", "2", "--radii", "20,15", "--box", "diameters=8"];
    s.ok(&args(
        &other,
        &["--runs", "4", "--shard", "1/2", "--out", "o1", "-q"],
    ));
    let file = "s1/runs/0001/summary.json";
    let own = s.read(file);
    let mut no_measure: Value = serde_json::from_str(&own).unwrap();
    no_measure.as_object_mut().unwrap().remove("coordination");
    let mut old: Value = serde_json::from_str(&own).unwrap();
    old["packbed_version"] = Value::String("0.0.9".into());
    let strangers = [
        (s.read("o1/runs/0001/summary.json"), "another config"),
        (no_measure.to_string(), "lacks the measure `coordination`"),
        (old.to_string(), "made by packbed 0.0.9"),
    ];
    for (text, why) in &strangers {
        std::fs::write(s.path(file), text).unwrap();
        assert_user_error(
            &s,
            &["merge", "s0", "s1", "--out", "m"],
            &[file, "does not belong to this ensemble", why],
        );
        assert_user_error(
            &s,
            &args(SMALL, &["--runs", "4", "--shard", "1/2", "--out", "s1"]),
            &[file, "does not belong to this ensemble", why, "remove it"],
        );
    }
    // Its own summary back: merged and resumed as before.
    std::fs::write(s.path(file), &own).unwrap();
    s.ok(&["merge", "s0", "s1", "--out", "m", "-q"]);
    let o = s.ok(&args(
        SMALL,
        &["--runs", "4", "--shard", "1/2", "--out", "s1"],
    ));
    assert_contains(&o.stdout, "0 built, 2 resumed");
}

/// Random sequential addition places single spheres and discs: a chain is
/// refused with the config, before any work or file, by every command.
#[test]
fn rsa_with_chains_is_refused_before_any_work() {
    let s = Scratch::new();
    let config = s.input(
        "rsa-chains.toml",
        "dim = 2\nmode = \"rsa\"\n[fill]\ncount = 20\n[[species]]\nname = \"rods\"\nradius = 10\n\
         shape = \"chain\"\nbeads = 3\n",
    );
    let config = config.to_str().unwrap();
    let needles = ["mode = \"rsa\"", "`rods` is a chain"];
    assert_user_error(&s, &["run", config, "--out", "r"], &needles);
    assert_user_error(
        &s,
        &["ensemble", config, "--runs", "2", "--out", "e"],
        &needles,
    );
    let dir = s.path("cluster");
    let dir = dir.to_str().unwrap();
    assert_user_error(
        &s,
        &["slurm", config, "--runs", "2", "--tasks", "1", "--out", dir],
        &needles,
    );
}
