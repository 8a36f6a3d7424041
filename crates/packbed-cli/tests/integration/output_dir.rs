//! The output directory holds one run's files, and a full disk costs the
//! pictures, never the tables (issue 57: "A reused `--out` keeps stale
//! files", "A full disk while writing pictures").

use crate::common::{words, Outcome, Scratch};
use std::process::{Command, Stdio};

/// Names in `work/<dir>`, sorted.
fn names(s: &Scratch, dir: &str) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(s.path(dir))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

const TABLES: [&str; 4] = [
    "contacts.csv",
    "particles.csv",
    "summary.json",
    "wall_contacts.csv",
];

#[test]
fn a_reused_out_holds_only_the_new_runs_files() {
    let s = Scratch::new();
    let pores = "run --radii 1 --box 16,16,30 --count 1500 --measures packing,pores --export xyz --out r -q";
    s.ok(&words(pores));
    let first = names(&s, "r");
    for f in [
        "pores.csv",
        "throats.csv",
        "network.vtp",
        "bed.png",
        "bed.xyz",
    ] {
        assert!(first.contains(&f.to_string()), "{first:?}");
    }
    // A file of the user's beside them stays.
    std::fs::write(s.path("r/notes.txt"), "mine").unwrap();
    s.ok(&words(
        "run --radii 1 --box 16,16,30 --count 1500 --out r -q --no-pictures",
    ));
    let mut expected: Vec<String> = TABLES.iter().map(|n| n.to_string()).collect();
    expected.push("notes.txt".into());
    expected.sort();
    assert_eq!(names(&s, "r"), expected);
    // `analyze` into the directory of the bed it reads: the run's pictures
    // and pore files go, the bed files (its possible inputs) stay.
    s.ok(&words(pores));
    s.ok(&words("analyze r/particles.csv --out r -q --no-pictures"));
    expected.insert(0, "bed.xyz".into());
    assert_eq!(names(&s, "r"), expected);
    assert!(!s.summary("r")["source"].is_null(), "analyze's summary");
    // `fragment` likewise: its tables replace the analysis'.
    s.ok(&words(
        "fragment r/particles.csv --breaks 2 --out r -q --no-pictures",
    ));
    assert_eq!(
        names(&s, "r"),
        [
            "bed.xyz",
            "bonds.csv",
            "breakage.csv",
            "notes.txt",
            "particles.csv",
            "summary.json"
        ]
    );
}

#[test]
fn a_directory_packbed_did_not_write_keeps_its_files() {
    // No packbed `summary.json`: the user's files are not a run's, whatever
    // their names; only the names the run writes are replaced.
    let s = Scratch::new();
    std::fs::create_dir(s.path("mine")).unwrap();
    for n in ["plot_mine.png", "pores.csv", "summary.json"] {
        std::fs::write(s.path(&format!("mine/{n}")), "mine").unwrap();
    }
    s.ok(&words("run --dim 2 --count 40 --out mine -q --no-pictures"));
    assert_eq!(s.read("mine/plot_mine.png"), "mine");
    assert_eq!(s.read("mine/pores.csv"), "mine");
    assert!(s.read("mine/summary.json").contains("packbed_version"));
}

/// Runs `packbed` with files limited to `blocks` × 512 bytes (`ulimit -f`;
/// SIGXFSZ ignored, so that a write past it fails with EFBIG as on a full
/// disk instead of killing the process).
fn with_file_limit(s: &Scratch, args: &[&str], blocks: u64) -> Outcome {
    let script = format!("trap '' XFSZ; ulimit -f {blocks} && exec \"$0\" \"$@\"");
    let out = Command::new("sh")
        .arg("-c")
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_packbed"))
        .args(args)
        .current_dir(&s.work)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    Outcome {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// No `.NAME.PID.tmp` left in `work/<dir>`.
fn no_temporaries(s: &Scratch, dir: &str) {
    let left: Vec<String> = names(s, dir)
        .into_iter()
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_picture_that_does_not_fit_on_the_disk_costs_only_itself() {
    // 50 KiB per file: the tables of 80 discs fit (at most 26 KB), a
    // 1200×1000 bed.png (174 KB) does not. The run keeps its tables and summary, names the picture, exit 0.
    let s = Scratch::new();
    let o = with_file_limit(&s, &words("run --dim 2 --count 80 --out r -q"), 100);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stderr
            .contains("packbed: warning: picture bed.png not written"),
        "{}",
        o.stderr
    );
    assert_eq!(s.read("r/particles.csv").lines().count(), 81);
    let w = s.summary("r")["warnings"].to_string();
    assert!(w.contains("picture bed.png not written"), "{w}");
    assert!(!s.path("r/bed.png").exists());
    assert!(s.path("r/contacts.csv").exists());
    no_temporaries(&s, "r");
    // `fragment` likewise: its tables stay when its pictures do not fit.
    let o = with_file_limit(
        &s,
        &words("fragment r/particles.csv --breaks 2 --out f -q"),
        100,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stderr
            .contains("packbed: warning: picture forces.png not written"),
        "{}",
        o.stderr
    );
    assert!(s.path("f/bonds.csv").exists() && s.path("f/breakage.csv").exists());
    no_temporaries(&s, "f");
}

#[test]
fn a_table_that_does_not_fit_keeps_the_complete_ones_and_names_itself() {
    // 150 KiB per file: the bed's tables of 1500 spheres fit (at most 111
    // KB), its pore tables (1.2 MB) do not: the bed is kept, the failure
    // named, no summary (the directory is incomplete).
    let s = Scratch::new();
    let o = with_file_limit(
        &s,
        &words("run --radii 1 --box 16,16,30 --count 1500 --measures packing,pores --out r -q --no-pictures"),
        300,
    );
    assert_ne!(o.code, 0, "{}", o.stderr);
    assert_eq!(o.stderr.lines().count(), 1, "{}", o.stderr);
    assert!(
        o.stderr.contains("kept, complete: particles.csv"),
        "{}",
        o.stderr
    );
    assert_eq!(s.read("r/particles.csv").lines().count(), 1501);
    assert!(o.stderr.contains("pores.csv"), "{}", o.stderr);
    assert!(!s.path("r/summary.json").exists());
    no_temporaries(&s, "r");
}

#[test]
fn ensemble_plots_that_do_not_fit_cost_only_themselves() {
    let s = Scratch::new();
    let mut args = words("ensemble --runs 2 --out e -q");
    args.extend_from_slice(crate::common::SMALL);
    // 50 KiB per file: the statistics (at most 44 KB) fit, the PNG plots
    // (78–129 KB) do not.
    let o = with_file_limit(&s, &args, 100);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stderr.contains("packbed: warning: picture plot_"),
        "{}",
        o.stderr
    );
    for f in crate::common::STAT_FILES {
        assert!(s.path(&format!("e/{f}")).exists(), "{f}");
    }
    no_temporaries(&s, "e");
}

#[test]
fn a_full_tmpfs_keeps_the_tables() {
    // A real full disk where this test may mount one (root); elsewhere the
    // `ulimit -f` tests above hold the same logic.
    let s = Scratch::new();
    let mnt = s.path("disk");
    std::fs::create_dir(&mnt).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=96k", "tmpfs"])
        .arg(&mnt)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|st| st.success());
    if !mounted {
        eprintln!("skipped: cannot mount a tmpfs here (not root?)");
        return;
    }
    let o = s.packbed(&words("run --dim 2 --count 80 --out disk/r -q"));
    let listed = names(&s, "disk/r");
    let _ = Command::new("umount").arg(&mnt).status();
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stderr.contains("not written"), "{}", o.stderr);
    for t in TABLES {
        assert!(listed.contains(&t.to_string()), "{listed:?}");
    }
    assert!(!listed.iter().any(|n| n.ends_with(".tmp")), "{listed:?}");
}
