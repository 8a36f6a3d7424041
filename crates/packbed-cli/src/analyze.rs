//! `packbed analyze PATH`: analyse an existing bed file and write the run's
//! outputs minus the bed files (summary.json, contacts.csv, wall_contacts.csv).

use crate::report;
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use packbed::analysis::orientation::AngleFrom;
use packbed::analysis::{analyze_with, overlaps, AnalysisOptions};
use packbed::bed::{AnyBed, Bed};
use packbed::io::read::{read_bed_report, BoxHint, ReadReport};
use packbed::io::summary::{AnalyzeSettings, AnalyzeTiming};
use packbed::io::{self, AnalyzeSummary};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `packbed analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// The bed file (packbed particles.csv, plain x y [z] r, LAMMPS dump, XYZ).
    pub path: PathBuf,
    /// Box: W,H (2D) or W,D,H (3D); wins over a box in the file or in the
    /// summary.json beside it.
    #[arg(long = "box", value_name = "W,[D,]H", allow_hyphen_values = true)]
    pub container: Option<String>,
    /// Periodic side boundaries (with --box).
    #[arg(long)]
    pub periodic: bool,
    /// Contact tolerance relative to the smaller radius of each pair.
    #[arg(
        long,
        value_name = "T",
        default_value_t = 1e-6,
        allow_hyphen_values = true
    )]
    pub contact_tol: f64,
    /// Percolation threshold: particles with radius >= R count as large
    /// (default: the largest of the species' median radii).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub large: Option<f64>,
    /// Bulk measures are null when the bulk region holds fewer bodies.
    #[arg(long, value_name = "N", default_value_t = packbed::analysis::BULK_MIN_BODIES)]
    pub bulk_min_bodies: u64,
    /// Measure chain angles from the vertical (default) or from the horizontal
    /// (as the source study did).
    #[arg(long, value_enum, value_name = "FROM", default_value = "vertical")]
    pub chain_angle_from: AngleFromArg,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-analysis")]
    pub out: PathBuf,
    /// Also write these exports: a comma-separated list of vtk, dump, xyz.
    #[arg(long, value_name = "LIST")]
    pub export: Option<String>,
    /// No pictures or plots (bed.png, bed.svg, plot_*.png|svg).
    #[arg(long)]
    pub no_pictures: bool,
    /// No summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `--chain-angle-from`: the library's [`AngleFrom`] for clap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AngleFromArg {
    /// Angles from the vertical: signed −90…90 in 2D, polar 0…90 in 3D.
    Vertical,
    /// Angles from the horizontal: 0…180 in 2D, elevation 0…90 in 3D.
    Horizontal,
}

impl From<AngleFromArg> for AngleFrom {
    fn from(a: AngleFromArg) -> AngleFrom {
        match a {
            AngleFromArg::Vertical => AngleFrom::Vertical,
            AngleFromArg::Horizontal => AngleFrom::Horizontal,
        }
    }
}

/// Runs `packbed analyze`.
pub fn analyze(args: AnalyzeArgs) -> Result<()> {
    if !(args.contact_tol.is_finite() && args.contact_tol >= 0.0) {
        bail!(
            "--contact-tol must be a non-negative number, got {}",
            args.contact_tol
        );
    }
    if let Some(r) = args.large {
        if !(r.is_finite() && r > 0.0) {
            bail!("--large must be a positive radius, got {r}");
        }
    }
    // Refuse a bad export list before any work.
    if let Some(list) = &args.export {
        io::export::Format::parse_list(list)?;
    }
    let hint = box_hint(&args)?;
    crate::run::check_out_dir(&args.out)?;
    let t = Instant::now();
    let (bed, read) = read_bed_report(&args.path, (!hint.size.is_empty()).then_some(&hint))?;
    let read_seconds = t.elapsed().as_secs_f64();
    let (summary, written) = match &bed {
        AnyBed::D2(b) => finish(&args, b, &read, read_seconds)?,
        AnyBed::D3(b) => finish(&args, b, &read, read_seconds)?,
    };
    if let Some(w) = report::overlap_warning(&summary) {
        eprintln!("{w}");
    }
    if !args.quiet {
        print!("{}", report::analyze_text(&summary, &args.out, &written));
    }
    Ok(())
}

fn box_hint(args: &AnalyzeArgs) -> Result<BoxHint> {
    let mut hint = BoxHint {
        size: Vec::new(),
        periodic: args.periodic,
    };
    if let Some(text) = &args.container {
        for f in text.split(',') {
            let v: f64 = f.trim().parse().map_err(|_| {
                anyhow::anyhow!(
                    "--box: `{}` is not a number (expected W,H or W,D,H)",
                    f.trim()
                )
            })?;
            if !(v.is_finite() && v > 0.0) {
                bail!("--box: sizes must be positive, got {v}");
            }
            hint.size.push(v);
        }
        if !(2..=3).contains(&hint.size.len()) {
            bail!("--box: give W,H (2D) or W,D,H (3D), got `{text}`");
        }
    } else if args.periodic {
        bail!("--periodic needs --box W,H or W,D,H");
    }
    Ok(hint)
}

fn finish<const D: usize>(
    args: &AnalyzeArgs,
    bed: &Bed<D>,
    read: &ReadReport,
    read_seconds: f64,
) -> Result<(AnalyzeSummary, Vec<PathBuf>)> {
    let t = Instant::now();
    let opts = AnalysisOptions {
        angle_from: args.chain_angle_from.into(),
        bulk_min_bodies: args.bulk_min_bodies,
        ..AnalysisOptions::new(args.contact_tol, args.large)
    };
    let (contacts, analysis) = analyze_with(bed, &opts);
    let overlaps = overlaps(bed, &contacts);
    let timing = AnalyzeTiming {
        read_seconds,
        analysis_seconds: t.elapsed().as_secs_f64(),
    };
    let settings = AnalyzeSettings {
        contact_tol: args.contact_tol,
        large_radius: args.large,
        chain_angle_from: args.chain_angle_from.into(),
    };
    let source = args.path.display().to_string();
    let summary = AnalyzeSummary::new(&source, bed, read, &overlaps, settings, &analysis, timing);
    let extras = packbed::output::RunExtras {
        pictures: !args.no_pictures,
        exports: match &args.export {
            Some(list) => io::export::Format::parse_list(list)?,
            None => Vec::new(),
        },
    };
    let written = packbed::output::write_analysis(&args.out, bed, &contacts, &summary, &extras)
        .with_context(|| format!("--out {}", args.out.display()))?;
    Ok((summary, written))
}
