//! Integration tests of the `packbed` command: each runs the built binary in a
//! fresh temporary directory and checks exit code, messages and files.

use crate::common::{
    assert_config_refused, assert_contains, assert_user_error, words, Outcome, Scratch,
};
use packbed::Config;
use serde_json::Value;
use std::path::Path;

/// A small, fast bed: 2D thesis box of equal discs of radius 10 (~600 discs).
const SMALL_2D: &str = "dim = 2\nseed = 5\n[[species]]\nradius = 10\n";

// ---- user errors ---------------------------------------------------------

#[test]
fn negative_radius_is_refused() {
    let s = Scratch::new();
    assert_user_error(
        &s,
        &["run", "--radii=-10,20"],
        &["species[0].radius", "-10"],
    );
    assert_user_error(&s, &["run", "--radii", "-10"], &["species[0].radius"]);
    assert_config_refused(
        &s,
        "neg.toml",
        "[[species]]\nradius = -5\n",
        &["neg.toml", "radius"],
    );
}

#[test]
fn nan_radius_is_refused() {
    let s = Scratch::new();
    assert_user_error(
        &s,
        &["run", "--radii", "nan,10"],
        &["species[0].radius", "NaN"],
    );
    assert_config_refused(
        &s,
        "nan.toml",
        "dim = 2\n[[species]]\nradius = nan\n",
        &["radius", "NaN"],
    );
    assert_config_refused(
        &s,
        "inf.toml",
        "[[species]]\nradius = 10\nratio = inf\n",
        &["ratio"],
    );
}

#[test]
fn unknown_key_is_named_with_its_line() {
    let s = Scratch::new();
    assert_config_refused(
        &s,
        "typo.toml",
        "dim = 3\n\n[box]\nwidht = 300\n",
        &["widht", "typo.toml:4"],
    );
    assert_config_refused(&s, "top.toml", "seeed = 3\n", &["seeed", "top.toml:1"]);
}

#[test]
fn box_smaller_than_particle_is_refused() {
    let s = Scratch::new();
    assert_user_error(
        &s,
        &["run", "--dim", "2", "--radii", "20", "--box", "30,100"],
        &["smaller than the largest particle"],
    );
    assert_config_refused(&s, "box.toml", "[box]\ndiameters = 0.5\n", &["smaller"]);
}

#[test]
fn unreadable_psd_table_is_refused() {
    let s = Scratch::new();
    assert_config_refused(
        &s,
        "psd.toml",
        "[[species]]\nsize = { table = \"missing-psd.csv\" }\n",
        &["missing-psd.csv"],
    );
    s.input("bad.csv", "radius,number\n10,1\n12,abc\n");
    assert_config_refused(
        &s,
        "bad.toml",
        "[[species]]\nsize = { table = \"bad.csv\" }\n",
        &["bad.csv:3"],
    );
}

#[test]
fn a_medium_file_reaching_into_the_feed_region_is_refused() {
    // Two spheres 3 high; lifted by the slurry's diameter (2) they stand 5
    // high, above the roof of a box 4 high: no room for the slurry.
    let s = Scratch::new();
    s.input(
        "plate.csv",
        "id,species,body,x,y,z,r\n0,0,0,5,5,1.5,1.5\n1,0,1,10,5,1.5,1.5\n",
    );
    assert_config_refused(
        &s,
        "plate.toml",
        "[box]\nwidth = 24\ndepth = 24\nheight = 4\nperiodic = true\n\
         [[species]]\nname = \"slurry\"\nradius = 1\n\
         [[feeds]]\nfile = \"plate.csv\"\n[[feeds]]\nspecies = [\"slurry\"]\ncount = 3\n",
        &[
            "feeds[0].file",
            "plate.csv",
            "stands 5 high",
            "box.height = 4",
            "feed region",
        ],
    );
}

#[test]
fn a_medium_file_with_no_opening_is_refused_for_a_filtration() {
    // One body of beads 0.5 apart (radius 1) in two layers over the whole
    // periodic floor: a plate no fluid passes.
    let s = Scratch::new();
    let mut plate = String::from("id,species,body,x,y,z,r\n");
    for id in 0..2 * 48 * 48 {
        let (k, i, j) = (id / (48 * 48), id / 48 % 48, id % 48);
        let (x, y, z) = (0.5 * i as f64, 0.5 * j as f64, 1 + 2 * k);
        plate.push_str(&format!("{id},0,0,{x},{y},{z},1\n"));
    }
    s.input("plate.csv", &plate);
    assert_config_refused(
        &s,
        "closed.toml",
        "[box]\nwidth = 24\ndepth = 24\nheight = 400\nperiodic = true\n\
         [[species]]\nname = \"slurry\"\nradius = 1\n\
         [[feeds]]\nfile = \"plate.csv\"\n[[feeds]]\nspecies = [\"slurry\"]\ncount = 30\n\
         [analysis]\nlength_unit = \"um\"\nsolid_density = 2650\n\
         [filtration]\npressure = 1e5\nconcentration = 100\n",
        &["feeds[0].file", "plate.csv", "no opening", "[filtration]"],
    );
}

#[test]
fn ratios_summing_to_zero_are_refused() {
    let s = Scratch::new();
    assert_user_error(&s, &["run", "--ratio", "0,0"], &["sum to zero"]);
}

#[test]
fn bad_override_syntax_is_explained() {
    let s = Scratch::new();
    assert_user_error(&s, &["run", "--radii", "10,abc"], &["--radii", "abc"]);
    assert_user_error(&s, &["run", "--box", "big"], &["--box", "big"]);
    assert_user_error(&s, &["run", "--dim", "2", "--box", "1,2,3"], &["--box"]);
    assert_user_error(
        &s,
        &["run", "--radii", "10,20", "--ratio", "1"],
        &["--ratio"],
    );
    assert_user_error(&s, &["run", "--dim", "4"], &["--dim"]);
    assert_user_error(&s, &["run", "--mode", "fast"], &["--mode"]);
    assert_user_error(&s, &["run", "--count", "-3"], &["--count"]);
    assert_user_error(&s, &["run", "--frobnicate"], &["--frobnicate"]);
    assert_user_error(&s, &["bench", "--n", "0"], &["--n"]);
    assert_user_error(&s, &["bench", "--gsd", "0.5"], &["--gsd", "`0.5`", ">= 1"]);
    assert_user_error(&s, &["bench", "--gsd", "NaN"], &["--gsd", "NaN"]);
    assert_user_error(
        &s,
        &["bench", "--radii", "10,-2"],
        &["--radii", "`-2`", "positive"],
    );
    // A negative value of a rule reaches the rule's own check, not the
    // argument parser's "unexpected argument".
    assert_user_error(&s, &["bench", "--gsd", "-2"], &["--gsd", "`-2`"]);
    for (flag, setting) in [
        ("--restitution", "settling.restitution"),
        ("--sticking", "settling.sticking"),
        ("--friction-angle", "settling.friction_angle"),
    ] {
        assert_user_error(&s, &["bench", flag, "-0.5"], &[setting, "-0.5"]);
    }
    assert_user_error(&s, &["bench", "--contacts", "-1"], &["--contacts", "-1"]);
    assert_user_error(&s, &["analyze"], &["analyze"]);
}

#[test]
fn missing_config_file_is_refused() {
    let s = Scratch::new();
    assert_user_error(&s, &["run", "no-such.toml"], &["no-such.toml"]);
}

#[test]
fn out_path_that_is_a_file_is_refused() {
    let s = Scratch::new();
    let f = s.input("taken", "not a directory");
    let o = s.packbed(&["run", "--out", f.to_str().unwrap()]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert_contains(&o.stderr, "not a directory");
    assert_eq!(std::fs::read_to_string(&f).unwrap(), "not a directory");
    // Below a file: refused before the run, not after it.
    let below = f.join("sub");
    let o = s.packbed(&["run", "--out", below.to_str().unwrap()]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert_eq!(o.stderr.lines().count(), 1, "{}", o.stderr);
    assert!(o.stdout.is_empty(), "the run went ahead: {}", o.stdout);
}

#[test]
fn io_errors_are_not_repeated() {
    let s = Scratch::new();
    let o = s.packbed(&["run", "no-such.toml"]);
    let line = o.stderr.trim_end();
    assert_eq!(line.matches("os error").count(), 1, "{line}");
}

#[test]
fn help_and_version_succeed() {
    let s = Scratch::new();
    for args in [&["--help"][..], &["run", "--help"], &["--version"]] {
        let o = s.packbed(args);
        assert_eq!(o.code, 0, "{args:?}: {}", o.stderr);
        assert!(!o.stdout.is_empty());
    }
    // No command: the help, as a usage error.
    assert_eq!(s.packbed(&[]).code, 2);
}

// ---- example configs -------------------------------------------------------

fn as_json(c: &Config) -> Value {
    serde_json::to_value(c).unwrap()
}

#[test]
fn example_parses_back_to_the_default() {
    let s = Scratch::new();
    let o = s.packbed(&["example"]);
    assert_eq!(o.code, 0);
    let parsed = Config::from_toml(&o.stdout, "example").unwrap();
    assert_eq!(as_json(&parsed), as_json(&Config::default()));
}

#[test]
fn example_files_are_valid() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut n = 0;
    let files = [dir.clone(), dir.join("settling"), dir.join("filtration")]
        .into_iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap())
        .map(|e| e.unwrap().path());
    for p in files {
        if p.extension().is_some_and(|x| x == "toml") {
            let c = Config::from_file(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            // A sweep is an ensemble's: every value is planned.
            let ok = match (c.sweep.is_some(), c.dim) {
                (true, _) => packbed::validate_ensemble(&c),
                (false, 2) => c.plan::<2>().map(drop),
                (false, _) => c.plan::<3>().map(drop),
            };
            ok.unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            n += 1;
        }
    }
    assert!(n >= 3, "only {n} example configs");
}

// ---- runs (need the deposition engine and the analysis) ---------------------

/// Runs the small 2D bed into `work/<out>` and returns the outcome.
fn small_run(s: &Scratch, out: &str, extra: &[&str]) -> Outcome {
    let c = s.input("small.toml", SMALL_2D);
    let mut args = vec!["run", c.to_str().unwrap(), "--out", out];
    args.extend_from_slice(extra);
    let o = s.packbed(&args);
    assert_eq!(o.code, 0, "{args:?}: {}", o.stderr);
    o
}

#[test]
fn run_writes_the_files_of_the_contract() {
    let s = Scratch::new();
    let o = small_run(&s, "out", &[]);
    assert_contains(&o.stdout, "packing fraction");
    assert_contains(&o.stdout, "out");
    let mut names: Vec<_> = std::fs::read_dir(s.work.join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    // Exactly these: no temporary file is left behind.
    assert_eq!(
        names,
        [
            "bed.png",
            "bed.svg",
            "contacts.csv",
            "particles.csv",
            "plot_coordination.png",
            "plot_coordination.svg",
            "plot_profile.png",
            "plot_profile.svg",
            "plot_regions.png",
            "plot_regions.svg",
            "summary.json",
            "wall_contacts.csv"
        ]
    );

    let particles = s.read("out/particles.csv");
    let mut lines = particles.lines();
    assert_eq!(lines.next(), Some("id,species,body,x,y,r"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() > 100, "{} particles", rows.len());
    for (id, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 6);
        assert_eq!(row[0] as usize, id);
        assert!(row.iter().all(|v| v.is_finite()));
        assert_eq!(row[5], 10.0);
    }
    assert!(s.read("out/contacts.csv").starts_with("i,j,gap\n"));
    let walls = s.read("out/wall_contacts.csv");
    assert!(walls.starts_with("i,wall,gap\n"));
    for l in walls.lines().skip(1) {
        let wall = l.split(',').nth(1).unwrap();
        assert!(["floor", "x0", "x1"].contains(&wall), "{l}");
    }

    let v = s.summary("out");
    assert_eq!(v["counts"]["particles"], rows.len() as u64);
    assert_eq!(v["dim"], 2);
    assert_eq!(v["seed"], 5);
    assert!(v["box"].get("depth").is_none(), "2D box has no depth");
}

#[test]
fn size_windows_are_shown_on_screen_and_in_the_summary() {
    let s = Scratch::new();
    let c = s.input(
        "sizes.toml",
        "dim = 2\nseed = 3\n[box]\nwidth = 400\nheight = 300\n[fill]\ncount = 40\n\
         [[species]]\nsize = { dist = \"lognormal\", median = 10, gsd = 2, min = 8, max = 12 }\n\
         [[species]]\nsize = { dist = \"lognormal\", median = 10, gsd = 2 }\n",
    );
    let o = s.ok(&["run", c.to_str().unwrap(), "--out", "w"]);
    let bounded = "r ~ lognormal(median 10, gsd 2) in [8, 12]";
    let default = "r ~ lognormal(median 10, gsd 2) in [1.25, 80] (±3 sd)";
    assert_contains(&o.stdout, &format!("{bounded}, ratio 1"));
    assert_contains(&o.stdout, &format!("{default}, ratio 1"));
    let v = s.summary("w");
    assert_eq!(v["species"][0]["size"], bounded);
    assert_eq!(v["species"][1]["size"], default);
    // The config as used keeps the bounds given, and only those.
    assert_eq!(v["config"]["species"][0]["size"]["min"], 8.0);
    assert_eq!(v["config"]["species"][0]["size"]["max"], 12.0);
    assert!(v["config"]["species"][1]["size"].get("max").is_none());
}

#[test]
fn bad_size_bounds_are_refused() {
    let s = Scratch::new();
    assert_config_refused(
        &s,
        "min.toml",
        "[[species]]\nsize = { dist = \"lognormal\", median = 10, gsd = 2, min = -1 }\n",
        &["min.toml", "species[0].size.min", "-1"],
    );
    assert_config_refused(
        &s,
        "tail.toml",
        "[[species]]\nsize = { dist = \"normal\", mean = 10, sd = 1, min = 20, max = 30 }\n",
        &["species[0].size", "[20, 30]", "holds only"],
    );
}

#[test]
fn summary_has_every_key_scripts_rely_on() {
    let s = Scratch::new();
    let o = s.ok(&["run", "--radii", "10,20", "--out", "out3", "--quiet"]);
    assert!(o.stdout.is_empty(), "--quiet: {}", o.stdout);
    let v = s.summary("out3");
    for key in packbed::SUMMARY_KEYS {
        assert!(v.pointer(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(v["dim"], 3);
    let g = v["packing"]["global"].as_f64().unwrap();
    assert!(g > 0.2 && g < 0.75, "global packing {g}");
    let placed: u64 = v["species"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["placed"].as_u64().unwrap())
        .sum();
    assert_eq!(placed, v["counts"]["bodies"].as_u64().unwrap());
    // The default box's bulk holds a handful of bodies: its measures are null,
    // with the reason, not numbers.
    assert!(v["packing"]["bulk"].is_null());
    assert!(v["packing"]["bulk_bodies"].as_u64().unwrap() < 50);
    assert!(v["packing"]["bulk_note"]
        .as_str()
        .unwrap()
        .contains("minimum"));
    assert_no_null(&v, "");
}

/// serde_json writes NaN as null: a null anywhere but at a bulk measure that
/// `packing.bulk_note` explains means a NaN got through.
fn assert_no_null(v: &Value, at: &str) {
    let bulk = at == ".packing.bulk"
        // g(r) is the bulk's; a bed whose surface has no flank has no heap.
        || at == ".packing.pair_correlation"
        || at == ".packing.heap"
        || at == ".coordination.mean_bulk"
        || (at.starts_with(".coordination.by_species[") && at.ends_with("].mean_bulk"))
        // The cake's bulk values are null with the bulk packing; Kozeny-Carman
        // is null for discs.
        || [
            ".cake.porosity",
            ".cake.d32",
            ".cake.specific_surface",
            ".cake.surface_per_bed_volume",
            ".cake.k_kozeny_carman",
            ".cake.whole.k_kozeny_carman",
        ]
        .contains(&at);
    match v {
        Value::Null if bulk => {}
        Value::Null => panic!("null (a NaN?) at {at}"),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .for_each(|(i, x)| assert_no_null(x, &format!("{at}[{i}]"))),
        Value::Object(o) => o
            .iter()
            .for_each(|(k, x)| assert_no_null(x, &format!("{at}.{k}"))),
        _ => {}
    }
}

#[test]
fn same_seed_gives_identical_files() {
    let s = Scratch::new();
    small_run(&s, "a", &["--quiet"]);
    small_run(&s, "b", &["--quiet"]);
    for f in ["particles.csv", "contacts.csv", "wall_contacts.csv"] {
        assert!(
            s.read(&format!("a/{f}")) == s.read(&format!("b/{f}")),
            "{f} differs between two runs with the same seed"
        );
    }
    small_run(&s, "c", &["--quiet", "--seed", "6"]);
    assert_ne!(s.read("a/particles.csv"), s.read("c/particles.csv"));
    let a = s.summary("a");
    let c = s.summary("c");
    assert_eq!(a["seed"], 5);
    assert_eq!(c["seed"], 6);
}

#[test]
fn default_run_needs_no_arguments() {
    let s = Scratch::new();
    let o = s.ok(&["run"]);
    assert_contains(&o.stdout, "3D");
    let v = s.summary("packbed-out");
    assert_eq!(v["dim"], 3);
    assert_eq!(v["seed"], 1);
    assert_eq!(v["config"]["box"]["preset"], "thesis");
    assert_eq!(v["box"]["width"], 240.0);
}

#[test]
fn overrides_reach_the_bed() {
    let s = Scratch::new();
    s.ok(&words(
        "run --dim 2 --radii 8 --box 200,150 --periodic --count 120 --seed 9 --out o --quiet",
    ));
    let v = s.summary("o");
    assert_eq!(v["counts"]["particles"], 120);
    assert_eq!(v["box"]["width"], 200.0);
    assert_eq!(v["box"]["height"], 150.0);
    assert_eq!(v["box"]["periodic"], true);
    assert_eq!(v["seed"], 9);
    assert_eq!(v["config"]["fill"]["count"], 120);
}

#[test]
fn bench_json_is_one_object_with_the_keys() {
    let s = Scratch::new();
    let o = s.ok(&["bench", "--dim", "2", "--n", "300", "--periodic", "--json"]);
    assert_eq!(o.stdout.lines().count(), 1, "{}", o.stdout);
    let v: Value = serde_json::from_str(&o.stdout).unwrap();
    for key in [
        "dim",
        "n",
        "seconds",
        "particles_per_second",
        "peak_rss_bytes",
    ] {
        assert!(v.get(key).is_some(), "bench --json lacks {key}: {v}");
    }
    assert_eq!(v["dim"], 2);
    assert_eq!(v["n"], 300);
    assert!(v["particles_per_second"].as_f64().unwrap() > 0.0);
    assert!(v["peak_rss_bytes"].as_u64().unwrap() > 0);
    assert!(s.entries().is_empty(), "bench writes no files");
}

#[test]
fn one_bed_is_the_same_on_any_number_of_threads() {
    let s = Scratch::new();
    let mut beds = Vec::new();
    for threads in ["1", "2", "3"] {
        let out = format!("t{threads}");
        s.ok_with(
            "RAYON_NUM_THREADS",
            threads,
            &words(&format!(
                "run --periodic --count 4000 --radii 10,20 --seed 5 --no-pictures --quiet --out {out}"
            )),
        );
        beds.push(s.bytes(&format!("{out}/particles.csv")));
        let b = s.ok_with(
            "RAYON_NUM_THREADS",
            threads,
            &words("bench --n 2000 --periodic --json"),
        );
        let v: Value = serde_json::from_str(&b.stdout).unwrap();
        assert_eq!(v["threads"].to_string(), threads, "{v}");
    }
    assert!(beds.windows(2).all(|w| w[0] == w[1]));
}

#[test]
fn bench_deposits_chains_and_counts_them() {
    let s = Scratch::new();
    let o = s.ok(&words("bench --dim 2 --chains 5 --n 40 --periodic --json"));
    let v: Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(v["bodies"], 40);
    assert_eq!(v["n"], 200);
    assert!(v["bodies_per_second"].as_f64().unwrap() > 0.0);
    assert!(v["redrops"].as_u64().is_some());
    let bad = s.packbed(&["bench", "--chains", "0"]);
    assert_eq!(bad.code, 2, "{}", bad.stderr);
}

#[test]
fn bench_times_every_analysis_stage_of_a_bed_file() {
    let s = Scratch::new();
    small_run(&s, "b", &["-q", "--no-pictures"]);
    let o = s.ok(&["bench", "--bed", "b/particles.csv", "--json"]);
    let v: Value = serde_json::from_str(&o.stdout).unwrap();
    let stages: Vec<&str> = v["analysis"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e[0].as_str().unwrap())
        .collect();
    for stage in [
        "contacts",
        "packing/global",
        "percolation/disjoint",
        "voids",
    ] {
        assert!(stages.contains(&stage), "no {stage} in {stages:?}");
    }
    assert!(v["analysis"]
        .as_array()
        .unwrap()
        .iter()
        .all(|e| e[1].as_f64().unwrap() >= 0.0));
    assert_eq!(v["n"], s.summary("b")["counts"]["particles"]);
    let missing = s.packbed(&["bench", "--bed", "none.csv"]);
    assert_eq!(missing.code, 2, "{}", missing.stderr);
}

/// `analyze` on the particles.csv that `run` wrote gives the same measures and
/// contact files (species names aside: a bed file does not carry them).
#[test]
fn analyze_reproduces_the_numbers_of_run() {
    let s = Scratch::new();
    for (dim, extra) in [("2", vec!["--periodic"]), ("3", vec![]), ("2", vec![])] {
        let mut args = vec!["run", "--dim", dim, "--count", "400", "--out", "r", "-q"];
        args.extend(extra.iter().copied());
        s.ok(&args);
        let o = s.ok(&["analyze", "r/particles.csv", "--out", "a"]);
        assert_contains(&o.stdout, "percolation");
        let run = s.summary("r");
        let ana = s.summary("a");
        for key in [
            "packing",
            "percolation",
            "voids",
            "segregation",
            "orientation",
        ] {
            assert_eq!(run.get(key), ana.get(key), "dim {dim} {extra:?}: {key}");
        }
        let mut run_box = run["box"].clone();
        run_box["source"] = "summary.json".into();
        assert_eq!(run_box, ana["box"], "dim {dim} {extra:?}");
        let strip = |v: &Value| {
            let mut c = v["coordination"].clone();
            for sp in c["by_species"].as_array_mut().unwrap() {
                sp["name"] = Value::Null;
            }
            c
        };
        assert_eq!(strip(&run), strip(&ana));
        for key in [
            "/coordination/histogram",
            "/coordination/by_species",
            "/packing/regions/floor",
            "/packing/profile",
            "/percolation/spans",
            "/percolation/spanning_clusters",
            "/percolation/shortest_chain",
            "/percolation/disjoint_chains",
            "/percolation/unique_chains",
        ] {
            assert!(ana.pointer(key).is_some(), "missing {key}");
        }
        assert_eq!(ana.pointer("/voids/count").is_some(), dim == "2");
        assert_eq!(s.read("r/contacts.csv"), s.read("a/contacts.csv"));
        assert_eq!(s.read("r/wall_contacts.csv"), s.read("a/wall_contacts.csv"));
        // A different threshold changes the large set.
        s.ok(&words("analyze r/particles.csv --out b --large 5 -q"));
        let b = s.summary("b");
        assert_eq!(b["percolation"]["large_bodies"], b["counts"]["bodies"]);
        for d in ["r", "a", "b"] {
            std::fs::remove_dir_all(s.work.join(d)).unwrap();
        }
    }
}

#[test]
fn analyze_refuses_bad_input() {
    let s = Scratch::new();
    let missing = s.inputs.join("none.csv");
    assert_user_error(&s, &["analyze", missing.to_str().unwrap()], &["none.csv"]);
    let bad = s.input("bad.csv", "x,y,r\n1,1,1\n2,oops,1\n");
    assert_user_error(
        &s,
        &["analyze", bad.to_str().unwrap(), "--box", "10,10"],
        &["bad.csv:3", "oops"],
    );
    let plain = s.input("plain.csv", "1 1 1\n3 1 1\n");
    let plain = plain.to_str().unwrap();
    assert_user_error(&s, &["analyze", plain], &["give the box"]);
    assert_user_error(
        &s,
        &["analyze", plain, "--box", "4,10", "--contact-tol", "-1"],
        &["--contact-tol"],
    );
    s.ok(&["analyze", plain, "--box", "4,10", "--out", "p", "-q"]);
    let v = s.summary("p");
    assert_eq!(v["percolation"]["shortest_chain"], 2);
    // Two corner voids and one between the discs on the floor.
    assert_eq!(v["voids"]["count"], 3);
}

#[test]
fn rsa_mode_runs_the_thesis_box_to_saturation() {
    let s = Scratch::new();
    let o = s.ok(&words("run --mode rsa --dim 2 --radii 10 --out rsa"));
    assert_contains(&o.stdout, "random sequential addition, saturated");
    let v = s.summary("rsa");
    assert_eq!(v["mode"], "rsa");
    assert_eq!(v["box"]["width"], 300.0);
    let n = v["counts"]["particles"].as_u64().unwrap();
    // A saturated RSA bed of the 2D thesis box holds about 150 discs, far fewer
    // than a deposited one (about 200).
    assert!((130..=170).contains(&n), "{n} particles");
    assert_eq!(v["counts"]["redrops"], 0);
    let phi = v["packing"]["global"].as_f64().unwrap();
    assert!((0.45..0.58).contains(&phi), "{phi}");
}

/// `analyze --export` writes the exports of the bed it read, and they read back
/// to the same measures.
#[test]
fn analyze_exports_round_trip() {
    let s = Scratch::new();
    s.ok(&["run", "--count", "300", "--out", "r", "-q"]);
    s.ok(&words(
        "analyze r/particles.csv --export vtk,dump,xyz --out a -q",
    ));
    let first = s.summary("a");
    for (file, out) in [("a/bed.dump", "d"), ("a/bed.xyz", "x"), ("a/bed.vtu", "v")] {
        s.ok(&["analyze", file, "--out", out, "-q", "--no-pictures"]);
        let again = s.summary(out);
        for key in ["/packing/global", "/packing/bulk", "/coordination/mean"] {
            assert_eq!(first.pointer(key), again.pointer(key), "{file}: {key}");
        }
        assert_eq!(
            s.read("a/contacts.csv"),
            s.read(&format!("{out}/contacts.csv"))
        );
    }
    // A bad export list is refused before any output.
    let bed = s.work.join("r/particles.csv");
    let bed = bed.to_str().unwrap();
    let fresh = Scratch::new();
    assert_user_error(
        &fresh,
        &["analyze", bed, "--export", "png", "--out", "z"],
        &["--export"],
    );
}

/// `run` draws the regional packing bars beside the other plots (a walled box
/// has all four regions); the PNG has the plot size.
#[test]
fn run_writes_the_regional_packing_plot() {
    let s = Scratch::new();
    s.ok(&["run", "--out", "r", "-q"]);
    let png = std::fs::read(s.work.join("r/plot_regions.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
    let height = u32::from_be_bytes([png[20], png[21], png[22], png[23]]);
    assert_eq!((width, height), (1000, 700));
    let svg = s.read("r/plot_regions.svg");
    for region in ["floor", "roof", "wall", "centre"] {
        assert!(svg.contains(region), "{region} missing from the SVG");
    }
}

/// A roof-miss count no run could reach is refused up front with its bound
/// (before, each miss cost a drop and such a run never ended).
#[test]
fn absurd_roof_misses_are_refused_with_the_bound() {
    let s = Scratch::new();
    for misses in ["1000000000000000", "1000000000000000000"] {
        let c = s.input(
            "misses.toml",
            &format!("dim = 2\n[box]\nwidth = 100\nheight = 40\n[fill]\nroof_misses = {misses}\n[[species]]\nradius = 10\n"),
        );
        let args = ["run", c.to_str().unwrap(), "--out", "m"];
        let o = s.within(&args, 60);
        assert_eq!(o.code, 2, "{}", o.stderr);
        assert_user_error(
            &s,
            &args,
            &["misses.toml", "fill.roof_misses", "at most", misses],
        );
    }
    // A sensible number still runs.
    let c = s.input(
        "ok.toml",
        "dim = 2\n[box]\nwidth = 100\nheight = 40\n[fill]\nroof_misses = 1000\n[[species]]\nradius = 10\n",
    );
    s.ok(&["run", c.to_str().unwrap(), "--out", "m", "--quiet"]);
}

/// `[analysis] chain_angle_from = "horizontal"` (and `analyze
/// --chain-angle-from`) give the source study's angles, and the outputs say so.
#[test]
fn chain_angles_from_the_horizontal_on_request() {
    let s = Scratch::new();
    let bed = "dim = 2\nseed = 3\n[box]\nwidth = 300\nheight = 200\n[fill]\ncount = 40\n\
               [[species]]\nradius = 10\nshape = \"chain\"\nbeads = 3\norientation = \"random\"\n";
    let h = s.input(
        "h.toml",
        &format!("{bed}[analysis]\nchain_angle_from = \"horizontal\"\n"),
    );
    let o = s.ok(&["run", h.to_str().unwrap(), "--out", "h"]);
    assert_contains(&o.stdout, "mean angle from horizontal");
    let v = s.input("v.toml", bed);
    s.ok(&["run", v.to_str().unwrap(), "--out", "v", "--quiet"]);
    let (h, v) = (s.summary("h"), s.summary("v"));
    assert_eq!(h["orientation"]["angle_from"], "horizontal");
    assert_eq!(v["orientation"]["angle_from"], "vertical");
    let mean = |j: &Value| j["orientation"]["mean_angle"].as_f64().unwrap();
    assert!(
        (mean(&h) - (90.0 - mean(&v))).abs() < 1e-9,
        "{} {}",
        mean(&h),
        mean(&v)
    );
    assert_eq!(h["orientation"]["histogram"]["lo"], 0.0);
    assert_eq!(v["orientation"]["histogram"]["lo"], -90.0);
    assert_eq!(h["config"]["analysis"]["chain_angle_from"], "horizontal");
    let texts = crate::common::svg_texts(&s.read("h/plot_chain_angles.svg"));
    assert!(
        texts.iter().any(|t| t.contains("from horizontal")),
        "{texts:?}"
    );
    let texts = crate::common::svg_texts(&s.read("v/plot_chain_angles.svg"));
    assert!(
        texts.iter().any(|t| t.contains("from vertical")),
        "{texts:?}"
    );
    // analyze gives the same numbers on the file, in either convention.
    s.ok(&words(
        "analyze v/particles.csv --chain-angle-from horizontal --out a --quiet",
    ));
    let a = s.summary("a");
    assert_eq!(a["orientation"]["angle_from"], "horizontal");
    assert_eq!(a["settings"]["chain_angle_from"], "horizontal");
    assert_eq!(a["orientation"]["histogram"], h["orientation"]["histogram"]);
    let bad = s.input(
        "bad.toml",
        &format!("{bed}[analysis]\nchain_angle_from = \"diagonal\"\n"),
    );
    assert_user_error(
        &s,
        &["run", bad.to_str().unwrap()],
        &["bad.toml", "diagonal", "horizontal"],
    );
}

// ---- the screen summary and the shape of errors ---------------------------

/// The names in the `files in DIR: …` line of a summary.
fn listed(stdout: &str) -> Vec<String> {
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("files in "))
        .unwrap_or_else(|| panic!("no files line in {stdout}"));
    let (_, names) = line.split_once(": ").unwrap();
    names
        .split(", ")
        .map(|n| n.trim().trim_end_matches('/').to_string())
        .collect()
}

/// Every file in `dir`, sorted.
fn files_in(s: &Scratch, dir: &str) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(s.path(dir))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn screen_summaries_list_every_file_written() {
    let s = Scratch::new();
    let o = s.ok(&words("run --dim 2 --radii 10 --box diameters=6 --out r"));
    let mut names = listed(&o.stdout);
    names.sort();
    assert_eq!(names, files_in(&s, "r"), "{}", o.stdout);
    assert!(names.iter().any(|n| n == "bed.png"), "{names:?}");
    let o = s.ok(&words("analyze r/particles.csv --out a --export xyz"));
    let mut names = listed(&o.stdout);
    names.sort();
    assert_eq!(names, files_in(&s, "a"), "{}", o.stdout);
    let o = s.ok(&words(
        "ensemble --dim 2 --radii 10 --box diameters=6 --runs 2 --out e",
    ));
    let mut names = listed(&o.stdout);
    names.sort();
    assert_eq!(names, files_in(&s, "e"), "{}", o.stdout);
    assert!(names.iter().any(|n| n == "plot_packing.png"), "{names:?}");
}

/// `text` holds `phrase` as a count of its own (not the end of `11 clusters`).
fn says(text: &str, phrase: &str) -> bool {
    text.match_indices(phrase).any(|(i, _)| {
        !text[..i].ends_with(|c: char| c.is_ascii_digit())
            && !text[i + phrase.len()..].starts_with(|c: char| c.is_alphanumeric())
    })
}

#[test]
fn screen_summary_counts_in_the_singular_and_by_name() {
    let s = Scratch::new();
    // Seven discs in a box of 3.33 diameters: one roof overflow (the fill
    // stops at the first), one cluster, one spanning cluster, one disjoint chain.
    let first_miss = s.input("first-miss.toml", "[fill]\nroof_misses = 0\n");
    let first_miss = first_miss.to_str().unwrap();
    let args = words("--dim 2 --radii 10 --box diameters=3.3333333 --out one");
    let o = s.ok(&[&["run", first_miss][..], &args].concat());
    for bad in [
        "1 roof overflows",
        "1 clusters",
        "1 spanning clusters",
        "1 vertex-disjoint chains",
    ] {
        assert!(!says(&o.stdout, bad), "`{bad}` in\n{}", o.stdout);
    }
    for good in [
        "1 roof overflow",
        "1 cluster",
        "1 spanning cluster",
        "1 vertex-disjoint chain",
    ] {
        assert!(says(&o.stdout, good), "`{good}` not in\n{}", o.stdout);
    }
    // Box sizes without float noise on screen; summary.json keeps every digit.
    assert_contains(&o.stdout, "66.6667 × 66.6667 box");
    assert_eq!(s.summary("one")["box"]["width"], 66.666666);

    // Segregation by species name; the base layer of chains in bodies.
    let c = s.input(
        "named.toml",
        "dim = 2\nseed = 2\n[box]\nwidth = 400\nheight = 300\n[fill]\ncount = 30\n\
         [[species]]\nname = \"coarse\"\nradius = 20\nshape = \"chain\"\nbeads = 3\n\
         [[species]]\nname = \"fine\"\nradius = 10\nshape = \"chain\"\nbeads = 3\n",
    );
    let o = s.ok(&["run", c.to_str().unwrap(), "--out", "named"]);
    let seg = o
        .stdout
        .lines()
        .find(|l| l.contains("segregation"))
        .unwrap();
    assert!(seg.contains("coarse ") && seg.contains("fine "), "{seg}");
    assert!(!seg.contains("species 0"), "{seg}");
    let j = s.summary("named");
    let bodies = j["counts"]["bodies"].as_u64().unwrap();
    let dropped = j["counts"]["dropped"].as_u64().unwrap();
    let line = o
        .stdout
        .lines()
        .find(|l| l.trim_start().starts_with("particles:"))
        .unwrap();
    let base: u64 = line
        .split_once('(')
        .unwrap()
        .1
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(base > 0, "{line}");
    assert_eq!(base + dropped, bodies, "{line}");
    assert!(line.contains(&format!("{bodies} bodies")), "{line}");
}

/// Errors with a place in a file read `packbed: error: FILE:LINE: what`,
/// whatever wraps them.
#[test]
fn errors_with_a_line_lead_with_file_and_line() {
    let s = Scratch::new();
    let c = s.input(
        "typo.toml",
        "dim = 2\n[[species]]\nradius = 10\nradiu = 3\n",
    );
    let typo = c.to_str().unwrap().to_string();
    assert_user_error(&s, &["run", &typo], &["radiu"]);
    assert_user_error(&s, &["ensemble", &typo, "--runs", "2"], &["radiu"]);
    s.input("table.csv", "radius,number\n10,1\nx,2\n");
    let p = s.input(
        "psd.toml",
        "dim = 2\n[[species]]\nsize = { table = \"table.csv\" }\n",
    );
    let table = s.inputs.join("table.csv").to_str().unwrap().to_string();
    assert_user_error(&s, &["run", p.to_str().unwrap()], &["psd.toml"]);
    let bed = s.input("bed.txt", "1 2 1\n3 4 x\n");
    let bed = bed.to_str().unwrap().to_string();
    for (args, place) in [
        (vec!["run", typo.as_str()], format!("{typo}:4: ")),
        (
            vec!["ensemble", typo.as_str(), "--runs", "2"],
            format!("{typo}:4: "),
        ),
        (vec!["run", p.to_str().unwrap()], format!("{table}:3: ")),
        (
            vec!["analyze", bed.as_str(), "--box", "10,10"],
            format!("{bed}:2: "),
        ),
        (
            vec!["render", bed.as_str(), "--box", "10,10"],
            format!("{bed}:2: "),
        ),
    ] {
        let o = s.packbed(&args);
        assert_eq!(o.code, 2, "{args:?}");
        assert!(
            o.stderr.starts_with(&format!("packbed: error: {place}")),
            "{args:?}: {}",
            o.stderr
        );
    }
}

// ---- measures chosen by the user -----------------------------------------

/// `--measures` computes only the measures named; the summary leaves the
/// others out and says so, the same on `run`, `analyze` and `ensemble`, and the
/// measures kept are equal to those of a full run.
#[test]
fn chosen_measures_leave_the_others_out_and_say_so() {
    let s = Scratch::new();
    let dem = words("run --dim 2 --radii 10 --seed 3 --no-pictures");
    let full: Vec<&str> = dem.iter().copied().chain(["--out", "full"]).collect();
    s.ok(&full);
    let args: Vec<&str> = dem
        .iter()
        .copied()
        .chain(["--measures", "packing,coordination", "--out", "some"])
        .collect();
    let o = s.ok(&args);
    assert_contains(
        &o.stdout,
        "left out: percolation, voids, orientation, segregation",
    );
    let (all, some) = (s.summary("full"), s.summary("some"));
    for gone in ["percolation", "voids", "segregation"] {
        assert!(
            all.get(gone).is_some() && some.get(gone).is_none(),
            "{gone}"
        );
    }
    assert_eq!(all["packing"], some["packing"]);
    assert_eq!(all["coordination"], some["coordination"]);
    assert!(all.get("measures_left_out").is_none());
    assert_eq!(
        some["measures_left_out"],
        serde_json::json!(["percolation", "voids", "orientation", "segregation"])
    );
    // The contacts are always found and written.
    assert_eq!(s.read("full/contacts.csv"), s.read("some/contacts.csv"));

    let o = s.ok(&words(
        "analyze full/particles.csv --measures percolation --out a --no-pictures",
    ));
    assert_contains(&o.stdout, "percolation (r >=");
    let a = s.summary("a");
    assert_eq!(a["percolation"], all["percolation"]);
    assert!(a.get("packing").is_none() && a.get("coordination").is_none());

    s.ok(&words(
        "ensemble --dim 2 --radii 10 --runs 2 --measures packing --no-pictures --out e",
    ));
    let table = s.read("e/ensemble.csv");
    assert!(table.contains("packing.global"), "{table}");
    assert!(!table.contains("coordination.mean"), "{table}");
    assert!(!table.contains("percolation."), "{table}");

    // Porosity is part of the cake properties, not a measure of its own.
    assert_user_error(
        &s,
        &["run", "--measures", "packing,porosity"],
        &["--measures", "porosity", "pores", "permeability"],
    );
}

/// A medium feed and a slurry feed in SI, ready for a `[filtration]` table.
const FILTER: &str =
    "[[species]]\nname = \"sand\"\nradius = 30\n[[species]]\nname = \"flour\"\nradius = 10\n\
                      [[feeds]]\nspecies = [\"sand\"]\ncount = 30\nmedium = true\n\
                      [[feeds]]\nspecies = [\"flour\"]\ncount = 300\n\
                      [analysis]\nlength_unit = \"um\"\nsolid_density = 2650\n[filtration]\n";

#[test]
fn settling_rules_run_and_bad_ones_are_refused() {
    let s = Scratch::new();
    let c = s.input(
        "loose.toml",
        "dim = 2\n[box]\nwidth = 200\nheight = 400\n[fill]\ncount = 300\n\
         [[species]]\nradius = 5\n[settling]\nfriction_angle = 30\nsticking = 0.2\n",
    );
    s.ok(&["run", c.to_str().unwrap(), "--out", "loose", "--quiet"]);
    let v = s.summary("loose");
    assert_eq!(v["config"]["settling"]["friction_angle"], 30.0);
    assert_eq!(v["config"]["settling"]["sticking"], 0.2);
    // Momentum settles rigid chains too (2D and 3D).
    for (name, dim, size) in [("rods2", 2, ""), ("rods3", 3, "depth = 100\n")] {
        let c = s.input(
            &format!("{name}.toml"),
            &format!(
                "dim = {dim}\n[box]\nwidth = 100\n{size}height = 400\n[fill]\ncount = 150\n\
                 [[species]]\nradius = 5\nshape = \"chain\"\nbeads = 3\n\
                 [settling]\nrestitution = 0.5\ndrop_height = 20\n"
            ),
        );
        s.ok(&["run", c.to_str().unwrap(), "--out", name, "--quiet"]);
        let v = s.summary(name);
        assert_eq!(v["config"]["settling"]["restitution"], 0.5, "{name}");
        assert_eq!(v["config"]["species"][0]["beads"], 3, "{name}");
    }
    for (name, text, needles) in [
        (
            "k.toml",
            "[settling]\ncontacts = 4\n",
            &["settling.contacts", "4"][..],
        ),
        (
            "p.toml",
            "[settling]\nsticking = 1.5\n",
            &["settling.sticking", "1.5"][..],
        ),
        (
            "a.toml",
            "[settling]\nfriction_angle = 90\n",
            &["settling.friction_angle", "90"][..],
        ),
        (
            "e.toml",
            "[settling]\nrestitution = 1\n",
            &["settling.restitution", "1"][..],
        ),
        (
            "climb.toml",
            "[settling]\nclimb_over = true\n",
            &["settling.climb_over", "restitution"][..],
        ),
        (
            "n.toml",
            "[settling]\ncohesion_diameter = 5\ncohesion_exponent = -1\n",
            &["settling.cohesion_exponent", "-1"][..],
        ),
        (
            "r.toml",
            "[settling]\nrule = \"glue\"\n",
            &["r.toml", "rule"][..],
        ),
        (
            "rsa.toml",
            "mode = \"rsa\"\n[settling]\ncontacts = 1\n",
            &["[settling]", "rsa"][..],
        ),
        (
            "f.toml",
            "[feed]\npattern = \"spiral\"\n",
            &["f.toml", "spiral"][..],
        ),
        (
            "at.toml",
            "[box]\nwidth = 100\ndepth = 100\nheight = 100\n[feed]\npattern = \"point\"\nat = [150, 50]\n",
            &["feed.at[0]", "150"][..],
        ),
        (
            "feeds.toml",
            "[[species]]\nname = \"a\"\nradius = 10\n[[feeds]]\nspecies = [\"sand\"]\ncount = 3\n",
            &["feeds[0].species", "sand"][..],
        ),
        (
            "filter-p.toml",
            &format!("{FILTER}pressure = 0\nconcentration = 50\n"),
            &["filtration.pressure", "0"][..],
        ),
        (
            "filter-c.toml",
            &format!("{FILTER}pressure = 1e5\nconcentration = -5\n"),
            &["filtration.concentration", "-5"][..],
        ),
        (
            "filter-medium.toml",
            &format!("{FILTER}pressure = 1e5\nconcentration = 50\n")
                .replace("medium = true\n", ""),
            &["[filtration]", "medium = true"][..],
        ),
        (
            "mesh-closed.toml",
            "[box]\nwidth = 20\ndepth = 20\nheight = 400\nperiodic = true\n[[species]]\nname = \"a\"\nradius = 1\n\
             [[feeds]]\nmesh = { wire_diameter = 2, aperture = 0 }\n[[feeds]]\nspecies = [\"a\"]\ncount = 3\n",
            &["feeds[0].mesh.aperture", "no opening"][..],
        ),
        (
            "medium-last.toml",
            "[[species]]\nname = \"a\"\nradius = 10\n[[feeds]]\nspecies = [\"a\"]\ncount = 3\nmedium = true\n",
            &["every feed is a medium"][..],
        ),
    ] {
        assert_config_refused(&s, name, text, needles);
    }
}
