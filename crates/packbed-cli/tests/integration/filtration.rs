//! The filtration researcher's way in: size distributions as measured (sieve
//! tables, laser curves), the placed sizes against the requested ones, and
//! `packbed compare` of two batches.

use crate::common::{assert_user_error, Scratch};

/// A sieve table in micrometres and a 3D cake of it in a small periodic box.
fn sieve(s: &Scratch, name: &str, rows: &str) -> String {
    s.input(
        &format!("{name}.csv"),
        &format!("diameter_min_um,diameter_max_um,mass_percent\n{rows}"),
    );
    let p = s.input(
        &format!("{name}.toml"),
        &format!(
            "dim = 3\nseed = 1\n[box]\nwidth = 400\ndepth = 400\nheight = 1200\nperiodic = true\n\
             [[species]]\nsize = {{ table = \"{name}.csv\" }}\n\
             [analysis]\nlength_unit = \"um\"\nsolid_density = 1500\n"
        ),
    );
    p.to_str().unwrap().to_string()
}

const COARSE: &str = "40,60,10\n60,90,50\n90,120,40\n";
const FINE: &str = "20,30,20\n30,45,30\n45,70,30\n70,120,20\n";

#[test]
fn a_sieve_table_builds_its_sizes_and_reports_placed_against_requested() {
    let s = Scratch::new();
    let cfg = sieve(&s, "coarse", COARSE);
    let o = s.ok(&["run", &cfg, "--out", "a"]);
    assert!(
        o.stdout
            .contains("sizes by mass, d10 / d50 / d90: requested"),
        "{}",
        o.stdout
    );
    let summary = s.summary("a");
    // Diameters 40–120 um in a bed measured in um: radii 20–60, not 40–120.
    let p = std::fs::read_to_string(s.path("a/particles.csv")).unwrap();
    let radii: Vec<f64> = p
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(radii.iter().all(|&r| (20.0..=60.0).contains(&r)));
    // Drawn within the classes, not collapsed onto their edges.
    let mut distinct = radii.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    assert!(
        distinct.len() > radii.len() / 2,
        "{} of {}",
        distinct.len(),
        radii.len()
    );
    // The requested curve is the table's: 10 % finer than 60 um, 60 % than 90.
    let table = summary["psd"]["table"].as_array().unwrap();
    let at = |d: f64| {
        table
            .iter()
            .find(|r| (r["diameter"].as_f64().unwrap() - d).abs() < 1e-9)
            .unwrap_or_else(|| panic!("no row at {d}"))
    };
    assert!((at(60.0)["requested_mass_percent_passing"].as_f64().unwrap() - 10.0).abs() < 1e-9);
    assert!((at(90.0)["requested_mass_percent_passing"].as_f64().unwrap() - 60.0).abs() < 1e-9);
    // The placed curve counts the bed's own particles (independently here).
    let total: f64 = radii.iter().map(|r| r.powi(3)).sum();
    let finer: f64 = radii
        .iter()
        .filter(|&&r| r <= 45.0)
        .map(|r| r.powi(3))
        .sum();
    let placed = at(90.0)["placed_mass_percent_passing"].as_f64().unwrap();
    assert!((placed - 100.0 * finer / total).abs() < 1e-9, "{placed}");
    let d50 = summary["psd"]["placed"]["d50"].as_f64().unwrap();
    assert!((80.0..=120.0).contains(&d50), "{d50}");
    // psd.csv holds the same rows; the plot is there with pictures.
    let csv = s.read("a/psd.csv");
    assert!(csv
        .starts_with("radius,diameter,requested_mass_percent_passing,placed_mass_percent_passing"));
    assert_eq!(csv.lines().count(), table.len() + 1);
    assert!(s.path("a/plot_psd.png").is_file());
    // The cake comes first in summary.json, with its SI resistance.
    // (After the version and any warnings: this small box warns that its
    // 40–60 um class is sampled to more than 1 point, psd.departure.)
    let text = s.read("a/summary.json");
    let first_key = text
        .lines()
        .filter(|l| l.starts_with("  \"") && !l.contains("\"packbed_version\""))
        .find(|l| !l.starts_with("  \"warnings\""))
        .unwrap();
    assert!(
        first_key.trim_start().starts_with("\"cake\""),
        "{first_key}"
    );
    assert!(summary["cake"]["specific_resistance"].as_f64().unwrap() > 0.0);
}

#[test]
fn a_two_column_file_without_a_known_header_is_refused() {
    let s = Scratch::new();
    s.input("psd.csv", "60,50\n90,50\n");
    let p = s.input(
        "psd.toml",
        "dim = 2\n[[species]]\nsize = { table = \"psd.csv\" }\n",
    );
    assert_user_error(
        &s,
        &["run", p.to_str().unwrap()],
        &[
            "psd.csv:1",
            "no header",
            "`60,50`",
            "diameter_min,diameter_max,mass_percent",
        ],
    );
    s.input("psd.csv", "size,amount\n60,50\n");
    assert_user_error(
        &s,
        &["run", p.to_str().unwrap()],
        &["unknown header `size,amount`", "percent_passing"],
    );
}

#[test]
fn compare_tells_two_batches_apart_beyond_their_scatter() {
    let s = Scratch::new();
    let a = sieve(&s, "coarse", COARSE);
    let b = sieve(&s, "fine", FINE);
    s.ok(&[
        "ensemble",
        &a,
        "--runs",
        "4",
        "--out",
        "coarse",
        "--no-pictures",
    ]);
    s.ok(&[
        "ensemble",
        &b,
        "--runs",
        "4",
        "--out",
        "fine",
        "--no-pictures",
    ]);
    let o = s.ok(&["compare", "coarse", "fine", "--out", "cmp"]);
    assert!(
        o.stdout.contains("coarse (4 beds) against fine (4 beds)"),
        "{}",
        o.stdout
    );
    let porosity = o
        .stdout
        .lines()
        .find(|l| l.trim_start().starts_with("cake.porosity"))
        .unwrap_or_else(|| panic!("{}", o.stdout));
    assert!(porosity.contains("p "), "{porosity}");
    // The sauter diameter of the fine batch is far below the coarse one's.
    let csv = s.read("cmp/compare.csv");
    let d32 = csv.lines().find(|l| l.starts_with("cake.d32,")).unwrap();
    let cells: Vec<&str> = d32.split(',').collect();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (ma, mb) = (
        cells[col("coarse.mean")].parse::<f64>().unwrap(),
        cells[col("fine.mean")].parse::<f64>().unwrap(),
    );
    assert!(mb < 0.8 * ma, "{ma} {mb}");
    let p: f64 = cells[col("fine.p")].parse().unwrap();
    assert!(p < 0.01, "{p}");
    assert!(s.read("cmp/compare.md").contains("beyond scatter"));
    assert!(s.path("cmp/plot_compare_cake_porosity.png").is_file());
    assert!(s.path("cmp/plot_compare_psd.png").is_file());
    // A run is a group of one bed: compared, without a test.
    s.ok(&["run", &a, "--out", "one", "--no-pictures"]);
    let o = s.ok(&["compare", "one", "fine", "--out", "cmp1", "--no-pictures"]);
    assert!(o.stdout.contains("n/a (fewer than 2 beds)"), "{}", o.stdout);
}

#[test]
fn compare_refuses_what_is_not_packbed_output() {
    let s = Scratch::new();
    std::fs::create_dir(s.path("empty")).unwrap();
    std::fs::create_dir(s.path("other")).unwrap();
    assert_user_error(
        &s,
        &["compare", "empty", "other", "--out", "cmp"],
        &[
            "empty",
            "not a run (summary.json), an ensemble (runs/) or a sweep (sweep/)",
        ],
    );
}

#[test]
fn a_late_optional_stage_that_fails_keeps_the_run() {
    // Two discs placed at random, touching nothing: no bond to break.
    let s = Scratch::new();
    let p = s.input(
        "rsa.toml",
        "dim = 2\nmode = \"rsa\"\n[box]\nwidth = 1000\nheight = 1000\n[fill]\ncount = 2\n\
         [[species]]\nradius = 10\n[fragmentation]\n",
    );
    let o = s.ok(&["run", p.to_str().unwrap(), "--out", "kept", "--no-pictures"]);
    assert!(
        o.stderr
            .contains("packbed: warning: fragmentation: the bed has no bonds"),
        "{}",
        o.stderr
    );
    assert!(s.path("kept/particles.csv").is_file());
    let summary = s.summary("kept");
    assert!(summary["warnings"][0]
        .as_str()
        .unwrap()
        .contains("without breakage"));
    assert!(summary.get("fragmentation").is_none());
}

#[test]
fn a_species_name_longer_than_a_legend_has_room_for_is_shortened() {
    // Once "plot ... is too small for its labels", exit 2 and no file at all,
    // on every rerun of an ensemble too.
    let s = Scratch::new();
    let long = "s".repeat(100);
    let p = s.input(
        "long.toml",
        &format!(
            "dim = 2\n[fill]\ncount = 150\n[[species]]\nname = \"{long}\"\nradius = 10\n\
             [[species]]\nname = \"small\"\nradius = 6\n"
        ),
    );
    let p = p.to_str().unwrap();
    let o = s.ok(&["run", p, "--out", "long", "-q"]);
    assert_eq!(o.stderr, "");
    let svg = s.read("long/plot_coordination.svg");
    assert!(
        svg.contains("sss…<") && !svg.contains(&long),
        "not shortened"
    );
    assert!(s.path("long/plot_coordination.png").is_file());
    assert!(s.summary("long").get("warnings").is_none());
    let o = s.ok(&["ensemble", p, "--runs", "2", "--out", "e", "-q"]);
    assert_eq!(o.stderr, "");
    assert!(s.path("e/plot_coordination.png").is_file());
}
