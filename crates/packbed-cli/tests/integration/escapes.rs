//! Names, fields and paths from the user reach every channel escaped for it:
//! the terminal (no control character but line breaks), SVG (well-formed
//! XML), Markdown (a table keeps its columns), CSV (quoted by the csv crate).

use crate::common::{assert_contains, Scratch};
use std::path::Path;

/// A species name with every troublesome character, as a TOML string: ESC
/// starting a colour, an OSC (window title) ended by BEL, the C1 CSI U+009B,
/// XML markup, a Markdown column bar, a quote and a newline.
const HOSTILE_TOML: &str = r#""big\u001b[31m\u001b]0;pwned\u0007\u009b2J<&>|\"'\nend""#;

/// No byte that acts on a terminal: no control character but `\n`, no C1.
#[track_caller]
fn assert_inert(what: &str, text: &str) {
    let bad: Vec<char> = text
        .chars()
        .filter(|&c| c.is_control() && c != '\n')
        .collect();
    assert!(bad.is_empty(), "{what}: raw controls {bad:?} in:\n{text}");
}

/// Every `.svg` under `dir` parses as XML; returns how many there were.
fn assert_svgs_parse(dir: &Path) -> usize {
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            n += assert_svgs_parse(&p);
        } else if p.extension().is_some_and(|x| x == "svg") {
            let text = std::fs::read_to_string(&p).unwrap();
            if let Err(e) = roxmltree::Document::parse(&text) {
                panic!("{} is not XML: {e}", p.display());
            }
            n += 1;
        }
    }
    n
}

/// Bars that separate cells: those not escaped by a backslash.
fn cell_bars(line: &str) -> usize {
    let mut n = 0;
    let mut escaped = false;
    for c in line.chars() {
        match c {
            '\\' if !escaped => escaped = true,
            '|' if !escaped => n += 1,
            _ => escaped = false,
        }
        if c != '\\' {
            escaped = false;
        }
    }
    n
}

/// Every row of every table of a Markdown text has its header's columns.
#[track_caller]
fn assert_tables_keep_columns(md: &str) {
    let mut header = None;
    for line in md.lines() {
        if line.starts_with('|') {
            let n = cell_bars(line);
            match header {
                None => header = Some(n),
                Some(h) => assert_eq!(n, h, "a row with other columns: {line}\n{md}"),
            }
        } else {
            header = None;
        }
    }
}

fn hostile_config(s: &Scratch, runs: Option<u32>) -> String {
    let ensemble = runs.map_or(String::new(), |n| format!("[ensemble]\nruns = {n}\n"));
    let text = format!(
        "dim = 2\n{ensemble}[box]\ndiameters = 8\n[[species]]\nname = {HOSTILE_TOML}\nradius = 20\n\
         [[species]]\nname = \"small\"\nradius = 10\n"
    );
    s.input("hostile.toml", &text).to_str().unwrap().to_string()
}

#[test]
fn a_hostile_species_name_and_out_name_reach_no_channel_raw() {
    let s = Scratch::new();
    let config = hostile_config(&s, None);
    let out = "o\u{1b}[2Jut\u{9b}";
    let o = s.ok(&["run", &config, "--out", out]);
    assert_inert("run stdout", &o.stdout);
    assert_inert("run stderr", &o.stderr);
    // The name is shown, escaped, on the species line: one line.
    assert_contains(
        &o.stdout,
        r"species big\u{1b}[31m\u{1b}]0;pwned\u{7}\u{9b}2J<&>|",
    );
    assert_contains(&o.stdout, r"\u{a}end: r = 20");
    assert_contains(&o.stdout, r"files in o\u{1b}[2Jut\u{9b}: ");
    let dir = s.path(out);
    let svgs = assert_svgs_parse(&dir);
    assert!(dir.join("bed.svg").exists() && dir.join("plot_coordination.svg").exists());
    assert!(svgs >= 2, "{svgs} SVG files");
    // The legend names the species, its markup escaped.
    let bed = std::fs::read_to_string(dir.join("bed.svg")).unwrap();
    assert_contains(&bed, "&lt;&amp;&gt;|&quot;&apos;");
    // The summary keeps the name as given (JSON escapes it).
    let v = s.summary(out);
    assert_eq!(
        v["species"][0]["name"],
        "big\u{1b}[31m\u{1b}]0;pwned\u{7}\u{9b}2J<&>|\"'\nend"
    );
}

#[test]
fn a_hostile_species_name_keeps_the_ensemble_tables_whole() {
    let s = Scratch::new();
    let config = hostile_config(&s, Some(2));
    let o = s.ok(&["ensemble", &config, "--out", "e"]);
    assert_inert("ensemble stdout", &o.stdout);
    assert_inert("ensemble stderr", &o.stderr);
    let md = s.read("e/ensemble.md");
    assert_inert("ensemble.md", &md);
    assert_tables_keep_columns(&md);
    // The species' rows are there, their name escaped for Markdown.
    assert_contains(&md, r"2J&lt;&amp;>\|");
    assert!(assert_svgs_parse(&s.path("e")) >= 1);
    // ensemble.csv quotes the name: every row has the header's fields.
    let csv = s.read("e/ensemble.csv");
    let mut r = csv::ReaderBuilder::new().from_reader(csv.as_bytes());
    let width = r.headers().unwrap().len();
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    assert!(rows.iter().all(|row| row.len() == width));
    assert!(rows.iter().any(|row| row[0].contains("<&>|\"'\nend")));
    // A merge prints the same, escaped.
    let o = s.ok(&["merge", "e", "--out", "m"]);
    assert_inert("merge stdout", &o.stdout);
}

#[test]
fn a_hostile_xyz_field_reaches_no_channel_raw() {
    let s = Scratch::new();
    // Two species named by their field: one with an OSC, BEL, ESC and C1.
    let bad = "A\u{1b}]0;x\u{7}\u{9b}<&>|";
    let mut rows = String::new();
    let mut n = 0;
    for i in 0..6 {
        for j in 0..3 {
            let name = if (i + j) % 2 == 0 { bad } else { "B" };
            rows += &format!("{name} {} {} 1 1\n", 1 + 2 * i, 1 + 2 * j);
            n += 1;
        }
    }
    let text = format!(
        "{n}\nLattice=\"12 0 0 0 6 0 0 0 12\" Properties=species:S:1:pos:R:3:radius:R:1 pbc=\"F F F\"\n{rows}"
    );
    let bed = s.input("b\u{1b}[5med.xyz", &text);
    let o = s.ok(&["analyze", bed.to_str().unwrap(), "--out", "a"]);
    assert_inert("analyze stdout", &o.stdout);
    assert_inert("analyze stderr", &o.stderr);
    assert_contains(&o.stdout, r"b\u{1b}[5med.xyz");
    assert_contains(&o.stdout, r"by species: A\u{1b}]0;x\u{7}\u{9b}<&>| 3.000");
    let svgs = assert_svgs_parse(&s.path("a"));
    assert!(s.path("a/plot_coordination.svg").exists() && svgs >= 2);
}
