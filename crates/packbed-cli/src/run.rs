//! `packbed run`: config (file and overrides) → deposition → analysis → files.

use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
use packbed::{text, ExportFormat as Format, RunExtras};
use std::path::{Path, PathBuf};

/// Arguments of `packbed run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Config file (TOML); without it, the default bed (see `packbed example`).
    #[arg(value_name = "CONFIG.toml")]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: packbed::Overrides,
    #[command(flatten)]
    pub files: FileArgs,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-out")]
    pub out: PathBuf,
}

/// What a command shows besides its tables: pictures, progress, a summary.
#[derive(Debug, Args)]
pub struct Shown {
    /// No pictures or plots (PNG, SVG).
    #[arg(long)]
    pub no_pictures: bool,
    /// No progress bar and no summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

impl Shown {
    /// Prints the summary `text` on stdout (unless quiet) and the `warnings`
    /// on stderr (always).
    pub fn report<S: AsRef<str>>(
        &self,
        text: impl FnOnce() -> String,
        warnings: impl IntoIterator<Item = S>,
    ) {
        if !self.quiet {
            // Names and paths are escaped where they are written; this is
            // the last guard for whatever else a summary quotes.
            print!("{}", text::screen(&text()));
        }
        eprint!("{}", text::warning_lines(warnings));
    }
}

/// A list of export formats, one option value (an alias, as [`packbed::Numbers`]).
type Formats = Vec<Format>;

/// What `run` and `analyze` write besides their tables, and what they print.
#[derive(Debug, Args)]
pub struct FileArgs {
    /// Also write these exports: a comma-separated list of vtk, dump, xyz.
    #[arg(long, value_name = "LIST", value_parser = |s: &str| Format::parse_list(s).map_err(|e| e.message()))]
    pub export: Option<Formats>,
    #[command(flatten)]
    pub shown: Shown,
}

impl FileArgs {
    /// The pictures and exports to write.
    pub fn extras(&self) -> RunExtras {
        RunExtras {
            pictures: !self.shown.no_pictures,
            exports: self.export.clone().unwrap_or_default(),
        }
    }
}

/// Runs `packbed run`.
pub fn run(args: RunArgs) -> Result<()> {
    let settings = &args.overrides;
    let config = settings.applied_to_file(args.config.as_deref())?;
    // Planned (validated) once, before any work or output.
    let plan =
        packbed::planned(&config).with_context(|| settings.source(args.config.as_deref()))?;
    let extras = args.files.extras();
    check_out_dir(&args.out)?;
    let mut progress = Progress::new(plan.estimated_particles(), args.files.shown.quiet);
    let finished = packbed::run_planned(&config, &plan, &mut |n| {
        progress.update(n);
        std::ops::ControlFlow::Continue(())
    });
    progress.finish();
    let finished = finished?;
    let written = finished.write_with(&args.out, &extras)?;
    let summary = || text::run_text(&finished.summary, &args.out, &written.files);
    args.files.shown.report(summary, &written.warnings);
    Ok(())
}

/// Refuses an output directory that cannot be created or written before the
/// run, so that a long run does not fail at its very end.
pub fn check_out_dir(out: &Path) -> Result<()> {
    packbed::check_out_dir(out).with_context(|| format!("--out {}", out.display()))
}
