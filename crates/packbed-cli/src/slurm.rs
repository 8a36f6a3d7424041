//! `packbed slurm`: an ensemble as a Slurm job array and a merge job. The
//! scripts, the checks and the calls of `sbatch`/`squeue`/`scancel` are in
//! `packbed::ensemble::slurm`; this file parses, dispatches and prints.

use crate::overrides::{at_least_one, Overrides};
use crate::run::{read_config, source_name};
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::ensemble::slurm::{self, Plan, Resources, WaitOutcome};
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `packbed slurm`.
#[derive(Debug, Args)]
pub struct SlurmArgs {
    /// Config file (TOML); without it, the default bed. A `[sweep]` table
    /// shards every value's replicates.
    #[arg(value_name = "CONFIG.toml")]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: Overrides,
    /// Replicate beds (per sweep value); default: `[ensemble] runs` of the config.
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = at_least_one)]
    pub runs: Option<usize>,
    /// Array tasks (shards), at most N.
    #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = at_least_one)]
    pub tasks: usize,
    /// Output directory, on a file system every node can write; the jobs'
    /// scripts, config, shards and logs go there too. Rerunning resumes.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Slurm partition (`sbatch --partition`).
    #[arg(long, value_name = "P")]
    pub partition: Option<String>,
    /// Time limit of each job (`sbatch --time`), e.g. 1:00:00.
    #[arg(long, value_name = "T")]
    pub time: Option<String>,
    /// CPUs of each array task (its `--jobs`); default 1.
    #[arg(long, value_name = "C", allow_negative_numbers = true, value_parser = at_least_one)]
    pub cpus_per_task: Option<usize>,
    /// Memory of each job (`sbatch --mem`), e.g. 4G.
    #[arg(long, value_name = "MEM")]
    pub mem: Option<String>,
    /// Account to charge (`sbatch --account`).
    #[arg(long, value_name = "A")]
    pub account: Option<String>,
    /// A further sbatch option for both jobs, e.g. --sbatch-arg=--qos=short (repeatable).
    #[arg(long = "sbatch-arg", value_name = "ARG", allow_hyphen_values = true)]
    pub sbatch_args: Vec<String>,
    /// Submit the array and the merge (after the array succeeded) with sbatch.
    #[arg(long)]
    pub submit: bool,
    /// Wait for the merge; exit 1 naming the tasks that failed (needs --submit).
    #[arg(long, requires = "submit")]
    pub wait: bool,
}

/// A submission whose tasks or merge failed: exit code 1, not 2 (the input was fine).
#[derive(Debug)]
pub struct JobsFailed(pub String);

impl std::fmt::Display for JobsFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for JobsFailed {}

/// Runs `packbed slurm`.
pub fn slurm(args: SlurmArgs) -> Result<()> {
    let config = read_config(args.config.as_deref(), &args.overrides)?;
    let source = source_name(args.config.as_deref(), &args.overrides);
    packbed::ensemble::validate(&config).with_context(|| source.clone())?;
    let runs = match (args.runs, &config.ensemble) {
        (Some(n), _) => n as u64,
        (None, Some(e)) => e.runs,
        (None, None) => bail!("--runs N is needed (the config has no `[ensemble] runs`)"),
    };
    if args.submit && !slurm::on_path("sbatch") {
        bail!("--submit: sbatch is not on PATH (run on a Slurm login node, or leave out --submit and submit the scripts by hand)");
    }
    let out =
        std::path::absolute(&args.out).with_context(|| format!("--out {}", args.out.display()))?;
    let binary = std::env::current_exe()
        .and_then(|p| p.canonicalize())
        .context("cannot find the path of the packbed binary")?;
    let plan = Plan {
        binary,
        out,
        runs,
        tasks: args.tasks as u64,
        resources: Resources {
            partition: args.partition,
            time: args.time,
            cpus_per_task: args.cpus_per_task.map(|c| c.min(u32::MAX as usize) as u32),
            mem: args.mem,
            account: args.account,
            extra: args.sbatch_args,
        },
    };
    if args.submit {
        for id in slurm::clear_queue(&plan)? {
            eprintln!("packbed: note: cancelled job {id} of an earlier submission: a task had failed, so it could never run");
        }
    }
    let prepared = slurm::prepare(&config, &plan)?;
    let dir = plan.out.display();
    if plan.out.starts_with("/tmp") || plan.out.starts_with("/dev/shm") {
        eprintln!("packbed: note: {dir} is usually local to each node; on a cluster of several nodes put --out on a shared file system");
    }
    println!(
        "packbed slurm: {runs} replicates in {} array tasks, in {dir}{}",
        plan.tasks,
        if prepared.resumed {
            " (resuming the shards there)"
        } else {
            ""
        }
    );
    println!(
        "  {}  the config every task runs",
        plan.config_path().display()
    );
    println!("  {}  the job array", plan.array_path().display());
    println!("  {}  the merge", plan.merge_path().display());
    if !args.submit {
        println!("submit with:");
        println!("  sbatch {}", plan.array_path().display());
        println!(
            "  sbatch --dependency=afterok:ARRAY_JOB_ID {}",
            plan.merge_path().display()
        );
        return Ok(());
    }
    let jobs = slurm::submit(&plan)?;
    println!(
        "submitted array job {} ({} tasks) and merge job {} (runs when every task succeeded)",
        jobs.array, plan.tasks, jobs.merge
    );
    println!("logs: {}", plan.out.join(slurm::LOGS_DIR).display());
    if !args.wait {
        println!("the ensemble files appear in {dir} when the merge job ends; to resume, run the same command again");
        return Ok(());
    }
    match slurm::wait(&plan, &jobs, Duration::from_secs(2))? {
        WaitOutcome::Done => {
            println!(
                "done: ensemble files in {dir} (log {})",
                plan.merge_log().display()
            );
            Ok(())
        }
        WaitOutcome::Failed(failures) => {
            let list: Vec<String> = failures.iter().map(|f| f.to_string()).collect();
            let merge_failed = failures.iter().any(|f| f.what == "the merge");
            Err(JobsFailed(format!(
                "{} {}: {}; {}; run the same command again to resume",
                if merge_failed {
                    "merge job"
                } else {
                    "array job"
                },
                if merge_failed {
                    &jobs.merge
                } else {
                    &jobs.array
                },
                list.join("; "),
                if merge_failed {
                    "the shards are complete".to_string()
                } else {
                    format!("so the merge (job {}) did not run", jobs.merge)
                }
            ))
            .into())
        }
    }
}
