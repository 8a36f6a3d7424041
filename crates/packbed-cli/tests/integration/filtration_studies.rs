//! Filtrations in ensembles, sweeps and `packbed compare`: the figures a
//! filtration study reads (α and R_m fitted and of the network, Ruth's
//! departure, where the curve ended, what passed, lodged and built the cake)
//! reach the ensemble's and the sweep's tables with their units, a sweep over
//! pressures or over the medium gives them per value, and a comparison of the
//! same filtration measured in µm and in mm puts them side by side in one unit.

use crate::common::Scratch;
use serde_json::Value;

/// A small filtration (about 0.4 s a bed): a precoat of `medium` spheres of
/// median diameter 60 µm (in `unit`, `um` or `mm`), 1,500 bouncing slurry
/// particles of median diameter 16 µm, 1 bar, 6 checkpoints; `extra` is
/// appended (a `[sweep]`).
pub fn small_filtration(unit: &str, medium: u64, extra: &str) -> String {
    let k = if unit == "mm" { 1e-3 } else { 1.0 };
    format!(
        "dim = 3\nseed = 3\n[box]\nwidth = {w}\ndepth = {w}\nheight = {h}\nperiodic = true\n\
         [fill]\nbase_layer = \"none\"\n\
         [[species]]\nname = \"precoat\"\nsize = {{ dist = \"lognormal\", median = {m}, gsd = 1.05 }}\n\
         [[species]]\nname = \"slurry\"\nsize = {{ dist = \"lognormal\", median = {s}, gsd = 1.3 }}\n\
         [[feeds]]\nspecies = [\"precoat\"]\ncount = {medium}\nmedium = true\n\
         settling = {{ restitution = 0.5 }}\n\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = 1500\nsettling = {{ restitution = 0.5 }}\n\
         [analysis]\nmeasures = [\"packing\"]\nlength_unit = \"{unit}\"\nsolid_density = 2650\n\
         [filtration]\npressure = 1e5\nconcentration = 100\ncheckpoints = 6\n{extra}",
        w = 150.0 * k,
        h = 20000.0 * k,
        m = 30.0 * k,
        s = 8.0 * k,
    )
}

/// The figures every table must carry, with their units.
const FIGURES: [(&str, &str); 14] = [
    ("filtration.alpha_fit_m_per_kg", "m/kg"),
    ("filtration.alpha_network_m_per_kg", "m/kg"),
    ("filtration.r_medium_fit_per_m", "1/m"),
    ("filtration.r_medium_clogged_per_m", "1/m"),
    ("filtration.r_medium_per_m", "1/m"),
    ("filtration.ruth_departure", "1"),
    ("filtration.final.time_s", "s"),
    ("filtration.final.volume_m3_per_m2", "m³/m²"),
    ("filtration.final.cake_height_m", "m"),
    ("filtration.final.mass_kg_per_m2", "kg/m²"),
    ("capture.passed_fraction", "1"),
    ("capture.lodged_fraction", "1"),
    ("capture.cake_fraction", "1"),
    ("capture.lodged", "bodies"),
];

/// The mean of `name` in an `ensemble.json`.
fn mean(json: &Value, name: &str) -> f64 {
    json["measures"][name]["mean"]
        .as_f64()
        .unwrap_or_else(|| panic!("no {name} in ensemble.json"))
}

#[test]
fn an_ensemble_of_filtrations_tables_their_figures_with_units() {
    let s = Scratch::new();
    let cfg = s.input("f.toml", &small_filtration("um", 80, ""));
    let o = s.ok(&[
        "ensemble",
        cfg.to_str().unwrap(),
        "--runs",
        "3",
        "--out",
        "e",
    ]);
    // On screen: α and R_m fitted, the time at the end, what passed.
    for key in [
        "filtration.alpha_fit_m_per_kg",
        "filtration.r_medium_fit_per_m",
        "filtration.final.time_s",
        "capture.passed_fraction",
    ] {
        assert!(o.stdout.contains(key), "{key} not on screen:\n{}", o.stdout);
    }
    let json: Value = serde_json::from_str(&s.read("e/ensemble.json")).unwrap();
    let md = s.read("e/ensemble.md");
    let csv = s.read("e/ensemble.csv");
    let filtration = md
        .split("## Filtration")
        .nth(1)
        .and_then(|t| t.split("## All measures").next())
        .unwrap_or_else(|| panic!("no Filtration section in\n{md}"));
    for (key, unit) in FIGURES {
        let m = &json["measures"][key];
        assert_eq!(m["n"], 3, "{key}: {m}");
        assert_eq!(m["unit"], unit, "{key}: {m}");
        assert!(csv.contains(&format!("\n{key},3,")), "{key} not in\n{csv}");
        let row = filtration
            .lines()
            .find(|l| l.contains(&format!("| {key} |")))
            .unwrap_or_else(|| panic!("{key} not in\n{filtration}"));
        assert!(row.contains(&format!("| {unit} | {key} |")), "{row}");
        // Each once: not repeated under all measures.
        assert_eq!(md.matches(&format!("| {key} |")).count(), 1, "{key}");
    }
    // The statistics are the replicates' own figures.
    let alpha: Vec<f64> = (0..3)
        .map(|i| {
            let run: Value =
                serde_json::from_str(&s.read(&format!("e/runs/{i:04}/summary.json"))).unwrap();
            let f = &run["filtration"];
            // `final` is the last checkpoint.
            let last = f["checkpoints"].as_array().unwrap().last().unwrap();
            assert_eq!(f["final"]["time_s"], last["time_s"]);
            let c = &run["capture"];
            let fed = c["fed"].as_f64().unwrap();
            assert_eq!(
                c["passed_fraction"].as_f64().unwrap(),
                c["passed"].as_f64().unwrap() / fed
            );
            f["alpha_fit_m_per_kg"].as_f64().unwrap()
        })
        .collect();
    let want = alpha.iter().sum::<f64>() / 3.0;
    let got = mean(&json, "filtration.alpha_fit_m_per_kg");
    assert!((got / want - 1.0).abs() < 1e-12, "{got} {want}");
    eprintln!("filtration ensemble: α fit {alpha:?} m/kg, mean {got:e}");
    // The curves go to ensemble.csv, not one row per checkpoint in the table;
    // the filtration's wall time is no measure of the bed.
    assert!(csv.contains("\nfiltration.checkpoints[6].r_total_per_m,3,"));
    assert!(!md.contains("| filtration.checkpoints["), "{md}");
    assert!(!csv.contains("filtration.seconds"), "{csv}");
    // A rerun: the same bytes (no wall time leaks into the statistics).
    s.ok(&[
        "ensemble",
        cfg.to_str().unwrap(),
        "--runs",
        "3",
        "--out",
        "e2",
        "-q",
    ]);
    for f in ["ensemble.json", "ensemble.csv", "ensemble.md"] {
        assert_eq!(
            s.bytes(&format!("e/{f}")),
            s.bytes(&format!("e2/{f}")),
            "{f}"
        );
    }
}

/// The mean of `name` for each value of a sweep, from `sweep.csv`.
fn per_value(csv: &str, name: &str) -> Vec<f64> {
    csv.lines()
        .filter(|l| l.split(',').nth(2) == Some(name))
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn a_sweep_over_pressures_scales_the_time_and_keeps_the_cake() {
    let s = Scratch::new();
    let sweep = "[sweep]\nparameter = \"filtration.pressure\"\nvalues = [1e5, 2e5]\n";
    let cfg = s.input("p.toml", &small_filtration("um", 80, sweep));
    s.ok(&[
        "ensemble",
        cfg.to_str().unwrap(),
        "--runs",
        "2",
        "--out",
        "p",
        "-q",
    ]);
    let csv = s.read("p/sweep.csv");
    let md = s.read("p/sweep.md");
    for (key, unit) in FIGURES {
        assert_eq!(per_value(&csv, key).len(), 2, "{key} in\n{csv}");
        assert!(md.contains(&format!("## {key} ({unit})")), "{key} in\n{md}");
    }
    // The same beds: the same cake and medium, whatever the pressure.
    for key in [
        "filtration.alpha_network_m_per_kg",
        "filtration.r_medium_clogged_per_m",
        "filtration.final.volume_m3_per_m2",
    ] {
        let v = per_value(&csv, key);
        assert!((v[1] / v[0] - 1.0).abs() < 1e-12, "{key}: {v:?}");
    }
    // At constant pressure t = μ/Δp ∫ R dV: twice the pressure, half the time.
    let t = per_value(&csv, "filtration.final.time_s");
    assert!((t[1] / t[0] - 0.5).abs() < 1e-9, "{t:?}");
    let p = per_value(&csv, "filtration.final.pressure_pa");
    assert_eq!(p, [1e5, 2e5]);
    eprintln!("pressure sweep: final time {t:?} s");
    // The headline table leads with them, units in its header.
    let head = md
        .lines()
        .find(|l| l.starts_with("| filtration.pressure |"))
        .unwrap();
    assert!(
        head.contains("| filtration.alpha_fit_m_per_kg (m/kg) |")
            && head.contains("| filtration.final.time_s (s) |")
            && head.contains("| capture.passed_fraction (1) |"),
        "{head}"
    );
    assert!(md.contains("Per checkpoint and per size class"), "{md}");
    for plot in [
        "plot_sweep_alpha",
        "plot_sweep_medium_resistance",
        "plot_sweep_filtration_time",
    ] {
        assert!(s.path(&format!("p/{plot}.png")).exists(), "{plot}");
    }
    assert!(!md.contains("## filtration.checkpoints["), "{md}");
    // A sweep over a config without a filtration is refused by name.
    let bare = s.input(
        "bare.toml",
        "dim = 3\n[box]\nwidth = 8\ndepth = 8\nheight = 40\n[fill]\ncount = 20\n\
         [sweep]\nparameter = \"filtration.pressure\"\nvalues = [1e5]\n",
    );
    let o = s.packbed(&[
        "ensemble",
        bare.to_str().unwrap(),
        "--runs",
        "1",
        "--out",
        "b",
    ]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("no [filtration] table"), "{}", o.stderr);
}

#[test]
fn sweeps_over_the_medium_change_its_resistance() {
    let s = Scratch::new();
    // The medium's depth (its feed's count) and its grains' size.
    for (name, sweep) in [
        (
            "depth",
            "[sweep]\nparameter = \"feeds[0].count\"\nvalues = [60, 120]\n",
        ),
        (
            "grain",
            "[sweep]\nparameter = \"species[0].size.median\"\nvalues = [25, 35]\n",
        ),
    ] {
        let cfg = s.input(&format!("{name}.toml"), &small_filtration("um", 80, sweep));
        s.ok(&[
            "ensemble",
            cfg.to_str().unwrap(),
            "--runs",
            "2",
            "--out",
            name,
            "-q",
        ]);
        let csv = s.read(&format!("{name}/sweep.csv"));
        for (key, _) in FIGURES {
            assert_eq!(per_value(&csv, key).len(), 2, "{name}: {key} in\n{csv}");
        }
        // A deeper medium, or one of coarser grains at the same count (a
        // thicker layer: R ∝ depth / d² ∝ count · d), resists more.
        let r = per_value(&csv, "filtration.r_medium_per_m");
        assert!(r[1] > 1.5 * r[0], "{name}: clean medium R_m {r:?}");
        let bodies = per_value(&csv, "capture.medium_bodies");
        eprintln!("{name} sweep: clean R_m {r:?} 1/m, medium bodies {bodies:?}");
        if name == "depth" {
            assert_eq!(bodies, [60.0, 120.0]);
        }
    }
    // A feed that is not there, and a key a feed cannot sweep.
    for (parameter, needle) in [
        ("feeds[5].count", "no feeds[5]"),
        ("feeds[0].medium", "a feed sweeps its count"),
    ] {
        let sweep = format!("[sweep]\nparameter = \"{parameter}\"\nvalues = [1]\n");
        let cfg = s.input("bad.toml", &small_filtration("um", 80, &sweep));
        let o = s.packbed(&[
            "ensemble",
            cfg.to_str().unwrap(),
            "--runs",
            "1",
            "--out",
            "x",
        ]);
        assert_eq!(o.code, 2, "{}", o.stderr);
        assert!(o.stderr.contains(needle), "{parameter}: {}", o.stderr);
    }
}

#[test]
fn compare_sets_filtrations_in_um_and_mm_side_by_side_in_one_unit() {
    let s = Scratch::new();
    let um = s.input("um.toml", &small_filtration("um", 80, ""));
    let mm = s.input("mm.toml", &small_filtration("mm", 80, ""));
    s.ok(&[
        "ensemble",
        um.to_str().unwrap(),
        "--runs",
        "3",
        "--out",
        "um",
        "-q",
    ]);
    s.ok(&[
        "ensemble",
        mm.to_str().unwrap(),
        "--runs",
        "3",
        "--out",
        "mm",
        "-q",
    ]);
    let o = s.ok(&["compare", "um", "mm", "--out", "cmp"]);
    // On screen, the headline with units: the filtration in SI.
    for cell in [
        "filtration.alpha_fit_m_per_kg (m/kg)",
        "filtration.r_medium_fit_per_m (1/m)",
        "filtration.final.time_s (s)",
        "capture.passed_fraction (1)",
    ] {
        assert!(o.stdout.contains(cell), "{cell} not in\n{}", o.stdout);
    }
    let json: Value = serde_json::from_str(&s.read("cmp/compare.json")).unwrap();
    assert_eq!(json["length_unit"], "um");
    assert!(
        json["not_converted"].as_array().unwrap().is_empty(),
        "{json}"
    );
    let row = |name: &str| {
        json["measures"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["measure"] == name)
            .unwrap_or_else(|| panic!("{name} not compared"))
            .clone()
    };
    // The same beds in two units: lengths of the capture converted to µm
    // (not 1000× apart), SI figures as they are; each row names its unit.
    for (name, unit) in [
        ("capture.medium_surface", "µm"),
        ("capture.criteria.medium_d15", "µm"),
        ("capture.classes[3].d_lo", "µm"),
        ("filtration.alpha_network_m_per_kg", "m/kg"),
        ("filtration.r_medium_clogged_per_m", "1/m"),
        ("filtration.final.volume_m3_per_m2", "m³/m²"),
        ("filtration.final.cake_height_m", "m"),
        ("capture.lodged_fraction", "1"),
    ] {
        let r = row(name);
        assert_eq!(r["unit"], unit, "{r}");
        let (a, b) = (
            r["groups"][0]["mean"].as_f64().unwrap(),
            r["groups"][1]["mean"].as_f64().unwrap(),
        );
        assert!((b / a - 1.0).abs() < 1e-9, "{name}: µm {a}, mm {b}");
    }
    let md = s.read("cmp/compare.md");
    assert!(md.contains("Units: lengths in µm"), "{md}");
    assert!(md.contains("| capture.criteria.medium_d15 (µm) |"), "{md}");
    // α fitted: within the scatter of the beds (the same beds).
    let alpha = row("filtration.alpha_fit_m_per_kg");
    assert_eq!(alpha["unit"], "m/kg");
    assert_eq!(
        alpha["against_first"][0]["beyond_scatter"], false,
        "{alpha}"
    );
}
