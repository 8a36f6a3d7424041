//! Ensembles on a Slurm cluster: a job array of shards and a merge job.
//!
//! `packbed slurm` writes into its output directory `DIR`:
//! - `config.toml`: the resolved config (file and command-line overrides),
//!   the one every task runs;
//! - `array.sh`: the job array; task `K` runs
//!   `packbed ensemble DIR/config.toml --runs N --shard K/M --out DIR/shards/K`;
//! - `merge.sh`: `packbed merge DIR/shards/* --out DIR`, submitted to run after
//!   every task succeeded (`--dependency=afterok:ARRAY`);
//! - `logs/task-K.out`, `logs/merge.out`: what the jobs printed, and
//!   `logs/task-K.status`, `logs/merge.status`: their exit codes, written by
//!   the scripts themselves, so that waiting for the jobs needs no Slurm
//!   accounting (`sacct`), only `squeue`;
//! - `manifest.json`: the manifest of the whole ensemble, written before any
//!   job runs, so that the merge may write into `DIR` and a resubmission with
//!   another config is refused up front.
//!
//! Resubmitting into `DIR` resumes: every task resumes its shard (the
//! replicates done are skipped, [`super::run`]) and the merge joins them.
//! Script text, job-id parsing and the checks are pure functions here; running
//! `sbatch`, `squeue` and `scancel` is in `jobs` (re-exported here).

mod jobs;

pub use jobs::*;

use super::manifest::{check_out, config_key, write_manifest, Manifest, MANIFEST};
use super::Shard;
use crate::config::{Config, EnsembleConfig, SizeConfig};
use crate::error::{Error, Result};
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

/// The resolved config the tasks run.
pub(crate) const CONFIG_FILE: &str = "config.toml";
/// The job-array script.
pub(crate) const ARRAY_SCRIPT: &str = "array.sh";
/// The merge script.
pub(crate) const MERGE_SCRIPT: &str = "merge.sh";
/// Directory of the shards' output directories (`shards/K`).
pub(crate) const SHARDS_DIR: &str = "shards";
/// Directory of the jobs' logs and exit statuses.
pub(crate) const LOGS_DIR: &str = "logs";

/// Options of `sbatch` the scripts carry: those of `packbed slurm`, which
/// the array and the merge share (the merge takes one CPU). With the `cli`
/// feature these are the command's options, their documentation its help.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct Resources {
    /// Slurm partition (`sbatch --partition`).
    #[cfg_attr(feature = "cli", arg(long, value_name = "P"))]
    pub partition: Option<String>,
    /// Time limit of each job (`sbatch --time`), e.g. 1:00:00.
    #[cfg_attr(feature = "cli", arg(long, value_name = "T"))]
    pub time: Option<String>,
    /// CPUs of each array task (its `--jobs`); default 1.
    #[cfg_attr(feature = "cli", arg(long, value_name = "C", allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..)))]
    pub cpus_per_task: Option<u32>,
    /// Memory of each job (`sbatch --mem`), e.g. 4G.
    #[cfg_attr(feature = "cli", arg(long, value_name = "MEM"))]
    pub mem: Option<String>,
    /// Account to charge (`sbatch --account`).
    #[cfg_attr(feature = "cli", arg(long, value_name = "A"))]
    pub account: Option<String>,
    /// A further sbatch option for both jobs, e.g. --sbatch-arg=--qos=short (repeatable).
    #[cfg_attr(
        feature = "cli",
        arg(long = "sbatch-arg", value_name = "ARG", allow_hyphen_values = true)
    )]
    pub extra: Vec<String>,
}

/// What `packbed slurm` arranges: everything the scripts are made of.
#[derive(Clone, Debug)]
pub struct JobArray {
    /// Absolute path of the `packbed` binary the jobs run.
    pub binary: PathBuf,
    /// Absolute output directory `DIR`.
    pub out: PathBuf,
    /// Replicates (per sweep value).
    pub runs: u64,
    /// Array tasks `M` (shards), `1 <= M <= runs`.
    pub tasks: u64,
    /// The `sbatch` options.
    pub resources: Resources,
}

/// The `sbatch` options the scripts set themselves.
const OWN_OPTIONS: [&str; 7] = [
    "--array",
    "--output",
    "--error",
    "--dependency",
    "--parsable",
    "--wait",
    "--job-name",
];

/// `text` as one shell word: single-quoted, a `'` as `'\''`.
pub(crate) fn shell_quote(text: &str) -> String {
    let safe = !text.is_empty()
        && text
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"/._-+=:,@%".contains(&b));
    if safe {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// A path as one shell word ([`shell_quote`]), for a command a user pastes.
pub(crate) fn shell_path(path: &Path) -> String {
    shell_quote(&path.to_string_lossy())
}

/// `text` as one argument of an `#SBATCH` line: sbatch splits those lines at
/// blanks outside quotes, drops quotes, reads `\` as an escape and an
/// unescaped `#` as the start of a comment (its `_get_argument`), so a word
/// with any of these is double-quoted and those escaped.
pub(crate) fn sbatch_word(text: &str) -> String {
    if !text.contains(|c: char| c.is_whitespace() || "\"'\\#".contains(c)) {
        return text.to_string();
    }
    let mut out = String::from("\"");
    for c in text.chars() {
        if "\"\\#".contains(c) {
            out.push('\\');
        }
        out.push(c);
    }
    out.push('"');
    out
}

/// A value that may stand in an `#SBATCH` line: Slurm reads `%` in file names
/// as a pattern (`%a` the task index), a line ends at a control character,
/// and values other than the directory (`quoted`) are written unquoted, so
/// may not hold blanks or quotes.
fn check_directive(setting: &'static str, value: &str, percent: bool, quoted: bool) -> Result<()> {
    let bad = value.chars().find(|&c| {
        c.is_control()
            || (!quoted && (c.is_whitespace() || "\"'\\".contains(c)))
            || (!percent && c == '%')
    });
    match bad {
        Some(c) => Err(Error::setting(
            setting,
            format!(
                "`{}` holds {}, which an #SBATCH line of a job script cannot carry",
                crate::error::echo(value),
                match c {
                    ' ' => "a blank".to_string(),
                    '%' => "`%` (a Slurm file-name pattern)".to_string(),
                    c if c.is_control() || c.is_whitespace() => "a control character".to_string(),
                    c => format!("`{c}`"),
                }
            ),
        )),
        None if value.is_empty() => Err(Error::setting(setting, "must not be empty")),
        None => Ok(()),
    }
}

impl JobArray {
    /// The plan of jobs that run this very binary, writing into `out` (made
    /// absolute: the jobs start elsewhere).
    pub fn for_this_binary(
        out: &Path,
        runs: u64,
        tasks: u64,
        resources: Resources,
    ) -> Result<JobArray> {
        let io = |path: &Path, source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let out = std::path::absolute(out).map_err(|e| io(out, e))?;
        let exe = std::env::current_exe().map_err(|e| io(Path::new("the packbed binary"), e))?;
        let binary = exe.canonicalize().map_err(|e| io(&exe, e))?;
        Ok(JobArray {
            binary,
            out,
            runs,
            tasks,
            resources,
        })
    }

    /// A note when `out` is on a file system usually local to each node.
    pub fn local_dir_note(&self) -> Option<String> {
        (self.out.starts_with("/tmp") || self.out.starts_with("/dev/shm")).then(|| {
            format!(
                "{} is usually local to each node; on a cluster of several nodes put --out on a \
                 shared file system",
                crate::error::inert_path(&self.out)
            )
        })
    }

    /// Checks the plan: `1 <= tasks <= runs`, an absolute `DIR` that
    /// `#SBATCH --output` can name, resource values that fit `#SBATCH` lines.
    pub(crate) fn check(&self) -> Result<()> {
        super::check_runs(self.runs)?;
        if self.tasks == 0 {
            return Err(Error::setting("tasks", "must be at least 1"));
        }
        if self.tasks > self.runs {
            return Err(Error::setting(
                "tasks",
                format!(
                    "{} tasks for {} replicates: every task needs at least one replicate; use --tasks {} or fewer",
                    self.tasks, self.runs, self.runs
                ),
            ));
        }
        if !self.out.is_absolute() {
            return Err(Error::setting(
                "out",
                format!("{}: must be an absolute path", self.out.display()),
            ));
        }
        let out = self.out.to_str().ok_or_else(|| {
            Error::setting("out", format!("{}: not valid UTF-8", self.out.display()))
        })?;
        check_directive("out", out, false, true)?;
        let r = &self.resources;
        for (setting, value) in [
            ("partition", &r.partition),
            ("time", &r.time),
            ("mem", &r.mem),
            ("account", &r.account),
        ] {
            if let Some(v) = value {
                check_directive(setting, v, false, false)?;
            }
        }
        if r.cpus_per_task == Some(0) {
            return Err(Error::setting("cpus-per-task", "must be at least 1"));
        }
        for a in &r.extra {
            check_directive("sbatch-arg", a, true, false)?;
            if !a.starts_with('-') {
                return Err(Error::setting(
                    "sbatch-arg",
                    format!("`{a}` is not an sbatch option (give one option each, e.g. --sbatch-arg=--qos=short)"),
                ));
            }
            let name = a.split('=').next().unwrap_or(a);
            if OWN_OPTIONS.contains(&name) || ["-a", "-o", "-e", "-d", "-W", "-J"].contains(&name) {
                return Err(Error::setting(
                    "sbatch-arg",
                    format!("`{a}`: packbed slurm sets {name} itself"),
                ));
            }
        }
        Ok(())
    }

    /// `DIR/config.toml`.
    pub(crate) fn config_path(&self) -> PathBuf {
        self.out.join(CONFIG_FILE)
    }

    /// `DIR/array.sh`.
    pub(crate) fn array_path(&self) -> PathBuf {
        self.out.join(ARRAY_SCRIPT)
    }

    /// `DIR/merge.sh`.
    pub(crate) fn merge_path(&self) -> PathBuf {
        self.out.join(MERGE_SCRIPT)
    }

    /// The log of task `K`.
    pub(crate) fn task_log(&self, k: u64) -> PathBuf {
        self.out.join(LOGS_DIR).join(format!("task-{k}.out"))
    }

    /// The exit status file of task `K`.
    pub(crate) fn task_status(&self, k: u64) -> PathBuf {
        self.out.join(LOGS_DIR).join(format!("task-{k}.status"))
    }

    /// The log of the merge.
    pub(crate) fn merge_log(&self) -> PathBuf {
        self.out.join(LOGS_DIR).join("merge.out")
    }

    /// The exit status file of the merge.
    pub(crate) fn merge_status(&self) -> PathBuf {
        self.out.join(LOGS_DIR).join("merge.status")
    }

    /// A job name from the directory's name: `packbed-NAME`.
    fn job_name(&self, suffix: &str) -> String {
        let base: String = self
            .out
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .take(40)
            .collect();
        format!("packbed-{base}{suffix}")
    }

    /// `#SBATCH` lines of the resources (`cpus`: whether to ask for `--cpus-per-task`).
    fn resource_lines(&self, cpus: bool) -> String {
        let r = &self.resources;
        let mut s = String::new();
        let mut line = |opt: &str, v: &Option<String>| {
            if let Some(v) = v {
                let _ = writeln!(s, "#SBATCH --{opt}={v}");
            }
        };
        line("partition", &r.partition);
        line("account", &r.account);
        line("time", &r.time);
        line("mem", &r.mem);
        if cpus {
            line("cpus-per-task", &r.cpus_per_task.map(|c| c.to_string()));
        }
        for a in &r.extra {
            let _ = writeln!(s, "#SBATCH {a}");
        }
        s
    }

    /// The variables both scripts start with.
    fn preamble(&self) -> String {
        format!(
            "set -u\nDIR={}\nPACKBED={}\n",
            shell_quote(&self.out.to_string_lossy()),
            shell_quote(&self.binary.to_string_lossy())
        )
    }

    /// The text of `array.sh`.
    pub(crate) fn array_script(&self) -> String {
        let (n, m) = (self.runs, self.tasks);
        let out = self.out.display();
        format!(
            "#!/bin/bash
# packbed ensemble of {n} replicates (per sweep value) in {m} Slurm array tasks.
# Task K runs the replicates i with i mod {m} == K into DIR/shards/K; merge.sh
# then joins the shards. Submit by hand: sbatch array.sh, then
# sbatch --dependency=afterok:ARRAY_JOB_ID merge.sh. Resubmitting resumes.
#SBATCH --job-name={name}
#SBATCH --array=0-{last}
#SBATCH --output={log}
{resources}
{preamble}K=\"$SLURM_ARRAY_TASK_ID\"
rm -f \"$DIR/{LOGS_DIR}/task-$K.status\"
\"$PACKBED\" ensemble \"$DIR/{CONFIG_FILE}\" --runs {n} --shard \"$K/{m}\" \\
    --out \"$DIR/{SHARDS_DIR}/$K\" --jobs \"${{SLURM_CPUS_PER_TASK:-1}}\" --no-pictures
status=$?
# The exit status, for `packbed slurm --wait` (no Slurm accounting needed).
echo \"$status\" > \"$DIR/{LOGS_DIR}/task-$K.status\"
exit \"$status\"
",
            name = self.job_name(""),
            log = sbatch_word(&format!("{out}/{LOGS_DIR}/task-%a.out")),
            last = m - 1,
            resources = self.resource_lines(true),
            preamble = self.preamble(),
        )
    }

    /// The text of `merge.sh`.
    pub(crate) fn merge_script(&self) -> String {
        let out = self.out.display();
        format!(
            "#!/bin/bash
# Joins the {m} shards of array.sh into the ensemble files of DIR, the same
# bytes as one `packbed ensemble` would write. Submit after the array:
# sbatch --dependency=afterok:ARRAY_JOB_ID merge.sh
#SBATCH --job-name={name}
#SBATCH --output={log}
{resources}
{preamble}rm -f \"$DIR/{LOGS_DIR}/merge.status\"
\"$PACKBED\" merge \"$DIR\"/{SHARDS_DIR}/* --out \"$DIR\"
status=$?
echo \"$status\" > \"$DIR/{LOGS_DIR}/merge.status\"
exit \"$status\"
",
            m = self.tasks,
            name = self.job_name("-merge"),
            log = sbatch_word(&format!("{out}/{LOGS_DIR}/merge.out")),
            resources = self.resource_lines(false),
            preamble = self.preamble(),
        )
    }
}

/// The config as the tasks get it: PSD tables and medium files made absolute (they are
/// relative to the config file, which moves into `DIR`), the replicate count
/// stored as `[ensemble] runs`.
fn task_config(config: &Config, runs: u64) -> Result<Config> {
    let mut c = config.clone();
    c.ensemble = Some(EnsembleConfig { runs });
    let tables = c.species.iter_mut().filter_map(|s| match &mut s.size {
        Some(SizeConfig { table: Some(t), .. }) => Some(t),
        _ => None,
    });
    // A medium's bed file too.
    let files = c.feeds.iter_mut().filter_map(|f| f.file.as_mut());
    for t in tables.chain(files) {
        if t.is_relative() {
            *t = std::path::absolute(&*t).map_err(|e| Error::Io {
                path: t.clone(),
                source: e,
            })?;
        }
    }
    Ok(c)
}

/// The TOML text of `config.toml`, checked to read back as the same config.
pub(crate) fn config_text(config: &Config, runs: u64) -> Result<(String, Config)> {
    let c = task_config(config, runs)?;
    let body = toml::to_string(&c)
        .map_err(|e| Error::config(format!("cannot write the config as TOML: {e}")))?;
    let text = format!(
        "# The config of this ensemble as packbed slurm resolved it (config file and\n# command-line options); every array task runs it.\n{body}"
    );
    let back = Config::from_toml(&text, CONFIG_FILE)?;
    if config_key(&back) != config_key(&c) {
        return Err(Error::Impossible(
            "the config does not read back the same from TOML (a bug in packbed, please report it)"
                .into(),
        ));
    }
    Ok((text, back))
}

/// What [`prepare`] wrote.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The files written (config, scripts, manifest).
    pub files: Vec<PathBuf>,
    /// Replicates of earlier submissions found done in the shards.
    pub resumed: bool,
}

/// Checks `plan` and `DIR` and writes the config, the scripts, the manifest
/// and the `shards/` and `logs/` directories. Nothing is written when a check
/// fails: a `DIR` that is not new, empty or an ensemble of this config, shards
/// of another task count, a directory that cannot be written.
pub fn prepare(config: &Config, plan: &JobArray) -> Result<Prepared> {
    plan.check()?;
    super::validate(config)?;
    let (text, task) = config_text(config, plan.runs)?;
    let manifest = Manifest {
        packbed_version: env!("CARGO_PKG_VERSION").into(),
        runs: plan.runs,
        shard: Shard::ALL,
        config: config_key(&task),
    };
    check_out(&plan.out, &manifest)?;
    let shards = plan.out.join(SHARDS_DIR);
    let mut resumed = false;
    if let Ok(entries) = fs::read_dir(&shards) {
        for e in entries.flatten() {
            let d = e.path();
            if !d.join(MANIFEST).exists() {
                continue;
            }
            let m = Manifest::read(&d)?;
            if m.shard.count != plan.tasks {
                return Err(Error::setting(
                    "tasks",
                    format!(
                        "{} holds shards of {} tasks; resume with --tasks {}, or use a new output directory",
                        plan.out.display(),
                        m.shard.count,
                        m.shard.count
                    ),
                ));
            }
            resumed = true;
        }
    }
    crate::output::check_out_dir(&plan.out)?;
    write_manifest(&plan.out, &manifest)?;
    for d in [shards, plan.out.join(LOGS_DIR)] {
        fs::create_dir_all(&d).map_err(|e| Error::Io { path: d, source: e })?;
    }
    let files = vec![
        (plan.config_path(), text),
        (plan.array_path(), plan.array_script()),
        (plan.merge_path(), plan.merge_script()),
    ];
    for (path, text) in &files {
        crate::output::write_file(path, text.as_bytes())?;
    }
    for script in [plan.array_path(), plan.merge_path()] {
        make_executable(&script)?;
    }
    let mut written: Vec<PathBuf> = files.into_iter().map(|(p, _)| p).collect();
    written.push(plan.out.join(MANIFEST));
    Ok(Prepared {
        files: written,
        resumed,
    })
}

#[cfg(unix)]
fn make_executable(path: &Path) -> Result<()> {
    use std::os::unix::fs::PermissionsExt;
    fs::set_permissions(path, fs::Permissions::from_mode(0o755)).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })
}

#[cfg(not(unix))]
fn make_executable(_: &Path) -> Result<()> {
    Ok(())
}

/// The job id in what `sbatch` printed: `Submitted batch job 123`, or with
/// `--parsable` `123` or `123;cluster`.
pub(crate) fn parse_job_id(stdout: &str) -> Option<String> {
    let line = stdout.lines().map(str::trim).rfind(|l| !l.is_empty())?;
    let word = line
        .strip_prefix("Submitted batch job")
        .map(str::trim)
        .unwrap_or(line);
    let id = word.split(';').next()?.trim();
    (!id.is_empty() && id.bytes().all(|b| b.is_ascii_digit())).then(|| id.to_string())
}

/// What ended a task or the merge, from its status file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Ended {
    /// Exit status 0.
    Ok,
    /// A nonzero exit status.
    Failed(i32),
    /// No status: killed (time limit, `scancel`, node failure) or never started.
    NoStatus,
}

/// What the status file `path` says.
pub(crate) fn ended(path: &Path) -> Ended {
    match fs::read_to_string(path)
        .ok()
        .and_then(|t| t.trim().parse::<i32>().ok())
    {
        Some(0) => Ended::Ok,
        Some(s) => Ended::Failed(s),
        None => Ended::NoStatus,
    }
}

/// One job of a submission: a task of the array, or the merge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Job {
    /// Array task `k`.
    Task(u64),
    /// The merge job.
    Merge,
}

impl std::fmt::Display for Job {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Job::Task(k) => write!(f, "task {k}"),
            Job::Merge => f.write_str("the merge"),
        }
    }
}

/// A task or the merge that did not succeed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Failure {
    /// Which job.
    pub what: Job,
    /// How it ended.
    pub ended: Ended,
    /// Its log file.
    pub log: PathBuf,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let how = match self.ended {
            Ended::Ok => "succeeded".to_string(),
            Ended::Failed(s) => format!("failed with exit status {s}"),
            Ended::NoStatus => "did not finish (cancelled, killed or never started)".to_string(),
        };
        write!(f, "{} {how}; log: {}", self.what, self.log.display())
    }
}

/// The tasks of `plan` that did not succeed, by their status files.
pub(crate) fn failed_tasks(plan: &JobArray) -> Vec<Failure> {
    (0..plan.tasks)
        .filter_map(|k| {
            let e = ended(&plan.task_status(k));
            (e != Ended::Ok).then(|| Failure {
                what: Job::Task(k),
                ended: e,
                log: plan.task_log(k),
            })
        })
        .collect()
}

/// Removes the status files of earlier submissions, before submitting again.
pub(crate) fn clear_statuses(plan: &JobArray) -> Result<()> {
    let mut paths: Vec<PathBuf> = (0..plan.tasks).map(|k| plan.task_status(k)).collect();
    paths.push(plan.merge_status());
    for p in paths {
        match fs::remove_file(&p) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(Error::Io { path: p, source: e })
            }
            _ => {}
        }
    }
    Ok(())
}

/// What `packbed slurm` prints once the scripts are written: where, which
/// files, and (unless it submits them) how to submit them by hand.
pub fn prepared_text(plan: &JobArray, runs: u64, prepared: &Prepared, submitting: bool) -> String {
    use crate::error::inert_path as path;
    let dir = path(&plan.out);
    let resuming = if prepared.resumed {
        " (resuming the shards there)"
    } else {
        ""
    };
    let mut t = format!(
        "packbed slurm: {runs} replicates in {} array tasks, in {dir}{resuming}\n\
         \x20 {}  the config every task runs\n  {}  the job array\n  {}  the merge\n",
        plan.tasks,
        path(&plan.config_path()),
        path(&plan.array_path()),
        path(&plan.merge_path())
    );
    if !submitting {
        // Lines to paste into a shell: each path one quoted word.
        t += &format!(
            "submit with:\n  sbatch {}\n  sbatch --dependency=afterok:ARRAY_JOB_ID {}\n",
            shell_path(&plan.array_path()),
            shell_path(&plan.merge_path())
        );
    }
    t
}

/// What `packbed slurm --submit` prints once both jobs are queued.
pub fn submitted_text(plan: &JobArray, jobs: &Submitted, waiting: bool) -> String {
    let mut t = format!(
        "submitted array job {} ({} tasks) and merge job {} (runs when every task succeeded)\n\
         logs: {}\n",
        jobs.array,
        plan.tasks,
        jobs.merge,
        crate::error::inert_path(&plan.out.join(LOGS_DIR))
    );
    if !waiting {
        t += &format!(
            "the ensemble files appear in {} when the merge job ends; to resume, run the same \
             command again\n",
            crate::error::inert_path(&plan.out)
        );
    }
    t
}

/// A submission whose tasks or merge failed: the input was fine, so the
/// command exits 1 rather than 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct JobsFailed(pub String);

/// Waits for the merge of `jobs` (`wait`): the line saying where the
/// ensemble's files are, or [`JobsFailed`] naming the tasks that failed.
pub fn wait_for_merge(
    plan: &JobArray,
    jobs: &Submitted,
    poll: std::time::Duration,
) -> Result<std::result::Result<String, JobsFailed>> {
    Ok(match wait(plan, jobs, poll)? {
        WaitOutcome::Done => Ok(format!(
            "done: ensemble files in {} (log {})",
            crate::error::inert_path(&plan.out),
            crate::error::inert_path(&plan.merge_log())
        )),
        WaitOutcome::Failed(failures) => Err(JobsFailed(failed_text(jobs, &failures))),
    })
}

/// The one line of a submission that failed: which job, which of its tasks
/// and why, and what a rerun does.
pub(crate) fn failed_text(jobs: &Submitted, failures: &[Failure]) -> String {
    let list: Vec<String> = failures.iter().map(|f| f.to_string()).collect();
    let (job, then) = if failures.iter().any(|f| f.what == Job::Merge) {
        (
            format!("merge job {}", jobs.merge),
            "the shards are complete".to_string(),
        )
    } else {
        (
            format!("array job {}", jobs.array),
            format!("so the merge (job {}) did not run", jobs.merge),
        )
    };
    format!(
        "{job}: {}; {then}; run the same command again to resume",
        list.join("; ")
    )
}

#[cfg(test)]
mod tests {
    use super::jobs::is_job;
    use super::*;
    use std::process::Command;

    #[test]
    fn a_failed_submission_names_the_job_that_failed_and_what_a_rerun_does() {
        let jobs = Submitted {
            array: "11".into(),
            merge: "12".into(),
        };
        let failure = |what, ended| Failure {
            what,
            ended,
            log: PathBuf::from("/d/logs/x.out"),
        };
        let tasks = [
            failure(Job::Task(3), Ended::Failed(2)),
            failure(Job::Task(5), Ended::NoStatus),
        ];
        let t = failed_text(&jobs, &tasks);
        assert!(t.starts_with("array job 11: task 3 failed with exit status 2; log: /d/logs/x.out; task 5 did not finish"), "{t}");
        assert!(
            t.ends_with("so the merge (job 12) did not run; run the same command again to resume"),
            "{t}"
        );
        let t = failed_text(&jobs, &[failure(Job::Merge, Ended::Failed(1))]);
        assert!(t.starts_with("merge job 12: the merge failed"), "{t}");
        assert!(t.contains("the shards are complete"), "{t}");
    }

    #[test]
    fn the_texts_list_the_scripts_and_how_to_submit_them() {
        let p = plan(Path::new("/tmp/ens"));
        let prepared = Prepared {
            files: Vec::new(),
            resumed: true,
        };
        let t = prepared_text(&p, 10, &prepared, false);
        assert!(t.starts_with("packbed slurm: 10 replicates in 4 array tasks, in /tmp/ens (resuming the shards there)\n"), "{t}");
        assert!(
            t.contains("sbatch --dependency=afterok:ARRAY_JOB_ID /tmp/ens/merge.sh"),
            "{t}"
        );
        assert!(!prepared_text(&p, 10, &prepared, true).contains("submit with"));
        assert!(p.local_dir_note().is_some());
        assert!(plan(Path::new("/scratch/ens")).local_dir_note().is_none());
    }

    fn plan(out: &Path) -> JobArray {
        JobArray {
            binary: PathBuf::from("/opt/pack bed/bin/packbed"),
            out: out.to_path_buf(),
            runs: 10,
            tasks: 4,
            resources: Resources {
                partition: Some("short".into()),
                time: Some("1:00:00".into()),
                cpus_per_task: Some(2),
                mem: Some("4G".into()),
                account: Some("proj42".into()),
                extra: vec!["--qos=low".into(), "--mail-type=END,FAIL".into()],
            },
        }
    }

    #[test]
    fn sbatch_words_keep_blanks_quotes_and_hashes() {
        assert_eq!(sbatch_word("/a/b-%a.out"), "/a/b-%a.out");
        assert_eq!(sbatch_word("/my runs/x"), "\"/my runs/x\"");
        assert_eq!(sbatch_word(r#"/a"b\c#d"#), r#""/a\"b\\c\#d""#);
    }

    #[test]
    fn quoting() {
        assert_eq!(shell_quote("/a/b-c_d.e"), "/a/b-c_d.e");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's"), r"'it'\''s'");
        assert_eq!(shell_quote(""), "''");
        assert_eq!(shell_quote("$HOME;rm"), "'$HOME;rm'");
    }

    #[test]
    fn array_script_names_everything() {
        let p = plan(Path::new("/scratch/u/cake"));
        let s = p.array_script();
        assert!(s.starts_with("#!/bin/bash\n"), "{s}");
        for line in [
            "#SBATCH --array=0-3\n",
            "#SBATCH --output=/scratch/u/cake/logs/task-%a.out\n",
            "#SBATCH --partition=short\n",
            "#SBATCH --time=1:00:00\n",
            "#SBATCH --cpus-per-task=2\n",
            "#SBATCH --mem=4G\n",
            "#SBATCH --account=proj42\n",
            "#SBATCH --qos=low\n",
            "#SBATCH --mail-type=END,FAIL\n",
            "#SBATCH --job-name=packbed-cake\n",
            "DIR=/scratch/u/cake\n",
            "PACKBED='/opt/pack bed/bin/packbed'\n",
            "--runs 10 --shard \"$K/4\"",
            "--out \"$DIR/shards/$K\"",
            "\"$DIR/config.toml\"",
        ] {
            assert!(s.contains(line), "no {line:?} in\n{s}");
        }
        // Slurm reads #SBATCH lines only before the first command.
        let lines: Vec<&str> = s.lines().collect();
        let first_command = lines
            .iter()
            .position(|l| !l.is_empty() && !l.starts_with('#'))
            .unwrap();
        let last_directive = lines
            .iter()
            .rposition(|l| l.starts_with("#SBATCH"))
            .unwrap();
        assert!(last_directive < first_command, "{s}");
    }

    #[test]
    fn merge_script_names_everything() {
        let p = plan(Path::new("/scratch/u/cake"));
        let s = p.merge_script();
        for line in [
            "#SBATCH --output=/scratch/u/cake/logs/merge.out\n",
            "#SBATCH --partition=short\n",
            "#SBATCH --time=1:00:00\n",
            "#SBATCH --mem=4G\n",
            "#SBATCH --account=proj42\n",
            "#SBATCH --qos=low\n",
            "\"$PACKBED\" merge \"$DIR\"/shards/* --out \"$DIR\"\n",
        ] {
            assert!(s.contains(line), "no {line:?} in\n{s}");
        }
        assert!(!s.contains("--array"), "{s}");
        assert!(!s.contains("cpus-per-task"), "{s}");
    }

    #[test]
    fn scripts_pass_bash_n() {
        if !on_path("bash") {
            // `.ci/run` sets this: there the scripts' syntax check must run.
            let required = std::env::var("PACKBED_REQUIRE_SLURM").is_ok_and(|v| v == "1");
            assert!(!required, "no bash on PATH, and PACKBED_REQUIRE_SLURM=1");
            eprintln!("SKIP: no bash (PACKBED_REQUIRE_SLURM=1 makes this a failure)");
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let mut p = plan(dir.path());
        p.binary = PathBuf::from("/weird dir/it's \"here\"/$packbed");
        for (name, text) in [("a.sh", p.array_script()), ("m.sh", p.merge_script())] {
            let path = dir.path().join(name);
            fs::write(&path, text).unwrap();
            let st = Command::new("bash").arg("-n").arg(&path).status().unwrap();
            assert!(st.success(), "bash -n {name}");
        }
        // And the quoted binary path survives the shell unchanged.
        let probe = format!("{}echo \"$PACKBED\"\n", p.preamble());
        let out = Command::new("bash").arg("-c").arg(probe).output().unwrap();
        assert_eq!(
            String::from_utf8(out.stdout).unwrap().trim_end(),
            "/weird dir/it's \"here\"/$packbed"
        );
    }

    #[test]
    fn checks() {
        let ok = plan(Path::new("/scratch/x"));
        assert!(ok.check().is_ok());
        let msg = |p: JobArray| p.check().unwrap_err().to_string();
        let mut p = ok.clone();
        p.tasks = 11;
        assert!(msg(p).starts_with("tasks: 11 tasks for 10 replicates"));
        let mut p = ok.clone();
        p.tasks = 0;
        assert!(msg(p).starts_with("tasks:"));
        let mut p = ok.clone();
        p.out = PathBuf::from("rel/dir");
        assert!(msg(p).starts_with("out:"));
        let mut p = ok.clone();
        p.out = PathBuf::from("/a b/c");
        assert!(p.check().is_ok());
        assert!(p
            .array_script()
            .contains("#SBATCH --output=\"/a b/c/logs/task-%a.out\"\n"));
        let mut p = ok.clone();
        p.resources.partition = Some("a b".into());
        assert!(msg(p).contains("a blank"));
        let mut p = ok.clone();
        p.out = PathBuf::from("/a%b");
        assert!(msg(p).contains('%'));
        let mut p = ok.clone();
        p.resources.time = Some("1:00\n#SBATCH --x".into());
        assert!(msg(p).starts_with("time:"));
        let mut p = ok.clone();
        p.resources.extra = vec!["--array=0-9".into()];
        assert!(msg(p).starts_with("sbatch-arg:"));
        let mut p = ok.clone();
        p.resources.extra = vec!["qos=low".into()];
        assert!(msg(p).starts_with("sbatch-arg:"));
    }

    #[test]
    fn job_ids() {
        assert_eq!(
            parse_job_id("Submitted batch job 123\n").as_deref(),
            Some("123")
        );
        assert_eq!(parse_job_id("123\n").as_deref(), Some("123"));
        assert_eq!(parse_job_id("4567;cluster1\n").as_deref(), Some("4567"));
        assert_eq!(parse_job_id(""), None);
        assert_eq!(parse_job_id("sbatch: error: nope"), None);
    }

    #[test]
    fn squeue_lines() {
        let q = parse_squeue(
            "12_[2-3]|PENDING|JobArrayTaskLimit|/s/a\n12_1|RUNNING|None|/s/a\n13|PENDING|DependencyNeverSatisfied|/s/a b|c\n\n",
        );
        assert_eq!(q.len(), 3);
        assert_eq!(q[2].dir, "/s/a b|c");
        assert!(is_job(&q[0].id, "12") && is_job(&q[1].id, "12"));
        assert!(!is_job(&q[2].id, "12") && !is_job("123_1", "12"));
        assert_eq!(q[2].reason, "DependencyNeverSatisfied");
    }

    #[test]
    fn config_round_trips_and_prepare_writes() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("ens");
        let mut config = Config {
            dim: 2,
            seed: 7,
            ..Config::default()
        };
        let p = JobArray {
            out: out.clone(),
            runs: 3,
            tasks: 2,
            ..plan(&out)
        };
        let prepared = prepare(&config, &p).unwrap();
        assert_eq!(prepared.files.len(), 4);
        let back = Config::from_file(&p.config_path()).unwrap();
        assert_eq!(back.dim, 2);
        assert_eq!(back.seed, 7);
        assert_eq!(back.ensemble, Some(EnsembleConfig { runs: 3 }));
        assert!(out.join("shards").is_dir() && out.join("logs").is_dir());
        // Again into the same directory: fine (resume).
        prepare(&config, &p).unwrap();
        // Another config: refused, naming the difference.
        config.seed = 8;
        let e = prepare(&config, &p).unwrap_err().to_string();
        assert!(e.contains("different config") && e.contains("seed"), "{e}");
        // A status file says how a task ended.
        fs::write(p.task_status(0), "0\n").unwrap();
        fs::write(p.task_status(1), "143\n").unwrap();
        let f = failed_tasks(&p);
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].ended, Ended::Failed(143));
        assert!(f[0].to_string().contains("logs/task-1.out"), "{}", f[0]);
        clear_statuses(&p).unwrap();
        assert_eq!(failed_tasks(&p).len(), 2);
    }

    #[test]
    fn nothing_written_on_bad_plan() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("ens");
        let p = JobArray {
            out: out.clone(),
            runs: 3,
            tasks: 5,
            ..plan(&out)
        };
        assert!(prepare(&Config::default(), &p).is_err());
        assert!(!out.exists());
    }
}
