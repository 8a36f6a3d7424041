//! `--measures agglomeration` through the command: the dried cake's solid
//! bridges and agglomerates, and its refusals.

use crate::common::{assert_config_refused, assert_user_error, Scratch};

fn config(extra: &str) -> String {
    format!(
        "dim = 3\nseed = 1\n[box]\nwidth = 10\ndepth = 10\nheight = 60\nperiodic = true\n\
         [fill]\ncount = 800\n[[species]]\nradius = 1\n\
         [analysis]\nmeasures = [\"packing\", \"agglomeration\"]\nlength_unit = \"um\"\n{extra}"
    )
}

#[test]
fn agglomeration_writes_its_bridges_and_agglomerates() {
    let s = Scratch::new();
    let saturated = s.input("sat.toml", &config(""));
    let o = s.ok(&[
        "run",
        saturated.to_str().unwrap(),
        "--out",
        "sat",
        "--no-pictures",
    ]);
    let screen = format!("{}{}", o.stdout, o.stderr);
    assert!(
        screen.contains("agglomeration: dried at 50 kg/m³"),
        "{screen}"
    );
    let a = &s.summary("sat")["agglomeration"];
    // The solid dissolved in the liquid left is all placed.
    let solid = a["solid_volume"].as_f64().unwrap();
    let placed = a["solid_at_pairs"].as_f64().unwrap() + a["solid_on_surfaces"].as_f64().unwrap();
    assert!(solid > 0.0 && (placed - solid).abs() < 1e-9 * solid);
    let bridges = s.read("sat/bridges.csv");
    assert!(bridges.starts_with(
        "particle_a,particle_b,sx,sy,gap,liquid,solid,neck_radius,bond,strength_n,agglomerate,\
         broken_at_pa,agglomerate_after\n"
    ));
    let bonds = bridges
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(8) == Some("1"))
        .count() as u64;
    assert_eq!(bonds, a["bonds"].as_u64().unwrap());
    let groups = s.read("sat/agglomerates.csv");
    assert_eq!(
        groups.lines().count() as u64 - 1,
        a["agglomerates"].as_u64().unwrap()
    );
    // A washed cake (its liquid a tenth of the solubility) bonds more
    // weakly than the saturated mother liquor.
    let washed = s.input(
        "washed.toml",
        &config("[analysis.drying]\nconcentration = 5\nsolubility = 50\n"),
    );
    s.ok(&[
        "run",
        washed.to_str().unwrap(),
        "--out",
        "washed",
        "--no-pictures",
    ]);
    let w = &s.summary("washed")["agglomeration"];
    let strength = |x: &serde_json::Value| x["mean_bond_strength"].as_f64().unwrap();
    assert!(strength(w) < strength(a), "{w} against {a}");
    // Nothing dissolved: nothing bonds.
    let clean = s.input(
        "clean.toml",
        &config("[analysis.drying]\nconcentration = 0\n"),
    );
    s.ok(&[
        "run",
        clean.to_str().unwrap(),
        "--out",
        "clean",
        "--no-pictures",
    ]);
    assert_eq!(s.summary("clean")["agglomeration"]["agglomerates"], 0);
}

#[test]
fn agglomeration_bad_input() {
    let s = Scratch::new();
    let bad = [
        (
            "[analysis.drying]\nconcentration = 60\nsolubility = 50\n",
            "above the solubility",
        ),
        ("[analysis.drying]\nconcentration = -1\n", "concentration"),
        (
            "[analysis.drying]\ncrystal_density = 0\n",
            "crystal_density",
        ),
        ("[analysis.drying]\nbinder = 3\n", "binder"),
    ];
    for (k, (extra, needle)) in bad.iter().enumerate() {
        assert_config_refused(&s, &format!("bad{k}.toml"), &config(extra), &[needle]);
    }
}

#[test]
fn analyze_dries_a_given_bed_with_the_settings_of_a_config() {
    let s = Scratch::new();
    let washed = s.input(
        "washed.toml",
        &config("[analysis.drying]\nconcentration = 5\nsolubility = 50\n"),
    );
    let washed = washed.to_str().unwrap();
    s.ok(&["run", washed, "--out", "r", "--no-pictures", "-q"]);
    // The bed the run built, analysed with the run's [analysis]: the same
    // agglomeration, at the washed concentration.
    s.ok(&[
        "analyze",
        "r/particles.csv",
        "--config",
        washed,
        "--out",
        "a",
        "-q",
    ]);
    let a = &s.summary("a")["agglomeration"];
    assert_eq!(a["concentration"], 5.0);
    assert_eq!(a, &s.summary("r")["agglomeration"]);
    // Without the config, the default liquid (saturated at 50 kg/m³).
    s.ok(&[
        "analyze",
        "r/particles.csv",
        "--measures",
        "agglomeration",
        "--length-unit",
        "um",
        "--out",
        "d",
        "-q",
    ]);
    assert_eq!(s.summary("d")["agglomeration"]["concentration"], 50.0);
    // An option given wins over the file: no agglomeration asked for.
    s.ok(&[
        "analyze",
        "r/particles.csv",
        "--config",
        washed,
        "--measures",
        "packing",
        "--out",
        "p",
        "-q",
    ]);
    assert!(s.summary("p").get("agglomeration").is_none());
    // Bad files and settings: one line, exit 2, named where they are.
    let over = s.input(
        "over.toml",
        "[analysis]\nmeasures = [\"agglomeration\"]\n[analysis.drying]\nconcentration = 60\nsolubility = 50\n",
    );
    let negative = s.input("negative.toml", "[analysis]\nlarge_radius = -1\n");
    let unknown = s.input("unknown.toml", "[analysis.drying]\nbinder = 3\n");
    let bed = "r/particles.csv";
    for (args, needles) in [
        (
            vec!["--config", over.to_str().unwrap()],
            vec![
                "over.toml: analysis.drying: the concentration 60",
                "above the solubility",
            ],
        ),
        (
            vec!["--config", negative.to_str().unwrap()],
            vec!["negative.toml: analysis.large_radius must be"],
        ),
        (
            vec!["--config", negative.to_str().unwrap(), "--large", "-2"],
            vec!["--large"],
        ),
        (
            vec!["--config", unknown.to_str().unwrap()],
            vec!["unknown.toml", "binder"],
        ),
        (
            vec!["--config", "missing.toml"],
            vec!["--config", "missing.toml"],
        ),
    ] {
        let mut all = vec!["analyze", bed, "--out", "bad"];
        all.extend(args);
        assert_user_error(&s, &all, &needles);
    }
}

/// `[analysis.drying.agitation]` through the command: the agitated product
/// in the summary, the broken bridges and the agglomerates after it in
/// `bridges.csv`, the picture coloured by agglomerate after it, and the
/// same agitation from `analyze --config` of the run's bed.
#[test]
fn agitation_breaks_bridges_and_writes_the_product_after_it() {
    let s = Scratch::new();
    let text = config(
        "[analysis.drying]\nconcentration = 0.5\nsolubility = 50\n\
         [analysis.drying.agitation]\nstress = 1e4\n",
    );
    let path = s.input("agitated.toml", &text);
    let path = path.to_str().unwrap();
    s.ok(&["run", path, "--out", "r", "-q"]);
    let a = &s.summary("r")["agglomeration"];
    let g = &a["agitation"];
    let broken = g["broken"].as_u64().unwrap();
    assert!(broken > 0, "{g}");
    assert!(g["agglomerates"].is_u64() && g["first_break_stress"].as_f64().unwrap() > 0.0);
    // After ⊆ before: no more particles in agglomerates than before.
    assert!(
        g["fraction_in_agglomerates"].as_f64().unwrap()
            <= a["fraction_in_agglomerates"].as_f64().unwrap()
    );
    let bridges = s.read("r/bridges.csv");
    let rows: Vec<Vec<&str>> = bridges
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let marked = rows.iter().filter(|r| !r[11].is_empty()).count() as u64;
    assert_eq!(marked, broken);
    for r in rows.iter().filter(|r| !r[11].is_empty()) {
        let at: f64 = r[11].parse().unwrap();
        assert!(r[8] == "1" && at > 0.0 && at <= 1e4, "{r:?}");
        assert_eq!(r[12], "0");
    }
    assert!(s.path("r/agglomerates_agitated.png").exists());
    assert!(s.path("r/agglomerates.png").exists());
    s.ok(&[
        "analyze",
        "r/particles.csv",
        "--config",
        path,
        "--out",
        "a",
        "-q",
    ]);
    assert_eq!(&s.summary("a")["agglomeration"], a);
}
