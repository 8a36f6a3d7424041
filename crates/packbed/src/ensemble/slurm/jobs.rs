//! Running Slurm's commands for a [`JobArray`]: `sbatch` (submit), `squeue`
//! (what is queued), `scancel`, and waiting for the jobs to end.

use super::{clear_statuses, ended, failed_tasks, parse_job_id, Ended, Failure, Job, JobArray};
use crate::error::{Error, Result};
use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

/// Whether `program` is an executable file on `PATH`.
pub fn on_path(program: &str) -> bool {
    let Some(path) = std::env::var_os("PATH") else {
        return false;
    };
    std::env::split_paths(&path).any(|d| {
        let p = d.join(program);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            p.metadata()
                .map(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
                .unwrap_or(false)
        }
        #[cfg(not(unix))]
        {
            p.is_file()
        }
    })
}

/// Runs a Slurm command and returns its standard output, or an error with
/// the first line it wrote to standard error.
fn slurm_command(program: &str, args: &[&str], dir: &Path) -> Result<String> {
    let out = Command::new(program)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| Error::Impossible(format!("cannot run {program}: {e}")))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let first = err
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty())
            .unwrap_or("no message");
        return Err(Error::Impossible(format!(
            "{program} {} failed ({}): {first}",
            args.join(" "),
            out.status
        )));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The job ids of a submission.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Submitted {
    /// The job array.
    pub array: String,
    /// The merge job, held until every task of the array succeeded.
    pub merge: String,
}

/// Submits `array.sh`, then `merge.sh` depending on it (`afterok`).
pub fn submit(plan: &JobArray) -> Result<Submitted> {
    clear_statuses(plan)?;
    let sbatch = |args: &[&str]| -> Result<String> {
        let out = slurm_command("sbatch", args, &plan.out)?;
        parse_job_id(&out).ok_or_else(|| {
            Error::Impossible(format!(
                "sbatch printed no job id: `{}`",
                out.trim().replace('\n', " ")
            ))
        })
    };
    let array_path = plan.array_path();
    let array = sbatch(&["--parsable", &array_path.to_string_lossy()])?;
    let merge_path = plan.merge_path();
    let merge = sbatch(&[
        "--parsable",
        &format!("--dependency=afterok:{array}"),
        &merge_path.to_string_lossy(),
    ])
    .map_err(|e| {
        Error::Impossible(format!(
            "{e} (the array job {array} is submitted; submit merge.sh by hand: sbatch --dependency=afterok:{array} {})",
            super::shell_path(&merge_path)
        ))
    })?;
    Ok(Submitted { array, merge })
}

/// One job of `squeue`: id (`123`, `123_4`, `123_[0-9]`), state, reason,
/// working directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct QueuedJob {
    /// The job id as `squeue` shows it.
    pub id: String,
    /// E.g. `PENDING`, `RUNNING`.
    pub state: String,
    /// E.g. `Dependency`, `DependencyNeverSatisfied`, `None`.
    pub reason: String,
    /// The job's working directory: `DIR` for the jobs of `packbed slurm`,
    /// which submits from there.
    pub dir: String,
}

/// The `squeue -o` format [`parse_squeue`] reads.
const SQUEUE_FORMAT: &str = "%i|%T|%r|%Z";

/// Parses `squeue -h -o '%i|%T|%r|%Z'`.
pub(crate) fn parse_squeue(text: &str) -> Vec<QueuedJob> {
    text.lines()
        .filter_map(|l| {
            let mut f = l.trim().splitn(4, '|');
            let id = f.next()?.trim();
            let mut next = || f.next().unwrap_or("").trim().to_string();
            (!id.is_empty()).then(|| QueuedJob {
                id: id.to_string(),
                state: next(),
                reason: next(),
                dir: next(),
            })
        })
        .collect()
}

/// Whether the squeue id `id` belongs to job (or job array) `job`.
pub(super) fn is_job(id: &str, job: &str) -> bool {
    id == job
        || id
            .strip_prefix(job)
            .is_some_and(|rest| rest.starts_with('_'))
}

/// The jobs of this user in the queue (pending, running, completing).
pub(crate) fn queue() -> Result<Vec<QueuedJob>> {
    let out = slurm_command(
        "squeue",
        &["-h", "--me", "-o", SQUEUE_FORMAT],
        Path::new("."),
    )?;
    Ok(parse_squeue(&out))
}

/// Makes way for a new submission into `plan.out`: cancels the merge jobs of
/// earlier submissions there that can never run (a task had failed:
/// `DependencyNeverSatisfied`) and returns their ids; refuses while other
/// jobs of earlier submissions there are queued or running, since two tasks
/// writing one shard would spoil it.
pub fn clear_queue(plan: &JobArray) -> Result<Vec<String>> {
    let Ok(real) = fs::canonicalize(&plan.out) else {
        return Ok(Vec::new());
    };
    let ours: Vec<QueuedJob> = queue()?
        .into_iter()
        .filter(|j| Path::new(&j.dir) == real || Path::new(&j.dir) == plan.out)
        .collect();
    let (dead, live): (Vec<_>, Vec<_>) = ours
        .into_iter()
        .partition(|j| j.reason == "DependencyNeverSatisfied");
    if !live.is_empty() {
        let ids: Vec<&str> = live.iter().map(|j| j.id.as_str()).collect();
        return Err(Error::setting(
            "out",
            format!(
                "jobs of an earlier submission into {} are still queued or running ({}): wait for them, or scancel them, then run again",
                plan.out.display(),
                ids.join(", ")
            ),
        ));
    }
    let mut cancelled = Vec::new();
    for j in dead {
        cancel(&j.id)?;
        cancelled.push(j.id);
    }
    Ok(cancelled)
}

/// Cancels a job.
pub(crate) fn cancel(job: &str) -> Result<()> {
    slurm_command("scancel", &[job], Path::new(".")).map(drop)
}

/// How a waited-for submission ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum WaitOutcome {
    /// Every task and the merge succeeded.
    Done,
    /// These tasks (or the merge) did not succeed; the merge job, if still
    /// held, was cancelled.
    Failed(Vec<Failure>),
}

/// Waits until the array and the merge of `jobs` have left the queue,
/// polling `squeue` every `poll`, and reads their status files. A merge that
/// can never run (a task failed) is cancelled rather than waited for.
pub(crate) fn wait(plan: &JobArray, jobs: &Submitted, poll: Duration) -> Result<WaitOutcome> {
    let mut squeue_errors = 0;
    let mut grace = 0;
    loop {
        let q = match queue() {
            Ok(q) => {
                squeue_errors = 0;
                q
            }
            // A busy controller may time out now and then.
            Err(e) => {
                squeue_errors += 1;
                if squeue_errors > 10 {
                    return Err(e);
                }
                std::thread::sleep(poll);
                continue;
            }
        };
        let array_queued = q.iter().any(|j| is_job(&j.id, &jobs.array));
        let merge_queued = q.iter().any(|j| j.id == jobs.merge);
        if !array_queued {
            let failed = failed_tasks(plan);
            // Status files on a shared file system may show up a little late.
            if !failed.is_empty() && grace < 3 {
                grace += 1;
                std::thread::sleep(poll.max(Duration::from_secs(1)));
                continue;
            }
            if !failed.is_empty() {
                if merge_queued {
                    cancel(&jobs.merge)?;
                }
                return Ok(WaitOutcome::Failed(failed));
            }
            if !merge_queued {
                return Ok(match ended(&plan.merge_status()) {
                    Ended::Ok => WaitOutcome::Done,
                    e => WaitOutcome::Failed(vec![Failure {
                        what: Job::Merge,
                        ended: e,
                        log: plan.merge_log(),
                    }]),
                });
            }
        }
        std::thread::sleep(poll);
    }
}
