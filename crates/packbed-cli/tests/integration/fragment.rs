//! `packbed fragment`: the files it writes and the inputs it refuses.

use crate::common::{assert_contains, assert_user_error, words, Scratch};

/// A 2D bed of equal discs written by `packbed run` into `work/bed`.
fn bed(s: &Scratch) -> String {
    s.ok(&words(
        "run --dim 2 --radii 10 --seed 3 --out bed --no-pictures -q",
    ));
    "bed/particles.csv".to_string()
}

#[test]
fn fragment_writes_bonds_breakage_and_summary() {
    let s = Scratch::new();
    let b = bed(&s);
    let o = s.ok(&["fragment", &b, "--out", "frag", "--no-pictures"]);
    assert_contains(&o.stdout, "under shear");
    let bonds = s.read("frag/bonds.csv");
    let mut lines = bonds.lines();
    assert_eq!(
        lines.next().unwrap(),
        "bond,i,j,wall,px,py,nx,ny,fx,fy,normal,tangential,magnitude"
    );
    // One bond per contact of the analysis: pairs plus floor and side walls.
    s.ok(&["analyze", &b, "--out", "an", "--no-pictures", "-q"]);
    let contacts = s.read("an/contacts.csv").lines().count() - 1;
    let walls = s.read("an/wall_contacts.csv").lines().count() - 1;
    assert_eq!(lines.count(), contacts + walls);
    let summary = s.summary("frag");
    let f = &summary["fragmentation"];
    assert_eq!(f["load"], "shear");
    assert_eq!(f["bonds"].as_u64().unwrap() as usize, contacts + walls);
    assert_eq!(f["failed"], true);
    let breaks = f["breaks"].as_u64().unwrap();
    assert_eq!(f["breaks_to_failure"].as_u64().unwrap(), breaks);
    // What the forces are relative to, and how to get a stress, on file and
    // on screen.
    let note = summary["force_note"].as_str().unwrap();
    assert!(note.contains("relative to a total load F = 1"), "{note}");
    assert!(
        note.contains("shear stress τ") && note.contains("F = τ·A"),
        "{note}"
    );
    assert_contains(&o.stdout, &format!("  note: {note}\n"));
    // No progress bar when stderr is not a terminal.
    assert_eq!(o.stderr, "");
    let breakage = s.read("frag/breakage.csv");
    assert_eq!(breakage.lines().count() as u64, breaks + 1);
    assert!(breakage.starts_with("step,i,j,wall,magnitude,fragments,largest_fragment\n"));
    // A fixed number of breaks under compression.
    s.ok(&[
        "fragment",
        &b,
        "--out",
        "comp",
        "--no-pictures",
        "--load",
        "compression",
        "--breaks",
        "5",
        "-q",
    ]);
    let c = s.summary("comp");
    assert_eq!(c["fragmentation"]["breaks"], 5);
    assert_eq!(c["settings"]["breaks"], "5");
}

#[test]
fn fragment_refuses_bad_input_with_one_line() {
    let s = Scratch::new();
    let b = bed(&s);
    assert_user_error(
        &s,
        &["fragment", "missing.csv", "--out", "x"],
        &["missing.csv"],
    );
    let bad = s.input("bad.csv", "id,species,body,x,y,r\n0,0,0,1,oops,1\n");
    assert_user_error(
        &s,
        &["fragment", bad.to_str().unwrap(), "--out", "x"],
        &["bad.csv"],
    );
    assert_user_error(
        &s,
        &["fragment", &b, "--load", "twist", "--out", "x"],
        &["--load", "twist"],
    );
    assert_user_error(
        &s,
        &["fragment", &b, "--breaks", "0", "--out", "x"],
        &["--breaks"],
    );
    assert_user_error(
        &s,
        &["fragment", &b, "--breaks", "many", "--out", "x"],
        &["--breaks"],
    );
    assert_user_error(
        &s,
        &["fragment", &b, "--kt-kn=-1", "--out", "x"],
        &["--kt-kn"],
    );
    // Two discs floating apart in a box: no bonds.
    let lone = s.input("lone.txt", "10 50 1\n30 50 1\n");
    assert_user_error(
        &s,
        &[
            "fragment",
            lone.to_str().unwrap(),
            "--box",
            "40,100",
            "--out",
            "x",
        ],
        &["no bonds"],
    );
}

#[test]
fn run_config_with_fragmentation_table_reports_it() {
    let s = Scratch::new();
    let c = s.input(
        "f.toml",
        "dim = 2\nseed = 2\n[[species]]\nradius = 10\n[fragmentation]\nload = \"gravity\"\nbreaks = 3\n",
    );
    s.ok(&[
        "run",
        c.to_str().unwrap(),
        "--out",
        "r",
        "--no-pictures",
        "-q",
    ]);
    let f = &s.summary("r")["fragmentation"];
    assert_eq!(f["load"], "gravity");
    assert_eq!(f["breaks"], 3);
    let bad = s.input("g.toml", "dim = 2\n[fragmentation]\nload = \"twist\"\n");
    assert_user_error(&s, &["run", bad.to_str().unwrap()], &["twist"]);
    let zero = s.input("z.toml", "dim = 2\n[fragmentation]\nbreaks = 0\n");
    assert_user_error(&s, &["run", zero.to_str().unwrap()], &["breaks"]);
}

#[test]
fn a_bed_without_top_bodies_says_what_is_missing_and_why() {
    // A standing chain of ten beads with a disc resting against its side,
    // higher than the chain's centre: the chain is covered, and the disc's
    // top is more than 2 r_max below the chain's.
    let s = Scratch::new();
    let mut table = String::from("id,species,body,x,y,r\n");
    for k in 0..10 {
        table += &format!("{k},0,0,100,{},10\n", 10 + 10 * k);
    }
    table += "10,1,1,120,70,10\n";
    let bed = s.input("standing.csv", &table);
    let b = bed.to_str().unwrap();
    for load in ["shear", "compression"] {
        assert_user_error(
            &s,
            &[
                "fragment", b, "--box", "200,250", "--load", load, "--out", "f",
            ],
            &[
                "no body qualifies as top",
                &format!("the {load} load has nowhere to act"),
                "no bonded partner whose reference point",
                "within 2 r_max = 20 of the bed's highest point (110)",
                "(1 of them) has a partner above",
                "the `gravity` load needs none",
            ],
        );
    }
    s.ok(&[
        "fragment", b, "--box", "200,250", "--load", "gravity", "--out", "g", "-q",
    ]);
}
