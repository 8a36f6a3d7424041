//! `packbed slurm`: an ensemble as a Slurm job array and a merge job. The
//! scripts, the checks and the calls of `sbatch`/`squeue`/`scancel` are in
//! `packbed::slurm`; this file parses, dispatches and prints.

use crate::overrides::at_least_one;
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::slurm::{self, JobArray, Resources};
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `packbed slurm`.
#[derive(Debug, Args)]
pub struct SlurmArgs {
    #[command(flatten)]
    pub replicates: crate::ensemble::Replicates,
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

/// Runs `packbed slurm`.
pub fn slurm(args: SlurmArgs) -> Result<()> {
    let (config, runs) = args.replicates.load()?;
    if args.submit && !slurm::on_path("sbatch") {
        bail!("--submit: sbatch is not on PATH (run on a Slurm login node, or leave out --submit and submit the scripts by hand)");
    }
    let resources = Resources {
        partition: args.partition,
        time: args.time,
        cpus_per_task: args.cpus_per_task.map(|c| c.min(u32::MAX as usize) as u32),
        mem: args.mem,
        account: args.account,
        extra: args.sbatch_args,
    };
    let plan = JobArray::for_this_binary(&args.out, runs, args.tasks as u64, resources)
        .with_context(|| format!("--out {}", args.out.display()))?;
    if args.submit {
        for id in slurm::clear_queue(&plan)? {
            eprintln!("packbed: note: cancelled job {id} of an earlier submission: a task had failed, so it could never run");
        }
    }
    let prepared = slurm::prepare(&config, &plan)?;
    if let Some(note) = plan.local_dir_note() {
        eprintln!("packbed: note: {note}");
    }
    print!(
        "{}",
        slurm::prepared_text(&plan, runs, &prepared, args.submit)
    );
    if !args.submit {
        return Ok(());
    }
    let jobs = slurm::submit(&plan)?;
    print!("{}", slurm::submitted_text(&plan, &jobs, args.wait));
    if !args.wait {
        return Ok(());
    }
    println!(
        "{}",
        slurm::wait_for_merge(&plan, &jobs, Duration::from_secs(2))??
    );
    Ok(())
}
