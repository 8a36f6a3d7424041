//! `packbed slurm` on a real single-node Slurm, started on this machine by
//! `scripts/slurm-test-cluster.sh` (root, Debian's `slurm-wlm` and `munge`).
//! Where it cannot be started the test says why and is skipped, unless
//! `PACKBED_REQUIRE_SLURM=1` (as in `.ci/run`), which makes that a failure.
//!
//! Every `packbed slurm ... --submit --wait` result is compared byte for byte
//! with `packbed ensemble` of the same settings: a plain ensemble, a sweep,
//! and an ensemble whose task was cancelled mid-run and then resubmitted;
//! and a filtration sweep over pressures (its scripts also run by hand, where
//! no Slurm is needed).

use crate::common::{packbed, Scratch, SMALL, STAT_FILES};
use crate::filtration_studies::small_filtration;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The cluster's `SLURM_CONF`, or `None` (test skipped) when Slurm cannot run here.
fn cluster() -> Option<String> {
    let required = std::env::var("PACKBED_REQUIRE_SLURM").is_ok_and(|v| v == "1");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/slurm-test-cluster.sh");
    let out = Command::new("bash")
        .arg(&script)
        .stdin(Stdio::null())
        .output()
        .expect("bash runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(0) => {
            let stdout = String::from_utf8_lossy(&out.stdout);
            let conf = stdout
                .lines()
                .rev()
                .find_map(|l| l.strip_prefix("SLURM_CONF="))
                .expect("the script names SLURM_CONF");
            Some(conf.to_string())
        }
        // 3: no root or no packages; 1: the daemons did not come up.
        Some(_) if !required => {
            eprintln!(
                "SKIP: slurm test: {} (set PACKBED_REQUIRE_SLURM=1 to make this a failure)",
                stderr.trim()
            );
            None
        }
        _ => panic!(
            "cannot start Slurm ({}{}):\n{stderr}",
            script.display(),
            if required {
                "; PACKBED_REQUIRE_SLURM=1 makes that a failure"
            } else {
                ""
            }
        ),
    }
}

/// A Slurm client command (`squeue`, `scancel`) for the test cluster.
fn client(conf: &str, program: &str, args: &[&str]) -> Output {
    Command::new(program)
        .args(args)
        .env("SLURM_CONF", conf)
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

/// `packbed` with the test cluster's `SLURM_CONF`.
fn packbed_cmd(conf: &str, dir: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_packbed"));
    c.args(args)
        .current_dir(dir)
        .env("SLURM_CONF", conf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

fn run_ok(conf: &str, dir: &Path, args: &[&str]) -> String {
    let start = Instant::now();
    let out = packbed_cmd(conf, dir, args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{args:?}: {:?}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!(
        "slurm test: {:?} took {:.1} s",
        args.first(),
        start.elapsed().as_secs_f64()
    );
    stdout
}

fn cat<'a>(parts: &[&[&'a str]]) -> Vec<&'a str> {
    parts.iter().flat_map(|p| p.iter().copied()).collect()
}

/// Runs the sweep `config` (two replicates) locally and as two Slurm tasks,
/// into `{tag}-local` and `{tag}-cl`: the same sweep statistics.
fn sweep_same_on_cluster(conf: &str, work: &Path, config: &Path, tag: &str) {
    let config = config.to_str().unwrap();
    let (local, cluster) = (format!("{tag}-local"), format!("{tag}-cl"));
    run_ok(
        conf,
        work,
        &["ensemble", config, "--runs", "2", "--out", &local, "-q"],
    );
    run_ok(
        conf,
        work,
        &[
            "slurm", config, "--runs", "2", "--tasks", "2", "--out", &cluster, "--submit", "--wait",
        ],
    );
    assert_same(
        &work.join(local),
        &work.join(cluster),
        &["sweep.csv", "sweep.md"],
    );
}

fn assert_same(a: &Path, b: &Path, files: &[&str]) {
    for f in files {
        let (x, y) = (a.join(f), b.join(f));
        let bx = std::fs::read(&x).unwrap_or_else(|e| panic!("{}: {e}", x.display()));
        let by = std::fs::read(&y).unwrap_or_else(|e| panic!("{}: {e}", y.display()));
        assert!(bx == by, "{} and {} differ", x.display(), y.display());
    }
}

/// Waits for `cond` up to `limit`, polling every 0.2 s.
fn wait_for(limit: Duration, what: &str, mut cond: impl FnMut() -> bool) {
    let start = Instant::now();
    while !cond() {
        assert!(start.elapsed() < limit, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// Whether this user has no jobs in the queue.
fn queue_empty(conf: &str) -> impl FnMut() -> bool + '_ {
    move || {
        let q = client(conf, "squeue", &["-h", "--me", "-o", "%i"]);
        q.status.success() && q.stdout.iter().all(|b| b.is_ascii_whitespace())
    }
}

fn finish(child: Child) -> (i32, String, String) {
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn slurm_ensembles_equal_local_ones() {
    let Some(conf) = cluster() else {
        return;
    };
    let s = Scratch::new();
    let work = s.work.clone();

    // 1. A plain ensemble: 6 replicates in 3 array tasks.
    let local = work.join("local");
    run_ok(
        &conf,
        &work,
        &cat(&[
            &["ensemble"],
            SMALL,
            &["--runs", "6", "--out", "local", "-q"],
        ]),
    );
    let out = run_ok(
        &conf,
        &work,
        &cat(&[
            &["slurm"],
            SMALL,
            &[
                "--runs", "6", "--tasks", "3", "--out", "cl", "--time", "10:00",
            ],
            &["--submit", "--wait"],
        ]),
    );
    assert!(out.contains("submitted array job"), "{out}");
    let cl = work.join("cl");
    assert_same(&local, &cl, &STAT_FILES);
    for k in 0..3 {
        assert!(cl.join(format!("shards/{k}/manifest.json")).exists());
        assert_eq!(s.read(&format!("cl/logs/task-{k}.status")).trim(), "0");
    }
    let script = s.read("cl/array.sh");
    assert!(script.contains("#SBATCH --array=0-2\n"), "{script}");
    assert!(script.contains("#SBATCH --time=10:00\n"), "{script}");

    // 2. A sweep: every value's replicates sharded; sweep.csv and every
    // value's statistics the same as a local run's.
    let sweep = s.input(
        "sweep.toml",
        "dim = 2\n[box]\ndiameters = 6\n[[species]]\nradius = 20\n[[species]]\nradius = 10\n[sweep]\nparameter = \"ratio\"\nvalues = [[1, 1], [1, 2]]\n",
    );
    let sweep = sweep.to_str().unwrap();
    run_ok(
        &conf,
        &work,
        &["ensemble", sweep, "--runs", "4", "--out", "sw-local", "-q"],
    );
    run_ok(
        &conf,
        &work,
        &[
            "slurm", sweep, "--runs", "4", "--tasks", "2", "--out", "sw-cl", "--submit", "--wait",
        ],
    );
    assert_same(
        &work.join("sw-local"),
        &work.join("sw-cl"),
        &["sweep.csv", "sweep.md"],
    );
    let values: Vec<PathBuf> = std::fs::read_dir(work.join("sw-local/sweep"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(values.len(), 2);
    for v in values {
        let name = v.file_name().unwrap();
        assert_same(&v, &work.join("sw-cl/sweep").join(name), &STAT_FILES);
    }

    // 2b. A sweep over a settling rule's parameter (the momentum rule's
    // restitution, with sliding friction; the fitted cohesion law) gives the
    // same statistics on the cluster as locally.
    let settle = s.input(
        "settle.toml",
        "dim = 3\n[box]\nwidth = 12\ndepth = 12\nheight = 400\nperiodic = true\n[fill]\ncount = 300\n\
         [[species]]\nradius = 1\n[settling]\nrestitution = 0.2\nsliding_friction = 0.3\n\
         cohesion_diameter = 1\ncohesion_exponent = 0.7\n\
         [sweep]\nparameter = \"settling.restitution\"\nvalues = [0.2, 0.6]\n",
    );
    sweep_same_on_cluster(&conf, &work, &settle, "st");

    // 2c. A sweep over compaction steps (the compaction's wall time is left
    // out of the statistics, which are the same bytes on any machine).
    let compact = s.input(
        "compact.toml",
        "dim = 2\n[box]\nwidth = 12.3\nheight = 400\nperiodic = true\n[fill]\ncount = 150\n\
         base_layer = \"none\"\n[[species]]\nradius = 0.5\n\
         [sweep]\nparameter = \"compaction.steps\"\nvalues = [0, 40]\n",
    );
    sweep_same_on_cluster(&conf, &work, &compact, "cp");

    // 3. A task cancelled mid-run: `--wait` names it and its log, exits 1,
    // and cancels the merge that can no longer run; the same command again
    // resumes, and the result equals the local one.
    let long: &[&str] = &[
        "--dim",
        "2",
        "--radii",
        "20,10",
        "--box",
        "diameters=400",
        "--runs",
        "8",
    ];
    run_ok(
        &conf,
        &work,
        &cat(&[&["ensemble"], long, &["--out", "long-local", "-q"]]),
    );
    let slurm_args = cat(&[&["slurm"], long, &["--tasks", "2", "--out", "long-cl"]]);
    let child = packbed_cmd(&conf, &work, &cat(&[&slurm_args, &["--submit", "--wait"]]))
        .spawn()
        .unwrap();
    let shard1 = work.join("long-cl/shards/1/runs");
    let done_in_shard1 = || {
        std::fs::read_dir(&shard1)
            .map(|d| {
                d.flatten()
                    .filter(|e| e.path().join("summary.json").exists())
                    .count()
            })
            .unwrap_or(0)
    };
    // Task 1 has replicates 1, 3, 5, 7: cancel it once the first is done.
    wait_for(Duration::from_secs(120), "task 1's first replicate", || {
        done_in_shard1() >= 1
    });
    let q = client(&conf, "squeue", &["-h", "--me", "-o", "%i|%T"]);
    let q = String::from_utf8_lossy(&q.stdout).into_owned();
    let task1 = q
        .lines()
        .filter_map(|l| l.split_once('|'))
        .find(|(id, st)| id.ends_with("_1") && *st == "RUNNING")
        .map(|(id, _)| id.to_string())
        .unwrap_or_else(|| panic!("task 1 is not running: {q}"));
    let cancelled_after = done_in_shard1();
    assert!(
        cancelled_after < 4,
        "task 1 finished before it could be cancelled"
    );
    let c = client(&conf, "scancel", &[&task1]);
    assert!(c.status.success(), "scancel {task1}");
    let (code, stdout, stderr) = finish(child);
    eprintln!(
        "slurm test: after scancel {task1}, --wait said: {}",
        stderr.trim()
    );
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(
        stderr.contains("task 1 did not finish") || stderr.contains("task 1 failed"),
        "{stderr}"
    );
    assert!(stderr.contains("logs/task-1.out"), "{stderr}");
    assert!(!stderr.contains("task 0 "), "{stderr}");
    assert!(!work.join("long-cl/ensemble.csv").exists());
    // The merge, which could never run, is cancelled (Slurm may take a
    // moment to drop it from the queue).
    wait_for(
        Duration::from_secs(30),
        "an empty queue",
        queue_empty(&conf),
    );
    // The resubmission resumes the replicates task 1 finished; a second
    // submission while its jobs are in the queue is refused.
    let out = run_ok(&conf, &work, &cat(&[&slurm_args, &["--submit"]]));
    assert!(out.contains("resuming"), "{out}");
    let again = packbed_cmd(&conf, &work, &cat(&[&slurm_args, &["--submit"]]))
        .output()
        .unwrap();
    let again_err = String::from_utf8_lossy(&again.stderr);
    assert_eq!(again.status.code(), Some(2), "{again_err}");
    assert!(again_err.contains("still queued or running"), "{again_err}");
    wait_for(
        Duration::from_secs(180),
        "the resubmitted jobs",
        queue_empty(&conf),
    );
    let log = s.read("long-cl/logs/task-1.out");
    eprintln!(
        "slurm test: task 1 cancelled after {cancelled_after} replicates; resubmitted log:\n{log}"
    );
    assert!(
        log.contains(" resumed") && !log.contains(" 0 resumed"),
        "{log}"
    );
    assert_eq!(s.read("long-cl/logs/merge.status").trim(), "0");
    // And once more with --wait: nothing left to build, the same files.
    run_ok(&conf, &work, &cat(&[&slurm_args, &["--submit", "--wait"]]));
    assert_same(&work.join("long-local"), &work.join("long-cl"), &STAT_FILES);
}

#[test]
fn slurm_writes_scripts_and_refuses_bad_requests() {
    let s = Scratch::new();
    // No Slurm needed: these fail before anything is submitted or written.
    let o = packbed(
        &s.work,
        &cat(&[
            &["slurm"],
            SMALL,
            &["--runs", "2", "--tasks", "3", "--out", "x"],
        ]),
    );
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(
        o.stderr.contains("--tasks") && o.stderr.contains("3 tasks for 2 replicates"),
        "{}",
        o.stderr
    );
    assert_eq!(o.stderr.lines().count(), 1, "{}", o.stderr);
    assert!(!s.path("x").exists());
    let o = packbed(
        &s.work,
        &cat(&[
            &["slurm"],
            SMALL,
            &["--runs", "2", "--tasks", "0", "--out", "x"],
        ]),
    );
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(!s.path("x").exists());
    // sbatch missing: an empty PATH.
    let out = Command::new(env!("CARGO_BIN_EXE_packbed"))
        .args(cat(&[
            &["slurm"],
            SMALL,
            &["--runs", "2", "--tasks", "2", "--out", "x", "--submit"],
        ]))
        .current_dir(&s.work)
        .env("PATH", "")
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("sbatch is not on PATH"), "{stderr}");
    assert!(!s.path("x").exists());
    // An output directory that cannot be made.
    std::fs::write(s.path("file"), "x").unwrap();
    let o = packbed(
        &s.work,
        &cat(&[
            &["slurm"],
            SMALL,
            &["--runs", "2", "--tasks", "2", "--out", "file/sub"],
        ]),
    );
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("file"), "{}", o.stderr);
    // Without --submit: the scripts, which bash accepts, and how to submit them.
    let o = s.ok(&cat(&[
        &["slurm"],
        SMALL,
        &[
            "--runs",
            "4",
            "--tasks",
            "2",
            "--out",
            "plan",
            "--partition",
            "short",
            "--mem",
            "2G",
        ],
        &[
            "--account",
            "a1",
            "--cpus-per-task",
            "2",
            "--time",
            "0:30:00",
            "--sbatch-arg=--qos=low",
        ],
    ]));
    assert!(
        o.stdout.contains("sbatch --dependency=afterok:"),
        "{}",
        o.stdout
    );
    for f in ["array.sh", "merge.sh"] {
        let st = Command::new("bash")
            .arg("-n")
            .arg(s.path(&format!("plan/{f}")))
            .status()
            .unwrap();
        assert!(st.success(), "bash -n {f}");
    }
    let a = s.read("plan/array.sh");
    for d in [
        "--array=0-1",
        "--partition=short",
        "--mem=2G",
        "--account=a1",
        "--cpus-per-task=2",
        "--time=0:30:00",
        "--qos=low",
    ] {
        assert!(a.contains(&format!("#SBATCH {d}\n")), "{d} missing:\n{a}");
    }
    let m = s.read("plan/merge.sh");
    for d in [
        "--partition=short",
        "--mem=2G",
        "--account=a1",
        "--time=0:30:00",
        "--qos=low",
    ] {
        assert!(m.contains(&format!("#SBATCH {d}\n")), "{d} missing:\n{m}");
    }
    assert!(s.path("plan/config.toml").exists());
    // Another config into the same directory is refused; another task count too.
    let o = packbed(
        &s.work,
        &cat(&[
            &["slurm"],
            SMALL,
            &[
                "--seed", "5", "--runs", "4", "--tasks", "2", "--out", "plan",
            ],
        ]),
    );
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("different config"), "{}", o.stderr);
    let o = packbed(
        &s.work,
        &cat(&[
            &["slurm"],
            SMALL,
            &["--runs", "4", "--tasks", "4", "--out", "plan"],
        ]),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    std::fs::create_dir_all(s.path("plan/shards/0")).unwrap();
    s.ok(&cat(&[
        &["ensemble"],
        &[
            "plan/config.toml",
            "--shard",
            "0/4",
            "--out",
            "plan/shards/0",
            "-q",
        ],
    ]));
    let o = packbed(
        &s.work,
        &cat(&[
            &["slurm"],
            SMALL,
            &["--runs", "4", "--tasks", "2", "--out", "plan"],
        ]),
    );
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("shards of 4 tasks"), "{}", o.stderr);
    // A PSD table relative to the config file: config.toml names it by its
    // absolute path, so that the tasks find it from DIR.
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let psd = std::fs::read_to_string(examples.join("psd.csv")).unwrap();
    s.input("psd.csv", &psd);
    s.input(
        "psd.toml",
        "dim = 2\n[fill]\ncount = 50\n[[species]]\nsize = { table = \"psd.csv\" }\n",
    );
    s.ok(&[
        "slurm",
        "../inputs/psd.toml",
        "--runs",
        "2",
        "--tasks",
        "2",
        "--out",
        "psd",
    ]);
    let toml = s.read("psd/config.toml");
    let table = s.inputs.join("psd.csv").canonicalize().unwrap();
    let named = toml
        .lines()
        .find_map(|l| l.trim().strip_prefix("table = "))
        .unwrap_or_else(|| panic!("no table in\n{toml}"));
    assert_eq!(
        Path::new(named.trim_matches('"')).canonicalize().unwrap(),
        table,
        "{toml}"
    );
    // A task runs it from anywhere.
    let elsewhere = s.inputs.clone();
    let dir = s.path("psd");
    let config = dir.join("config.toml");
    let shard = dir.join("shards/1");
    crate::common::ok(
        &elsewhere,
        &[
            "ensemble",
            config.to_str().unwrap(),
            "--shard",
            "1/2",
            "--out",
            shard.to_str().unwrap(),
            "-q",
        ],
    );
}

#[test]
fn an_out_with_blanks_relative_or_not_is_quoted_in_the_scripts() {
    let s = Scratch::new();
    let o = s.ok(&cat(&[
        &["slurm"],
        SMALL,
        &["--runs", "2", "--tasks", "2", "--out", "my runs/cake #1"],
    ]));
    assert!(o.stdout.contains("sbatch"), "{}", o.stdout);
    let dir = s.path("my runs/cake #1");
    let shown = dir.to_str().unwrap();
    let a = s.read("my runs/cake #1/array.sh");
    assert!(
        a.contains(&format!(
            "#SBATCH --output=\"{}/logs/task-%a.out\"\n",
            shown.replace('#', "\\#")
        )),
        "{a}"
    );
    assert!(a.contains(&format!("DIR='{shown}'\n")), "{a}");
    let m = s.read("my runs/cake #1/merge.sh");
    assert!(m.contains("/logs/merge.out\"\n"), "{m}");
    for f in ["array.sh", "merge.sh"] {
        let st = Command::new("bash")
            .arg("-n")
            .arg(dir.join(f))
            .status()
            .unwrap();
        assert!(st.success(), "bash -n {f}");
    }
}

/// What `packbed slurm` prints to paste into a shell, and what its scripts
/// set, quotes every path: an `--out` holding `$(…)` and `;` runs nothing
/// when the printed `sbatch` lines are pasted, and they hand `sbatch` the
/// script's path intact.
#[test]
fn printed_submit_lines_and_script_paths_are_quoted_for_the_shell() {
    let s = Scratch::new();
    let out = "o$(touch X);x 'q'";
    let o = s.ok(&cat(&[
        &["slurm"],
        SMALL,
        &["--runs", "2", "--tasks", "1", "--out", out],
    ]));
    let dir = s.path(out);
    // A fake sbatch that writes its arguments, one a line.
    let bin = s.inputs.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let fake = bin.join("sbatch");
    std::fs::write(&fake, "#!/bin/sh\nprintf '%s\\n' \"$@\" >> \"$ARGS\"\n").unwrap();
    Command::new("chmod").arg("+x").arg(&fake).status().unwrap();
    let args_file = s.inputs.join("args");
    let lines: Vec<&str> = o
        .stdout
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("sbatch "))
        .collect();
    assert_eq!(lines.len(), 2, "{}", o.stdout);
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap());
    for line in &lines {
        let st = Command::new("sh")
            .args(["-c", line])
            .current_dir(&s.work)
            .env("PATH", &path)
            .env("ARGS", &args_file)
            .status()
            .unwrap();
        assert!(st.success(), "sh -c {line}");
    }
    assert!(!s.path("X").exists(), "a pasted line ran `touch X`");
    let got = std::fs::read_to_string(&args_file).unwrap();
    let want = format!(
        "{}\n--dependency=afterok:ARRAY_JOB_ID\n{}\n",
        dir.join("array.sh").display(),
        dir.join("merge.sh").display()
    );
    assert_eq!(got, want);
    // The scripts: valid shell, and DIR= and PACKBED= give the paths back.
    for f in ["array.sh", "merge.sh"] {
        let script = std::fs::read_to_string(dir.join(f)).unwrap();
        let st = Command::new("sh")
            .arg("-n")
            .arg(dir.join(f))
            .status()
            .unwrap();
        assert!(st.success(), "sh -n {f}");
        let assign: Vec<&str> = script
            .lines()
            .filter(|l| l.starts_with("DIR=") || l.starts_with("PACKBED="))
            .collect();
        assert_eq!(assign.len(), 2, "{script}");
        let shown = Command::new("sh")
            .args([
                "-c",
                &format!(
                    "{}\n{}\nprintf '%s\\n%s' \"$DIR\" \"$PACKBED\"",
                    assign[0], assign[1]
                ),
            ])
            .current_dir(&s.work)
            .output()
            .unwrap();
        assert_eq!(
            String::from_utf8(shown.stdout).unwrap(),
            format!("{}\n{}", dir.display(), env!("CARGO_BIN_EXE_packbed"))
        );
        assert!(!s.path("X").exists(), "{f}: sourcing DIR= ran `touch X`");
    }
}

/// The drying's settings and a sweep over them reach the array tasks: the
/// scripts, run by hand here (no Slurm needed), give the local ensemble's
/// agglomeration, value by value.
/// Runs `plan/array.sh` for each of its `tasks` and then `plan/merge.sh`,
/// as Slurm would, without a cluster.
fn run_scripts_by_hand(s: &Scratch, tasks: usize) {
    let bash = |script: &str, task: Option<usize>| {
        let mut c = Command::new("bash");
        c.arg(s.path(script))
            .current_dir(&s.work)
            .stdin(Stdio::null());
        if let Some(k) = task {
            c.env("SLURM_ARRAY_TASK_ID", k.to_string());
        }
        c.status().unwrap()
    };
    for k in 0..tasks {
        assert!(bash("plan/array.sh", Some(k)).success(), "task {k}");
    }
    assert!(bash("plan/merge.sh", None).success(), "merge");
}

#[test]
fn a_drying_sweep_through_the_scripts_equals_the_local_ensemble() {
    let s = Scratch::new();
    let sweep = s.input(
        "dry.toml",
        "dim = 3\nseed = 3\n[box]\nwidth = 8\ndepth = 8\nheight = 40\nperiodic = true\n\
         [fill]\ncount = 300\n[[species]]\nradius = 1\n\
         [analysis]\nmeasures = [\"agglomeration\"]\nlength_unit = \"um\"\n\
         [analysis.drying]\nsolubility = 50\nmin_neck = 0.08\n\
         [sweep]\nparameter = \"analysis.drying.concentration\"\nvalues = [50, 0.05]\n",
    );
    let sweep = sweep.to_str().unwrap();
    s.ok(&["ensemble", sweep, "--runs", "2", "--out", "local", "-q"]);
    s.ok(&[
        "slurm", sweep, "--runs", "2", "--tasks", "2", "--out", "plan",
    ]);
    let config = s.read("plan/config.toml");
    for needle in [
        "\"agglomeration\"",
        "[analysis.drying]",
        "min_neck = 0.08",
        "parameter = \"analysis.drying.concentration\"",
    ] {
        assert!(config.contains(needle), "{needle} not in:\n{config}");
    }
    run_scripts_by_hand(&s, 2);
    let (local, plan) = (s.path("local"), s.path("plan"));
    assert_same(&local, &plan, &["sweep.csv", "sweep.md"]);
    let csv = s.read("plan/sweep.csv");
    assert!(
        csv.contains(",agglomeration.bonds_per_particle,2,"),
        "{csv}"
    );
    for value in ["00-concentration-50", "01-concentration-0.05"] {
        let dir = format!("sweep/{value}");
        assert_same(&local.join(&dir), &plan.join(&dir), &STAT_FILES);
    }
}

/// A filtration sweep over pressures through `packbed slurm`'s scripts,
/// in `dir` under `s`: the config it records, its tasks and merge.
fn filtration_sweep(s: &Scratch) -> String {
    let sweep = "[sweep]\nparameter = \"filtration.pressure\"\nvalues = [1e5, 2e5]\n";
    let cfg = s.input("filter.toml", &small_filtration("um", 80, sweep));
    let cfg = cfg.to_str().unwrap().to_string();
    s.ok(&["ensemble", &cfg, "--runs", "2", "--out", "local", "-q"]);
    cfg
}

/// The filtration's statistics of a Slurm directory equal the local ones,
/// and carry its figures.
fn assert_filtration_same(s: &Scratch, plan: &str) {
    let (local, plan) = (s.path("local"), s.path(plan));
    assert_same(&local, &plan, &["sweep.csv", "sweep.md"]);
    for value in ["00-pressure-100000", "01-pressure-200000"] {
        let dir = format!("sweep/{value}");
        assert_same(&local.join(&dir), &plan.join(&dir), &STAT_FILES);
    }
    let csv = std::fs::read_to_string(plan.join("sweep.csv")).unwrap();
    for key in [
        "filtration.alpha_fit_m_per_kg",
        "filtration.r_medium_fit_per_m",
        "filtration.final.time_s",
        "capture.passed_fraction",
    ] {
        assert!(csv.contains(&format!(",{key},2,")), "{key} not in\n{csv}");
    }
    let md = std::fs::read_to_string(plan.join("sweep/01-pressure-200000/ensemble.md")).unwrap();
    assert!(
        md.contains("| m/kg | filtration.alpha_fit_m_per_kg |"),
        "{md}"
    );
}

/// A filtration (a medium feed, `[filtration]`, a sweep over pressures)
/// reaches the array tasks: the scripts, run by hand here (no Slurm
/// needed), give the local ensemble's filtration tables.
#[test]
fn a_filtration_sweep_through_the_scripts_equals_the_local_ensemble() {
    let s = Scratch::new();
    let cfg = filtration_sweep(&s);
    s.ok(&[
        "slurm", &cfg, "--runs", "2", "--tasks", "2", "--out", "plan",
    ]);
    let config = s.read("plan/config.toml");
    for needle in [
        "medium = true",
        "[filtration]",
        "parameter = \"filtration.pressure\"",
    ] {
        assert!(config.contains(needle), "{needle} not in:\n{config}");
    }
    let script = s.read("plan/array.sh");
    assert!(script.contains("#SBATCH --array=0-1\n"), "{script}");
    run_scripts_by_hand(&s, 2);
    assert_filtration_same(&s, "plan");
}

/// The same filtration sweep submitted to the real cluster: its merged
/// tables are the local ones, byte for byte.
#[test]
fn slurm_filtration_sweep_equals_local() {
    let Some(conf) = cluster() else {
        return;
    };
    let s = Scratch::new();
    let cfg = filtration_sweep(&s);
    let out = run_ok(
        &conf,
        &s.work,
        &[
            "slurm", &cfg, "--runs", "2", "--tasks", "2", "--out", "cl", "--submit", "--wait",
        ],
    );
    assert!(out.contains("submitted array job"), "{out}");
    for k in 0..2 {
        assert_eq!(s.read(&format!("cl/logs/task-{k}.status")).trim(), "0");
    }
    assert_filtration_same(&s, "cl");
}
