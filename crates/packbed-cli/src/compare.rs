//! `packbed compare DIR DIR...`: beds side by side.

use anyhow::Result;
use clap::Args;
use packbed::compare::{compare as compare_groups, read_groups, write_comparison};
use std::path::PathBuf;

/// Arguments of `packbed compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Runs, ensembles or sweeps (each sweep value a group; one sweep alone is enough); the first group is the reference.
    #[arg(required = true, num_args = 1.., value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Where compare.md, compare.csv, compare.json and the plots go.
    #[arg(long, value_name = "DIR", default_value = "packbed-compare")]
    pub out: PathBuf,
    /// No plots.
    #[arg(long)]
    pub no_pictures: bool,
}

/// Runs `packbed compare`.
pub fn compare(args: CompareArgs) -> Result<()> {
    crate::run::check_out_dir(&args.out)?;
    let groups = read_groups(&args.dirs)?;
    let c = compare_groups(&groups)?;
    let files = write_comparison(&args.out, &groups, &c, !args.no_pictures)?;
    eprint!("{}", packbed::text::warning_lines(&c.warnings));
    let beds: Vec<String> = c
        .groups
        .iter()
        .map(|(g, n)| format!("{g} ({n} beds)"))
        .collect();
    println!("packbed compare: {}", beds.join(" against "));
    print!("{}", c.to_text(&args.out));
    let names = packbed::text::file_names(&files);
    println!("  files in {}: {names}", args.out.display());
    Ok(())
}
