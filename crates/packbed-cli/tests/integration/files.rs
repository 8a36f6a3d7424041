//! Integration tests of how `packbed` reads bed files and writes its outputs:
//! refusals of inconsistent input, checks reported on input beds, CSV quoting,
//! temporary files after interruptions, unwritable output directories.

use crate::common::{assert_contains, assert_user_error, words, Scratch};
use serde_json::Value;
use std::path::Path;

// ---- counts ---------------------------------------------------------------

/// Body ids of a bed file may be sparse (molecule ids of another tool): the
/// count is of distinct bodies, not the largest id + 1.
#[test]
fn bodies_are_counted_not_numbered() {
    let s = Scratch::new();
    let f = s.input(
        "sparse.csv",
        "x,y,r,body\n1,1,1,0\n3,1,1,88000\n5,1,1,88000\n7,1,1,17\n",
    );
    s.ok(&[
        "analyze",
        f.to_str().unwrap(),
        "--box",
        "8,10",
        "--out",
        "a",
        "-q",
    ]);
    let v = s.summary("a");
    assert_eq!(v["counts"]["particles"], 4);
    assert_eq!(v["counts"]["bodies"], 3);
}

// ---- declared counts ------------------------------------------------------

/// A LAMMPS dump or XYZ file that declares fewer atoms than it has rows is
/// refused, naming both numbers, instead of being cut short.
#[test]
fn atom_count_below_the_rows_is_refused() {
    let s = Scratch::new();
    let dump = |n: usize| {
        format!(
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS ff ff ff\n\
             0 10\n0 10\n0 10\nITEM: ATOMS id type x y z radius\n\
             1 1 1 1 1 1\n2 1 3 1 1 1\n3 1 5 1 1 1\n"
        )
    };
    let short = s.input("short.dump", &dump(2));
    let needles = ["short.dump:12", "3 atom lines", "says 2"];
    assert_user_error(&s, &analyze(&short, "a"), &needles);
    let whole = s.input("whole.dump", &dump(3));
    assert_eq!(particles_read(&s, &whole, "a"), 3);

    let xyz = |n: usize| {
        format!(
            "{n}\nLattice=\"10 0 0 0 10 0 0 0 10\" Properties=pos:R:3:radius:R:1 pbc=\"F F F\"\n\
             1 1 1 1\n3 1 1 1\n5 1 1 1\n"
        )
    };
    let short = s.input("short.xyz", &xyz(1));
    let needles = ["short.xyz:4", "3 particle lines", "says 1"];
    assert_user_error(&s, &analyze(&short, "b"), &needles);
    let whole = s.input("whole.xyz", &xyz(3));
    assert_eq!(particles_read(&s, &whole, "b"), 3);
    // A second frame after a complete first one is not extra rows.
    let frames = s.input("frames.xyz", &format!("{}{}", xyz(3), xyz(3)));
    assert_eq!(particles_read(&s, &frames, "c"), 3);
}

/// `packbed analyze BED --out OUT`.
fn analyze<'a>(bed: &'a Path, out: &'a str) -> [&'a str; 4] {
    ["analyze", bed.to_str().unwrap(), "--out", out]
}

/// The particle count `packbed analyze` finds in `bed` (quietly, into `out`).
fn particles_read(s: &Scratch, bed: &Path, out: &str) -> Value {
    s.ok(&[&analyze(bed, out)[..], &["-q"]].concat());
    s.summary(out)["counts"]["particles"].clone()
}

// ---- the box ----------------------------------------------------------------

/// `--box` and `--periodic` win over the box of the summary.json beside a
/// particles.csv, and the output says which box was used.
#[test]
fn given_box_wins_over_the_summary_beside() {
    let s = Scratch::new();
    s.ok(&["run", "--dim", "2", "--count", "60", "--out", "r", "-q"]);
    let run = s.summary("r");
    let (w, h) = (
        run["box"]["width"].as_f64().unwrap(),
        run["box"]["height"].as_f64().unwrap(),
    );
    assert_eq!(run["box"]["periodic"], false);
    assert!(run["box"].get("source").is_none(), "{}", run["box"]);

    let o = s.ok(&["analyze", "r/particles.csv", "--out", "a"]);
    assert_contains(&o.stdout, "box from the summary.json");
    let a = s.summary("a");
    assert_eq!(a["box"], {
        let mut b = run["box"].clone();
        b["source"] = "summary.json".into();
        b
    });

    let given = format!("{w},{}", 2.0 * h);
    let o = s.ok(&[
        "analyze",
        "r/particles.csv",
        "--box",
        &given,
        "--periodic",
        "--out",
        "b",
    ]);
    assert_contains(&o.stdout, "box from the options, periodic sides");
    let b = s.summary("b");
    assert_eq!(b["box"]["width"].as_f64(), Some(w));
    assert_eq!(b["box"]["height"].as_f64(), Some(2.0 * h));
    assert_eq!(b["box"]["periodic"], true);
    assert_eq!(b["box"]["source"], "options");
    // The analysis used it: the same solid in a box twice as high, and no
    // side-wall contacts with periodic sides.
    let global = |v: &Value| v["packing"]["global"].as_f64().unwrap();
    assert!((global(&b) - global(&a) / 2.0).abs() < 1e-12 * global(&a));
    assert!(!s.read("b/wall_contacts.csv").contains(",x"));
}

/// Particles sticking out of the box by more than 1 % of their radius are
/// refused with their number and the line of the first; DEM-like small
/// overlaps with the walls pass; periodic centres are wrapped.
#[test]
fn particles_outside_the_box_are_refused() {
    let s = Scratch::new();
    let analyze = |name: &str, text: &str, boxed: &str, extra: &[&str], needles: &[&str]| {
        let f = s.input(name, text);
        let mut args = vec!["analyze", f.to_str().unwrap(), "--box", boxed, "--out", "o"];
        args.extend_from_slice(extra);
        assert_user_error(&s, &args, needles);
    };
    // The issue's case: a 3D table read as 2D, the heights taken for radii.
    analyze(
        "wall.txt",
        "5 5 1\n49.8 5 1\n20 5 1\n55 5 3\n",
        "50,50",
        &[],
        &[
            "wall.txt:2",
            "2 particles stick out",
            "x1",
            "0.800 of its radius",
        ],
    );
    analyze(
        "floor.txt",
        "5 5 1\n9 0.9 1\n",
        "50,50",
        &[],
        &["floor.txt:2", "floor"],
    );
    analyze(
        "roof.txt",
        "5 5 1\n9 49.5 1\n",
        "50,50",
        &[],
        &["roof.txt:2", "roof"],
    );
    analyze(
        "low.csv",
        "x,y,z,r\n5,5,5,1\n5,-0.5,5,1\n",
        "50,50,50",
        &[],
        &["low.csv:3", "y0"],
    );
    // The floor counts with periodic sides too, the roof does not.
    analyze(
        "pfloor.txt",
        "5 5 1\n9 0.5 1\n",
        "50,50",
        &["--periodic"],
        &["pfloor.txt:2", "floor"],
    );

    // Within 1 % of the radius: accepted.
    let f = s.input("dem.txt", "0.995 5 1\n49.005 5 1\n10 0.995 1\n");
    s.ok(&[
        "analyze",
        f.to_str().unwrap(),
        "--box",
        "50,50",
        "--out",
        "d",
        "-q",
    ]);
    // Periodic sides: centres outside [0, W) are wrapped, and the two discs
    // touch through the boundary; a disc above the roof passes.
    let f = s.input("wrap.txt", "-1 1 1\n1 1 1\n53 1 1\n10 60 1\n");
    s.ok(&[
        "analyze",
        f.to_str().unwrap(),
        "--box",
        "50,50",
        "--periodic",
        "--out",
        "p",
        "-q",
    ]);
    let contacts = s.read("p/contacts.csv");
    assert!(
        contacts.lines().any(|l| l.starts_with("0,1,")),
        "{contacts}"
    );
    assert!(
        contacts.lines().any(|l| l.starts_with("1,2,")),
        "{contacts}"
    );
}

// ---- checks on input beds -------------------------------------------------

/// Overlapping and duplicate particles are analysed, with a warning on stderr
/// and `checks.*` in summary.json; beads of one body do not count, nor do
/// packbed's own beds read back.
#[test]
fn overlaps_are_reported_not_refused() {
    let s = Scratch::new();
    // A duplicate (overlap 2 radii), a pair overlapping by half a radius, a
    // chain of two beads overlapping by design, one touching pair.
    let f = s.input(
        "overlaps.csv",
        "x,y,r,body\n5,5,1,0\n5,5,1,1\n10,5,1,2\n11.5,5,1,3\n20,5,1,4\n21,5,1,4\n30,5,1,5\n32,5,1,6\n",
    );
    let o = s.ok(&[
        "analyze",
        f.to_str().unwrap(),
        "--box",
        "50,50",
        "--out",
        "a",
        "-q",
    ]);
    let warning: Vec<&str> = o.stderr.lines().collect();
    assert_eq!(warning.len(), 1, "{}", o.stderr);
    assert!(
        warning[0].starts_with("packbed: warning: overlap: 2 pairs"),
        "{}",
        warning[0]
    );
    assert!(warning[0].contains("2.000"), "{}", warning[0]);
    let v = s.summary("a");
    assert_eq!(v["checks"]["overlapping_pairs"], 2);
    assert_eq!(v["checks"]["max_overlap"].as_f64(), Some(2.0));
    assert_eq!(v["counts"]["particles"], 8);

    // packbed's own beds, spheres and chains, 2D and 3D, read back: no overlap.
    for (out, args) in [
        ("r2", vec!["--dim", "2", "--count", "300"]),
        ("r3", vec!["--count", "300", "--periodic"]),
        ("c2", vec!["--dim", "2", "--beads", "4", "--count", "60"]),
    ] {
        let mut run = vec!["run", "--out", out, "-q", "--no-pictures"];
        run.extend(args);
        s.ok(&run);
        let csv = format!("{out}/particles.csv");
        let back = format!("{out}-a");
        let o = s.ok(&["analyze", &csv, "--out", &back, "-q", "--no-pictures"]);
        assert!(o.stderr.is_empty(), "{out}: {}", o.stderr);
        let v = s.summary(&back);
        assert_eq!(v["checks"]["overlapping_pairs"], 0, "{out}");
        assert_eq!(v["checks"]["max_overlap"].as_f64(), Some(0.0), "{out}");
    }
}

// ---- CSV --------------------------------------------------------------------

/// Every row of a CSV file read with the `csv` crate: header, then records.
fn read_csv(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// Species names are the user's: one holding a comma and quotes still gives
/// valid CSV in ensemble.csv, histograms.csv and sweep.csv, read back to the
/// same columns and values.
#[test]
fn csv_files_quote_names_with_commas() {
    let s = Scratch::new();
    let name = r#"fine, "wet""#;
    let config = s.input(
        "named.toml",
        &format!(
            "dim = 2\nseed = 3\n[box]\ndiameters = 8\n[[species]]\nradius = 20\nname = 'coarse'\n\
             [[species]]\nradius = 10\nname = '{name}'\n"
        ),
    );
    let c = config.to_str().unwrap();
    s.ok(&[
        "ensemble",
        c,
        "--runs",
        "2",
        "--out",
        "e",
        "-q",
        "--no-pictures",
    ]);
    let ensemble: Value = serde_json::from_str(&s.read("e/ensemble.json")).unwrap();
    let (header, rows) = read_csv(&s.read("e/ensemble.csv"));
    assert_eq!(header, ["name", "n", "mean", "sd", "min", "max", "kind"]);
    assert!(rows.iter().all(|r| r.len() == 7));
    let placed = format!("species.{name}.placed");
    let row = rows
        .iter()
        .find(|r| r[0] == placed)
        .unwrap_or_else(|| panic!("no row {placed}"));
    assert_eq!(row[1], "2");
    assert_eq!(row[6], "value");
    // The values are those of ensemble.json, bit for bit.
    let m = &ensemble["measures"][&placed];
    for (k, key) in ["mean", "sd", "min", "max"].iter().enumerate() {
        assert_eq!(row[2 + k].parse::<f64>().ok(), m[key].as_f64(), "{key}");
    }
    let (header, rows) = read_csv(&s.read("e/histograms.csv"));
    assert_eq!(header, ["name", "bin", "count", "fraction"]);
    assert!(rows.iter().all(|r| r.len() == 4));
    assert!(
        rows.iter().any(|r| r[0].contains(name)),
        "no histogram named after {name}"
    );
    for r in &rows {
        r[2].parse::<f64>().unwrap();
        r[3].parse::<f64>().unwrap();
    }
}

// ---- unwritable output ------------------------------------------------------

/// A directory nobody can create (below /proc), or one this user cannot
/// write (a read-only directory, when not running as root).
fn unwritable(s: &Scratch) -> Vec<String> {
    let mut v = vec!["/proc/packbed-no-such-dir/out".to_string()];
    let ro = s.inputs.join("read-only");
    std::fs::create_dir(&ro).unwrap();
    let mut perms = std::fs::metadata(&ro).unwrap().permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&ro, perms).unwrap();
    // Root writes anyway: then only the /proc case tells.
    if std::fs::write(ro.join("probe"), "x").is_err() {
        v.push(ro.join("out").to_string_lossy().into_owned());
    }
    v
}

/// Runs `args` and insists that it is refused as a user error about `--out`,
/// leaving nothing in `work/`. The work these commands are given takes minutes:
/// a command still running after `secs` seconds has started it before checking
/// its output (the guard stops it; it is not a speed criterion).
fn refused_before_the_work(s: &Scratch, args: &[&str], secs: u64) {
    let before = s.entries();
    let o = s.within(args, secs);
    assert_eq!(o.code, 2, "{args:?}: {}", o.stderr);
    assert_eq!(o.stderr.lines().count(), 1, "{args:?}: {}", o.stderr);
    assert!(
        o.stderr.starts_with("packbed: error: --out "),
        "{args:?}: {}",
        o.stderr
    );
    assert!(o.stdout.is_empty(), "{args:?}");
    assert_eq!(s.entries(), before, "{args:?} left files");
}

/// An output directory that cannot be written is refused before the work
/// (a 3D bed of 5·10^6 spheres would take minutes), by every command with
/// --out.
#[test]
fn unwritable_out_is_refused_before_the_work() {
    let s = Scratch::new();
    s.ok(&words("run --dim 2 --count 50 --out r -q --no-pictures"));
    let bed = s.work.join("r/particles.csv");
    let bed = bed.to_str().unwrap();
    let config = s.input(
        "small.toml",
        "dim = 2\nseed = 5\n[[species]]\nradius = 10\n",
    );
    let config = config.to_str().unwrap();
    for out in unwritable(&s) {
        let o = out.as_str();
        let picture = format!("{out}/bed.png");
        refused_before_the_work(
            &s,
            &["run", "--count", "5000000", "--periodic", "-q", "--out", o],
            20,
        );
        refused_before_the_work(
            &s,
            &["ensemble", config, "--runs", "4000", "-q", "--out", o],
            20,
        );
        refused_before_the_work(&s, &["analyze", bed, "-q", "--out", o], 20);
        refused_before_the_work(&s, &["render", bed, "--out", &picture], 20);
        refused_before_the_work(&s, &["merge", "r", "--out", o], 20);
    }
}

// ---- interrupted runs ---------------------------------------------------------

/// Hidden temporary files (`.NAME.PID.tmp`) in `dir`.
fn temp_files(dir: &std::path::Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with('.') && n.ends_with(".tmp"))
                .collect()
        })
        .unwrap_or_default()
}

/// A run stopped by SIGTERM or SIGINT while writing its files removes its
/// temporary files and exits with 143 or 130.
#[test]
fn signals_remove_the_temporary_files() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let s = Scratch::new();
        let out = s.work.join("big");
        // About 5 s of deposition and analysis, then ~30 MB of CSV to write.
        let mut child = Command::new(env!("CARGO_BIN_EXE_packbed"))
            .args([
                "run",
                "--dim",
                "2",
                "--count",
                "200000",
                "--radii",
                "10",
                "--box",
                "3000,3000",
                "--periodic",
                "--no-pictures",
                "-q",
                "--out",
                "big",
            ])
            .current_dir(&s.work)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let t = Instant::now();
        // The bed's own file, not the probe of --out made at the start.
        while !temp_files(&out)
            .iter()
            .any(|n| n.starts_with(".particles.csv."))
        {
            assert!(
                child.try_wait().unwrap().is_none(),
                "finished before a temporary file of particles.csv was seen"
            );
            // Only stops a hung process, not a speed criterion: the run ends
            // (and the assertion above fails) long before this.
            if t.elapsed() > Duration::from_secs(1800) {
                let _ = child.kill();
                let _ = child.wait();
                panic!("packbed hung: no temporary file and no exit after 30 minutes");
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        let killed = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let o = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "SIG{signal}: {stderr}");
        assert!(stderr.contains(&format!("SIG{signal}")), "{stderr}");
        assert_eq!(temp_files(&out), Vec::<String>::new(), "SIG{signal}");
        assert!(!out.join("summary.json").exists());
    }
}

/// Temporary files a killed run left (SIGKILL cannot be caught) are removed
/// by the next run into the same directory when their process is gone; files
/// of a live process and other names are left alone.
#[test]
fn stale_temporary_files_are_removed_by_the_next_run() {
    let s = Scratch::new();
    let out = s.work.join("r");
    std::fs::create_dir(&out).unwrap();
    // Above the largest process id Linux hands out (2^22).
    let stale = [".particles.csv.999999999.tmp", ".summary.json.4194305.tmp"];
    let alive = format!(".particles.csv.{}.tmp", std::process::id());
    let others = [
        ".notes.tmp",
        ".particles.csv.12ab.tmp",
        "keep.999999999.tmp",
        &alive,
    ];
    for n in stale.iter().chain(&others) {
        std::fs::write(out.join(n), "half").unwrap();
    }
    s.ok(&words("run --dim 2 --count 30 --out r -q --no-pictures"));
    for n in stale {
        assert!(!out.join(n).exists(), "{n} is still there");
    }
    for n in others {
        assert_eq!(std::fs::read_to_string(out.join(n)).unwrap(), "half", "{n}");
    }
    assert!(out.join("summary.json").exists());
}

// ---- inputs the reader once took or echoed badly (issue 30, item 9) --------

#[test]
fn files_that_are_not_utf8_are_refused_at_their_line() {
    let s = Scratch::new();
    let bed = s.inputs.join("latin1.csv");
    std::fs::write(&bed, b"x,y,r\n10,10,10\n40,10,1\xb5\n").unwrap();
    assert_user_error(
        &s,
        &["analyze", bed.to_str().unwrap(), "--box", "100,100"],
        &["latin1.csv:3: not UTF-8", "byte 0xb5 at column 8"],
    );
    let config = s.inputs.join("latin1.toml");
    std::fs::write(&config, b"dim = 2\n[[species]]\nname = \"\xe9\"\n").unwrap();
    assert_user_error(
        &s,
        &["run", config.to_str().unwrap()],
        &["latin1.toml:3: not UTF-8", "column 9"],
    );
}

#[test]
fn a_header_naming_a_column_twice_is_refused() {
    let s = Scratch::new();
    for (header, column, at) in [
        ("x,x,y,r", "`x`", "columns 1 and 2"),
        ("x,y,r,radius", "`radius`", "columns 3 and 4"),
    ] {
        let bed = s.input("dup.csv", &format!("{header}\n1,2,3,4\n"));
        assert_user_error(
            &s,
            &["analyze", bed.to_str().unwrap(), "--box", "100,100"],
            &["dup.csv:1:", column, "twice", at],
        );
    }
}

#[test]
fn a_summary_of_another_dimension_beside_a_bed_is_refused() {
    let s = Scratch::new();
    s.ok(&words("run --dim 2 --count 5 --out b -q --no-pictures"));
    let text = s
        .read("b/summary.json")
        .replacen("\"dim\": 2", "\"dim\": 3", 1);
    std::fs::write(s.path("b/summary.json"), text).unwrap();
    assert_user_error(
        &s,
        &["analyze", "b/particles.csv", "--out", "a"],
        &["b/summary.json:1: says dim 3", "2D bed", "another bed"],
    );
}

#[test]
fn all_in_a_list_of_measures_is_refused_saying_to_give_it_alone() {
    let s = Scratch::new();
    let bed = s.input("b.csv", "x,y,r\n10,10,10\n40,10,10\n");
    assert_user_error(
        &s,
        &[
            "analyze",
            bed.to_str().unwrap(),
            "--box",
            "100,100",
            "--measures",
            "all,packing",
        ],
        &[
            "`all` cannot be part of a list",
            "give `all` alone",
            "`packing`",
        ],
    );
}

#[cfg(unix)]
#[test]
fn an_output_that_cannot_be_written_names_the_real_problem() {
    let s = Scratch::new();
    let bed = s.input("b.csv", "x,y,r\n10,10,10\n40,10,10\n");
    let b = bed.to_str().unwrap();
    if std::path::Path::new("/proc/self").is_dir() {
        assert_user_error(
            &s,
            &["render", b, "--box", "100,100", "--out", "/proc/x.png"],
            &["--out /proc/x.png", "cannot create a file in it"],
        );
    }
    std::os::unix::fs::symlink("/nonexistent/packbed-dir", s.path("dangling")).unwrap();
    assert_user_error(
        &s,
        &["analyze", b, "--box", "100,100", "--out", "dangling"],
        &["a symbolic link to /nonexistent/packbed-dir, which does not exist"],
    );
}
