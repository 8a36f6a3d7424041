//! Size distributions as labs write them and the figures a cake of them
//! gives: sieve tables with a pan, the placed curve against its sampling
//! error, figures outside the physical range of filter cakes, and the limits
//! on what a config or bed file may hold.

use crate::common::{assert_config_refused, assert_user_error, Scratch};

/// A config of one species drawing from `table.csv`; `rest` holds top-level
/// keys, then tables.
fn config(s: &Scratch, name: &str, table: &str, rest: &str) -> String {
    s.input("table.csv", table);
    let split = rest.find("\n[").map_or(rest.len(), |k| k + 1);
    let (top, tables) = rest.split_at(split);
    let p = s.input(
        name,
        &format!("seed = 1\n{top}{tables}\n[[species]]\nsize = {{ table = \"table.csv\" }}\n"),
    );
    p.to_str().unwrap().to_string()
}

#[test]
fn a_lab_sieve_table_with_a_pan_gives_the_hand_computed_d50() {
    // Mass retained on each sieve (mm) with a pan, as a lab writes it. By
    // hand: 20 % passes 0.125 mm and 70 % passes 0.25 mm, so d50 lies 0.6 of
    // the way through the 0.125–0.25 class by mass; log-uniform by number puts
    // mass ∝ d² dd there: d50³ = 0.125³ + 0.6 (0.25³ − 0.125³), 0.216560 mm.
    let s = Scratch::new();
    let cfg = config(
        &s,
        "sieve.toml",
        "Sieve (mm),Retained (%)\n0.5,0\n0.25,30\n0.125,50\nPan,20\n",
        "dim = 2\n[fill]\ncount = 200\n[analysis]\nlength_unit = \"mm\"\n",
    );
    s.ok(&["run", &cfg, "--out", "a", "--no-pictures"]);
    let summary = s.summary("a");
    let d50 = summary["psd"]["requested"]["d50"].as_f64().unwrap();
    assert!((d50 - 0.216_559_776).abs() < 1e-6, "{d50}");
    // The pan from half the finest aperture by default, or from `pan_min`.
    let d10 = summary["psd"]["requested"]["d10"].as_f64().unwrap();
    assert!((d10 - 0.103_185_227).abs() < 1e-6, "{d10}");
    let size = summary["species"][0]["size"].as_str().unwrap();
    assert!(size.contains("retained on sieves"), "{size}");
    let cfg = s.input(
        "pan.toml",
        "seed = 1\ndim = 2\n[fill]\ncount = 200\n[[species]]\n\
         size = { table = \"table.csv\", pan_min = 0.1 }\n[analysis]\nlength_unit = \"mm\"\n",
    );
    s.ok(&["run", cfg.to_str().unwrap(), "--out", "b", "--no-pictures"]);
    let d10 = s.summary("b")["psd"]["requested"]["d10"].as_f64().unwrap();
    assert!((d10 - 0.113_872_086).abs() < 1e-6, "{d10}");
}

#[test]
fn sieve_headers_that_could_mean_two_things_are_refused_at_their_line() {
    let s = Scratch::new();
    let rest = "dim = 2\n[analysis]\nlength_unit = \"mm\"\n";
    for (table, needles) in [
        (
            "sieve_mm,mass_percent\n0.5,0\n0.25,100\n",
            &["table.csv:1:", "retained_percent", "percent_passing"][..],
        ),
        (
            "sieve_mm,cumulative_percent_retained\n0.5,0\n0.25,100\n",
            &["table.csv:1:", "both passing and retained"],
        ),
        (
            "# lab 4\nsieve_mm,retained_percent\n1.0,2\n0.5,98\n",
            &[
                "table.csv:3:",
                "largest sieve, 1",
                "add the next larger sieve",
            ],
        ),
    ] {
        let cfg = config(&s, "t.toml", table, rest);
        assert_user_error(&s, &["run", &cfg, "--out", "o"], needles);
    }
}

/// A sieve curve whose coarse class (1.5 % of the mass, diameters 80–120 um
/// against 40–60 um) expects one body in 500.
const COARSE_TAIL: &str = "diameter_um,percent_passing\n40,0\n60,98.5\n80,98.5\n120,100\n";

fn coarse_tail(s: &Scratch, count: u64) -> String {
    config(
        s,
        &format!("c{count}.toml"),
        COARSE_TAIL,
        &format!(
            "dim = 2\n[box]\nwidth = {}\nheight = 100000\n[fill]\ncount = {count}\n\
             [analysis]\nlength_unit = \"um\"\nmeasures = [\"packing\"]\n",
            (count as f64).sqrt() * 60.0
        ),
    )
}

#[test]
fn a_class_drawn_into_a_body_or_two_is_warned_with_the_count_that_holds_it() {
    let s = Scratch::new();
    let small = coarse_tail(&s, 500);
    let o = s.ok(&["run", &small, "--out", "small", "--no-pictures"]);
    let d = &s.summary("small")["psd"]["departure"];
    let expected = d["sparsest_class_expected_bodies"].as_f64().unwrap();
    assert!((0.5..2.0).contains(&expected), "{d}");
    assert_eq!(d["sparsest_class"][0].as_f64(), Some(80.0), "{d}");
    assert_eq!(d["exceeds_tolerance"], true, "{d}");
    let needed = d["bodies_needed"].as_f64().unwrap();
    assert!(needed > 5000.0, "{d}");
    let warning = o
        .stderr
        .lines()
        .find(|l| l.starts_with("packbed: warning: psd: the placed mass curve departs"))
        .unwrap_or_else(|| panic!("{}", o.stderr));
    for needle in ["500 bodies sample it to ±", "80–120", "bodies (a box of"] {
        assert!(warning.contains(needle), "`{needle}` not in {warning}");
    }
    let warnings = s.summary("small")["warnings"].clone();
    assert!(
        warnings.as_array().unwrap().iter().any(|w| w
            .as_str()
            .unwrap()
            .starts_with("psd: the placed mass curve")),
        "{warnings}"
    );
    // A run of the bodies it names holds the curve to 1 point: no warning.
    let big = coarse_tail(&s, needed.ceil() as u64);
    let o = s.ok(&["run", &big, "--out", "big", "--no-pictures"]);
    assert!(!o.stderr.contains("psd:"), "{}", o.stderr);
    let d = &s.summary("big")["psd"]["departure"];
    assert_eq!(d["exceeds_tolerance"], false, "{d}");
    assert!(d["max_percent"].as_f64().unwrap() < 1.0, "{d}");
}

#[test]
fn a_table_in_mm_under_a_bed_in_um_is_warned() {
    // The case: a sieve table without a unit, its values in mm, in a
    // bed whose length unit is um: a cake of 0.2 um fines whose α looks
    // possible. The unit-less header is named; and a cake in metres of
    // 2 m "particles" lies outside every range of filter cakes.
    let s = Scratch::new();
    let cfg = config(
        &s,
        "mm.toml",
        "diameter_min,diameter_max,mass_percent\n0.1,0.2,40\n0.2,0.4,60\n",
        "dim = 3\n[box]\nwidth = 3\ndepth = 3\nheight = 6\nperiodic = true\n\
         [analysis]\nlength_unit = \"um\"\nsolid_density = 2650\n",
    );
    let o = s.ok(&["run", &cfg, "--out", "a", "--no-pictures"]);
    let warning = "names no unit, so its sizes are read in the bed's length_unit, um";
    assert!(o.stderr.contains(warning), "{}", o.stderr);
    let summary = s.summary("a");
    assert!(
        summary["warnings"].to_string().contains(warning),
        "{summary}"
    );
    let p = s.input(
        "m.toml",
        "dim = 3\nseed = 1\n[box]\nwidth = 12\ndepth = 12\nheight = 40\nperiodic = true\n\
         [[species]]\nradius = 1\n[analysis]\nlength_unit = \"m\"\nsolid_density = 2650\n",
    );
    let o = s.ok(&["run", p.to_str().unwrap(), "--out", "m", "--no-pictures"]);
    for needle in [
        "packbed: warning: cake: d32 (2 m) 2.000e0 m lies outside 1e-7..1e-2 m",
        "packbed: warning: cake: specific resistance",
    ] {
        assert!(o.stderr.contains(needle), "`{needle}` not in {}", o.stderr);
    }
    let summary = s.summary("m");
    assert!(
        summary["warnings"]
            .to_string()
            .contains("cake: k (Kozeny-Carman)"),
        "{summary}"
    );
}

#[test]
fn a_bad_radius_deep_in_a_bed_file_is_reported_at_its_line() {
    let s = Scratch::new();
    let mut text = String::from("x,y,r\n");
    for k in 0..50_000 {
        text.push_str(&format!("{}.5,{}.5,0.4\n", k % 1000, k / 1000));
    }
    text.push_str("3.5,60.5,1e-40\n");
    let bed = s.input("bed.csv", &text);
    assert_user_error(
        &s,
        &[
            "analyze",
            bed.to_str().unwrap(),
            "--box",
            "1000,100",
            "--out",
            "o",
        ],
        &["bed.csv:50002:", "1e-40"],
    );
}

#[test]
fn a_huge_contact_tolerance_is_echoed_short() {
    let s = Scratch::new();
    let bed = s.input("b.csv", "x,y,r\n10,10,10\n40,10,10\n");
    let b = bed.to_str().unwrap();
    let args = [
        "analyze",
        b,
        "--box",
        "100,100",
        "--contact-tol",
        "1e300",
        "--out",
        "o",
    ];
    assert_user_error(&s, &args, &["--contact-tol is 1e300, but at most 1"]);
    let o = s.packbed(&args);
    assert!(o.stderr.len() < 200, "{}", o.stderr);
}

#[test]
fn a_species_name_of_megabytes_is_refused_at_once() {
    let s = Scratch::new();
    let name = "n".repeat(20 << 20);
    let cfg = format!("[[species]]\nname = \"{name}\"\nradius = 1\n");
    let start = std::time::Instant::now();
    assert_config_refused(
        &s,
        "long.toml",
        &cfg,
        &[
            "species[0].name is 20971520 bytes long, at most 256",
            "…(20971520 bytes)",
        ],
    );
    let took = start.elapsed().as_secs_f64();
    assert!(took < 3.0, "{took} s");
    // 256 bytes is a name.
    let cfg = format!(
        "dim = 2\n[fill]\ncount = 5\n[[species]]\nname = \"{}\"\nradius = 1\n",
        "n".repeat(256)
    );
    let p = s.input("ok.toml", &cfg);
    s.ok(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        "ok",
        "--no-pictures",
        "-q",
    ]);
}
