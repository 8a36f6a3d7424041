//! `packbed fragment BED`: contact forces of a bed under load and the order
//! its bonds break (`spec/fragmentation.md`).

use crate::overrides::{numbers, Numbers};
use anyhow::{bail, Context, Result};
use clap::Args;
use packbed::mechanics::{Breaks, Load, Options};
use packbed::output::text;
use std::path::PathBuf;

/// Arguments of `packbed fragment`.
#[derive(Debug, Args)]
pub struct FragmentArgs {
    /// The bed file (any file `packbed analyze` reads).
    pub path: PathBuf,
    /// The load: shear (the source study's), compression or gravity.
    #[arg(long, value_name = "LOAD", default_value = "shear")]
    pub load: String,
    /// Bonds to break: a number, or `failure` (until the bed fails).
    #[arg(long, value_name = "N|failure", default_value = "failure")]
    pub breaks: String,
    /// Tangential over normal spring stiffness (k_n = 1).
    #[arg(
        long,
        value_name = "R",
        default_value_t = 1.0,
        allow_hyphen_values = true
    )]
    pub kt_kn: f64,
    /// Box: W,H (2D) or W,D,H (3D); wins over a box in the file or in the
    /// summary.json beside it.
    #[arg(long = "box", value_name = "W,[D,]H", allow_hyphen_values = true, value_parser = numbers)]
    pub container: Option<Numbers>,
    /// Periodic side boundaries (with --box).
    #[arg(long)]
    pub periodic: bool,
    /// Contact tolerance relative to the smaller radius of each pair (0 to 1).
    #[arg(
        long,
        value_name = "T",
        default_value_t = 1e-6,
        allow_hyphen_values = true
    )]
    pub contact_tol: f64,
    /// No pictures (forces.png|svg, breakage.png|svg).
    #[arg(long)]
    pub no_pictures: bool,
    /// No progress bar and no summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-fragment")]
    pub out: PathBuf,
}

/// Runs `packbed fragment`.
pub fn fragment(args: FragmentArgs) -> Result<()> {
    let load: Load = args
        .load
        .parse()
        .map_err(|e: packbed::Error| anyhow::anyhow!("--load: {}", e.message()))?;
    let breaks: Breaks = args
        .breaks
        .parse()
        .map_err(|e: packbed::Error| anyhow::anyhow!("--breaks: {}", e.message()))?;
    let options = Options {
        load,
        breaks,
        kt_over_kn: args.kt_kn,
    };
    if let Err(e) = options.check() {
        bail!("{}", e.message().replace("kt_over_kn", "--kt-kn"));
    }
    if let Some(why) = packbed::config::contact_tol_problem(args.contact_tol, "--contact-tol") {
        bail!("{why}");
    }
    let hint = crate::analyze::box_hint(args.container.as_ref(), args.periodic)?;
    crate::run::check_out_dir(&args.out)?;
    // Each break re-solves the bed: thousands of them take minutes.
    let mut progress = crate::progress::BreakProgress::new(breaks, args.quiet);
    let done = packbed::fragment_file_with(
        &args.path,
        hint.as_ref(),
        &options,
        args.contact_tol,
        &mut |n| progress.update(n),
    );
    progress.finish();
    let done = done?;
    let written = done
        .write(&args.out, !args.no_pictures)
        .with_context(|| format!("--out {}", args.out.display()))?;
    if !args.quiet {
        print!(
            "{}",
            text::fragment_text(&done.summary, &args.out, &written.files)
        );
    }
    eprint!("{}", text::warning_lines(&written.warnings));
    Ok(())
}
