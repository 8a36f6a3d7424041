//! `packbed slurm`: an ensemble as a Slurm job array and a merge job. The
//! scripts, the checks and the calls of `sbatch`/`squeue`/`scancel` are in
//! `packbed::slurm`; this file parses, dispatches and prints.

use crate::parsers::at_least_one;
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::slurm::{self, JobArray, Resources};
use packbed::text;
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
    #[command(flatten)]
    pub resources: Resources,
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
    let plan = JobArray::for_this_binary(&args.out, runs, args.tasks as u64, args.resources)
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
        text::screen(&slurm::prepared_text(&plan, runs, &prepared, args.submit))
    );
    if !args.submit {
        return Ok(());
    }
    let jobs = slurm::submit(&plan)?;
    print!(
        "{}",
        text::screen(&slurm::submitted_text(&plan, &jobs, args.wait))
    );
    if !args.wait {
        return Ok(());
    }
    println!(
        "{}",
        text::screen(&slurm::wait_for_merge(
            &plan,
            &jobs,
            Duration::from_secs(2)
        )??)
    );
    Ok(())
}
