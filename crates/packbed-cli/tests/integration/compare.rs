//! `packbed compare` across length units, dimensions and versions, its
//! ratios, and group names that hold terminal escapes or Markdown.

use crate::common::{assert_user_error, Scratch};
use serde_json::Value;

/// A sand cake in millimetres (sieve classes 0.1–0.5 mm).
fn sand(s: &Scratch, unit: bool) -> String {
    // Without a unit, neither the table nor a density may name one.
    let (suffix, unit) = if unit {
        ("_mm", "length_unit = \"mm\"\nsolid_density = 2650\n")
    } else {
        ("", "")
    };
    s.input(
        "sand.csv",
        &format!(
            "diameter_min{suffix},diameter_max{suffix},mass_percent\n0.1,0.2,20\n0.2,0.3,50\n0.3,0.5,30\n"
        ),
    );
    let p = s.input(
        "sand.toml",
        &format!(
            "dim = 3\nseed = 1\n[box]\nwidth = 2.5\ndepth = 2.5\nheight = 5.5\nperiodic = true\n\
             [[species]]\nname = \"sand\"\nsize = {{ table = \"sand.csv\" }}\n\
             [analysis]\n{unit}measures = [\"packing\", \"coordination\", \"percolation\", \"voids\", \"orientation\", \"segregation\", \"pores\", \"permeability\"]\n"
        ),
    );
    p.to_str().unwrap().to_string()
}

/// A flour cake in micrometres (a laser curve, 20–100 µm), with or without
/// its unit.
fn flour(s: &Scratch, unit: bool) -> String {
    s.input(
        "flour.csv",
        "diameter,percent_passing\n20,0\n30,10\n45,40\n70,80\n100,100\n",
    );
    let unit = if unit {
        "length_unit = \"um\"\nsolid_density = 1500\n"
    } else {
        ""
    };
    let p = s.input(
        if unit.is_empty() {
            "flour-bare.toml"
        } else {
            "flour.toml"
        },
        &format!(
            "dim = 3\nseed = 1\n[box]\nwidth = 400\ndepth = 400\nheight = 1000\nperiodic = true\n\
             [[species]]\nname = \"flour\"\nsize = {{ table = \"flour.csv\" }}\n\
             [analysis]\n{unit}measures = [\"packing\", \"coordination\", \"percolation\", \"voids\", \"orientation\", \"segregation\", \"pores\", \"permeability\"]\n"
        ),
    );
    p.to_str().unwrap().to_string()
}

fn json(s: &Scratch, rel: &str) -> Value {
    serde_json::from_str(&s.read(rel)).unwrap()
}

/// The row of `measure` in `compare.json`.
fn row<'a>(c: &'a Value, measure: &str) -> &'a Value {
    c["measures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["measure"] == measure)
        .unwrap_or_else(|| panic!("no {measure} in compare.json"))
}

#[test]
fn compare_converts_lengths_to_the_first_groups_unit() {
    let s = Scratch::new();
    s.ok(&["run", &sand(&s, true), "--out", "sand", "--no-pictures"]);
    s.ok(&["run", &flour(&s, true), "--out", "flour", "--no-pictures"]);
    let (a, b) = (s.summary("sand"), s.summary("flour"));
    let kz = |v: &Value| v["permeability"]["k_z"].as_f64().unwrap();
    let o = s.ok(&["compare", "sand", "flour", "--out", "cmp"]);
    // Said on screen: which unit, which group was converted.
    assert!(
        o.stdout
            .contains("lengths in mm (the unit of sand): converted flour from µm"),
        "{}",
        o.stdout
    );
    let c = json(&s, "cmp/compare.json");
    assert_eq!(c["length_unit"], "mm");
    assert_eq!(c["groups"][1]["length_factor"].as_f64(), Some(1e-3));
    // k_z of the flour in mm²: its µm² value times 1e-6, and the ratio of
    // the two the ratio of the SI values.
    let k = row(&c, "permeability.k_z");
    let flour_mm2 = k["groups"][1]["mean"].as_f64().unwrap();
    assert!((flour_mm2 / (kz(&b) * 1e-6) - 1.0).abs() < 1e-12, "{k}");
    assert_eq!(k["groups"][0]["mean"].as_f64(), Some(kz(&a)));
    let ratio = k["against_first"][0]["ratio"].as_f64().unwrap();
    assert!(
        (ratio / (kz(&b) * 1e-12 / (kz(&a) * 1e-6)) - 1.0).abs() < 1e-12,
        "{ratio}"
    );
    assert!(ratio < 0.2, "the flour is the less permeable: {ratio}");
    assert_eq!(k["length_power"], 2);
    assert!(k["against_first"][0]["ratio_ci_95"].is_null());
    // A length and an inverse length; the SI resistance as it is.
    let d32 = row(&c, "cake.d32");
    let d = b["cake"]["d32"].as_f64().unwrap() * 1e-3;
    assert!((d32["groups"][1]["mean"].as_f64().unwrap() / d - 1.0).abs() < 1e-12);
    let sv = row(&c, "cake.specific_surface");
    let sv_b = b["cake"]["specific_surface"].as_f64().unwrap() * 1e3;
    assert!((sv["groups"][1]["mean"].as_f64().unwrap() / sv_b - 1.0).abs() < 1e-12);
    let alpha = row(&c, "cake.specific_resistance");
    assert_eq!(alpha["groups"][1]["mean"], b["cake"]["specific_resistance"]);
    // Every measure of a full summary has a known dimension: none left out.
    assert_eq!(
        c["not_converted"],
        serde_json::json!([]),
        "{}",
        c["warnings"]
    );
    // The ratio in words, on screen and in compare.md.
    let line = format!(
        "flour is {:.1}× less permeable than sand (permeability.k_z, no CI: one bed)",
        1.0 / ratio
    );
    assert!(o.stdout.contains(&line), "{line}\n{}", o.stdout);
    let md = s.read("cmp/compare.md");
    assert!(
        md.contains(&line) && md.contains("Units: lengths in mm"),
        "{md}"
    );
    // The plots: the common unit on the axes, the flour's sizes in mm.
    let svg = s.read("cmp/plot_compare_permeability_k_z.svg");
    assert!(svg.contains("network k along z (mm²)"), "{svg}");
    let psd = s.read("cmp/plot_compare_psd.svg");
    assert!(psd.contains("diameter (mm)"));
    let ticks = crate::common::svg_texts(&psd);
    assert!(ticks.iter().any(|t| t == "0.02"), "{ticks:?}");
}

#[test]
fn compare_refuses_a_group_without_a_length_unit_against_one_with() {
    let s = Scratch::new();
    s.ok(&["run", &sand(&s, true), "--out", "sand", "--no-pictures"]);
    s.ok(&["run", &flour(&s, false), "--out", "flour", "--no-pictures"]);
    assert_user_error(
        &s,
        &["compare", "sand", "flour", "--out", "cmp"],
        &["sand names its length unit (mm) and flour does not"],
    );
    assert!(!s.path("cmp").exists());
}

#[test]
fn compare_notes_2d_against_3d_and_other_packbed_versions() {
    let s = Scratch::new();
    s.ok(&["run", &sand(&s, false), "--out", "sand", "--no-pictures"]);
    s.ok(&[
        "run",
        "--dim",
        "2",
        "--radii",
        "0.2,0.1",
        "--box",
        "diameters=8",
        "--out",
        "disc",
        "--no-pictures",
    ]);
    // The same bed as written by another version.
    std::fs::create_dir(s.path("old")).unwrap();
    let mut old = s.summary("sand");
    old["packbed_version"] = "0.0.1".into();
    std::fs::write(s.path("old/summary.json"), old.to_string()).unwrap();
    let o = s.ok(&[
        "compare",
        "sand",
        "disc",
        "old",
        "--out",
        "cmp",
        "--no-pictures",
    ]);
    let warnings: Vec<&str> = o.stderr.lines().collect();
    assert_eq!(warnings.len(), 2, "{}", o.stderr);
    assert!(warnings[0]
        .starts_with("packbed: warning: the groups mix 2D and 3D beds (sand 3D, disc 2D, old 3D)"));
    assert!(
        warnings[1].starts_with("packbed: warning: the beds come from different packbed versions")
    );
    assert!(warnings[1].contains("old 0.0.1"), "{}", warnings[1]);
    let c = json(&s, "cmp/compare.json");
    assert_eq!(c["warnings"].as_array().unwrap().len(), 2);
    assert!(s
        .read("cmp/compare.md")
        .contains("Note: the groups mix 2D and 3D beds"));
}

#[test]
fn compare_keeps_escapes_and_markdown_in_group_names_inert() {
    let s = Scratch::new();
    let cfg = flour(&s, true);
    s.ok(&["run", &cfg, "--out", "a", "--no-pictures", "--seed", "1"]);
    s.ok(&["run", &cfg, "--out", "b", "--no-pictures", "--seed", "2"]);
    let (x, y) = ("x\u{1b}]0;owned\u{7}|y\u{9b}31m", "b|c\nd\u{1b}[2J <b>`e`");
    std::fs::rename(s.path("a"), s.path(x)).unwrap();
    std::fs::rename(s.path("b"), s.path(y)).unwrap();
    let o = s.ok(&["compare", x, y, "--out", "cmp"]);
    for bad in ['\u{1b}', '\u{7}', '\u{9b}'] {
        assert!(!o.stdout.contains(bad), "{bad:?} on stdout: {}", o.stdout);
        assert!(!o.stderr.contains(bad), "{bad:?} on stderr");
    }
    assert!(
        o.stdout
            .contains("x\\u{1b}]0;owned\\u{7}|y\\u{9b}31m (1 beds)"),
        "{}",
        o.stdout
    );
    // compare.md: every row of the table has as many cells as its header.
    let md = s.read("cmp/compare.md");
    let cells = |l: &str| l.replace("\\|", "").matches('|').count();
    let table: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
    assert!(table.len() > 5, "{md}");
    assert!(table.iter().all(|l| cells(l) == cells(table[0])), "{md}");
    assert!(md.lines().all(|l| !l.contains('\u{1b}')), "{md}");
    assert!(md.contains("b\\|c\\\\u{a}d"), "{md}");
    // The SVG plots hold no character XML forbids.
    let mut svgs = 0;
    for e in std::fs::read_dir(s.path("cmp")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "svg") {
            let svg = std::fs::read_to_string(&p).unwrap();
            let bad = svg
                .chars()
                .find(|&c| c.is_control() && !matches!(c, '\n' | '\r' | '\t'));
            assert_eq!(bad, None, "{}", p.display());
            svgs += 1;
        }
    }
    assert!(svgs > 0);
}
