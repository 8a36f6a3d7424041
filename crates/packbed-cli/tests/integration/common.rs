//! The harness of the command's tests: run the built `packbed` in a scratch
//! directory and look at what it printed and wrote.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use tempfile::TempDir;

/// The outcome of one `packbed` invocation.
pub struct Outcome {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs the built `packbed` in `dir` with no standard input.
pub fn packbed(dir: &Path, args: &[&str]) -> Outcome {
    let out = Command::new(env!("CARGO_BIN_EXE_packbed"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    outcome(out)
}

/// Exit code and printed text of a finished `packbed`.
fn outcome(out: std::process::Output) -> Outcome {
    Outcome {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// Runs `packbed` in `dir` and insists on success.
pub fn ok(dir: &Path, args: &[&str]) -> Outcome {
    let o = packbed(dir, args);
    assert_eq!(o.code, 0, "{args:?}: {}", o.stderr);
    o
}

/// A scratch directory: `work/` is the current directory of the command (and
/// gains nothing when a run fails), `inputs/` holds configs and tables.
pub struct Scratch {
    _root: TempDir,
    pub work: PathBuf,
    pub inputs: PathBuf,
}

impl Scratch {
    pub fn new() -> Scratch {
        let root = tempfile::tempdir().unwrap();
        let work = root.path().join("work");
        let inputs = root.path().join("inputs");
        std::fs::create_dir(&work).unwrap();
        std::fs::create_dir(&inputs).unwrap();
        Scratch {
            _root: root,
            work,
            inputs,
        }
    }

    /// Writes an input file and returns its path.
    pub fn input(&self, name: &str, text: &str) -> PathBuf {
        let p = self.inputs.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    pub fn packbed(&self, args: &[&str]) -> Outcome {
        packbed(&self.work, args)
    }

    pub fn ok(&self, args: &[&str]) -> Outcome {
        ok(&self.work, args)
    }

    pub fn path(&self, rel: &str) -> PathBuf {
        self.work.join(rel)
    }

    /// A text file under `work/`.
    pub fn read(&self, rel: &str) -> String {
        std::fs::read_to_string(self.path(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
    }

    /// Runs `packbed` in `work/`, killing it and failing if it still runs after
    /// `secs` seconds: a guard against a command that would never end.
    pub fn within(&self, args: &[&str], secs: u64) -> Outcome {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_packbed"));
        cmd.args(args);
        run_within(cmd, self, args, secs)
    }

    /// [`Scratch::ok`] with the environment variable `key` set to `value`.
    pub fn ok_with(&self, key: &str, value: &str, args: &[&str]) -> Outcome {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_packbed"));
        cmd.args(args).env(key, value);
        let o = run_within(cmd, self, args, 300);
        assert_eq!(o.code, 0, "{args:?}: {}", o.stderr);
        o
    }

    /// The `summary.json` of the output directory `work/<out>`.
    pub fn summary(&self, out: &str) -> serde_json::Value {
        serde_json::from_str(&self.read(&format!("{out}/summary.json"))).unwrap()
    }

    /// Any file under `work/`.
    pub fn bytes(&self, rel: &str) -> Vec<u8> {
        std::fs::read(self.path(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
    }

    /// Names in `work/`, sorted: a failed run must not change them.
    pub fn entries(&self) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(&self.work)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
}

/// Exit code 2, one line `packbed: error: …` containing every needle, no panic,
/// nothing on stdout, and nothing new under `work/`.
pub fn assert_user_error(s: &Scratch, args: &[&str], needles: &[&str]) {
    let before = s.entries();
    let o = s.packbed(args);
    assert_eq!(o.code, 2, "{args:?}: exit code; stderr: {}", o.stderr);
    let lines: Vec<&str> = o.stderr.lines().collect();
    assert_eq!(
        lines.len(),
        1,
        "{args:?}: one line expected, got:\n{}",
        o.stderr
    );
    assert!(lines[0].starts_with("packbed: error: "), "{}", lines[0]);
    for n in needles {
        assert!(lines[0].contains(n), "{args:?}: `{n}` not in: {}", lines[0]);
    }
    assert!(!o.stderr.contains("panicked"), "{}", o.stderr);
    assert!(o.stdout.is_empty(), "{args:?}: stdout: {}", o.stdout);
    assert_eq!(s.entries(), before, "{args:?} left files");
}

/// The arguments of a command line written as one string, split at white
/// space (for arguments without spaces of their own).
pub fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// Fails with the whole `haystack` on screen when it lacks `needle`.
#[track_caller]
pub fn assert_contains(haystack: &str, needle: &str) {
    assert!(haystack.contains(needle), "`{needle}` not in:\n{haystack}");
}

/// Writes the config `name` into `inputs/` and insists that `packbed run`
/// refuses it as a user error naming every needle.
pub fn assert_config_refused(s: &Scratch, name: &str, text: &str, needles: &[&str]) {
    let c = s.input(name, text);
    assert_user_error(s, &["run", c.to_str().unwrap()], needles);
}

/// Width and height of a PNG, checking its signature.
pub fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

/// The texts of an SVG's `<text>` elements.
pub fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| Some(t.split_once('>')?.1.split('<').next()?.to_string()))
        .collect()
}

/// Fast ensemble beds: 2D, radii 20 and 10 in a square of 8 large diameters.
pub const SMALL: &[&str] = &["--dim", "2", "--radii", "20,10", "--box", "diameters=8"];

/// The statistics files every ensemble writes.
pub const STAT_FILES: [&str; 4] = [
    "ensemble.json",
    "ensemble.csv",
    "histograms.csv",
    "ensemble.md",
];

/// [`Scratch::within`] under an address-space limit of `mib` MiB, so that a
/// command asking for tens of gigabytes fails here instead of eating the
/// machine's memory (an allocation beyond the limit aborts it).
pub fn within_memory(s: &Scratch, args: &[&str], secs: u64, mib: u64) -> Outcome {
    let script = format!("ulimit -v {} && exec \"$0\" \"$@\"", mib * 1024);
    let mut full = vec!["-c", &script, env!("CARGO_BIN_EXE_packbed")];
    full.extend_from_slice(args);
    let mut cmd = Command::new("sh");
    cmd.args(&full);
    run_within(cmd, s, args, secs)
}

/// Runs `cmd` in `s`'s work directory with no input, its output captured, and
/// waits for it as [`wait_within`] does.
fn run_within(mut cmd: Command, s: &Scratch, args: &[&str], secs: u64) -> Outcome {
    let child = cmd
        .current_dir(&s.work)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_within(child, args, secs)
}

/// Waits for `child`, killing it and failing if it still runs after `secs`.
fn wait_within(mut child: std::process::Child, args: &[&str], secs: u64) -> Outcome {
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() >= secs {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} still running after {secs} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    outcome(child.wait_with_output().unwrap())
}
