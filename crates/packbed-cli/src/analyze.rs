//! `packbed analyze PATH`: analyse an existing bed file and write the run's
//! outputs minus the bed files (summary.json, contacts.csv, wall_contacts.csv).

use crate::overrides::{numbers, Numbers};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use packbed::analysis::orientation::AngleFrom;
use packbed::check_box_hint;
use packbed::config::{AnalysisConfig, LengthUnit};
use packbed::io::read::BoxHint;
use packbed::output::text;
use std::path::PathBuf;

/// Arguments of `packbed analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// The bed file (packbed particles.csv, plain x y [z] r, LAMMPS dump, XYZ).
    pub path: PathBuf,
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
    /// Percolation threshold: particles with radius >= R count as large
    /// (default: the largest of the species' volume-median radii).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub large: Option<f64>,
    /// Bulk measures are null when the bulk region holds fewer bodies.
    #[arg(long, value_name = "N", default_value_t = packbed::analysis::BULK_MIN_BODIES)]
    pub bulk_min_bodies: u64,
    /// Measure chain angles from the vertical (default) or from the horizontal
    /// (as the source study did).
    #[arg(long, value_enum, value_name = "FROM", default_value = "vertical")]
    pub chain_angle_from: AngleFromArg,
    /// Density of the solid in kg/m³ (with --length-unit): the specific cake
    /// resistance and the solids' mass per area.
    #[arg(long, value_name = "KG_PER_M3")]
    pub solid_density: Option<f64>,
    /// The length of one unit of the bed file's lengths: permeabilities in m².
    #[arg(long, value_enum, value_name = "UNIT")]
    pub length_unit: Option<LengthUnitArg>,
    #[command(flatten)]
    pub measures: crate::overrides::MeasuresArg,
    #[command(flatten)]
    pub files: crate::run::FileArgs,
    /// Directory for the output files (created if needed).
    #[arg(long, value_name = "DIR", default_value = "packbed-analysis")]
    pub out: PathBuf,
}

/// `--chain-angle-from`: the library's [`AngleFrom`] for clap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AngleFromArg {
    /// Angles from the vertical: signed −90…90 in 2D, polar 0…90 in 3D.
    Vertical,
    /// Angles from the horizontal: 0…180 in 2D, elevation 0…90 in 3D.
    Horizontal,
}

/// `--length-unit`: the library's [`LengthUnit`] for clap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LengthUnitArg {
    /// Metre.
    M,
    /// Millimetre.
    Mm,
    /// Micrometre.
    Um,
    /// Nanometre.
    Nm,
}

impl From<LengthUnitArg> for LengthUnit {
    fn from(u: LengthUnitArg) -> Self {
        match u {
            LengthUnitArg::M => LengthUnit::Metre,
            LengthUnitArg::Mm => LengthUnit::Millimetre,
            LengthUnitArg::Um => LengthUnit::Micrometre,
            LengthUnitArg::Nm => LengthUnit::Nanometre,
        }
    }
}

/// Runs `packbed analyze`.
pub fn analyze(args: AnalyzeArgs) -> Result<()> {
    let settings = AnalysisConfig {
        contact_tol: args.contact_tol,
        large_radius: args.large,
        bulk_min_bodies: args.bulk_min_bodies,
        chain_angle_from: match args.chain_angle_from {
            AngleFromArg::Vertical => AngleFrom::Vertical,
            AngleFromArg::Horizontal => AngleFrom::Horizontal,
        },
        measures: args.measures.list.clone(),
        solid_density: args.solid_density,
        length_unit: args.length_unit.map(LengthUnit::from),
        flow: Default::default(),
    };
    if let Err(e) = settings.check() {
        // The library names the settings; say the options that set them.
        let m = e.message();
        let m = m.replace("analysis.contact_tol", "--contact-tol");
        let m = m.replace("analysis.solid_density", "--solid-density");
        let m = m.replace("analysis.length_unit", "--length-unit");
        bail!("{}", m.replace("analysis.large_radius", "--large"));
    }
    // Refuse a bad export list or output folder before any work.
    let extras = args.files.extras()?;
    let hint = box_hint(args.container.as_ref(), args.periodic)?;
    crate::run::check_out_dir(&args.out)?;
    let analyzed = packbed::analyze_file(&args.path, hint.as_ref(), &settings)?;
    let written = analyzed
        .write_with(&args.out, &extras)
        .with_context(|| format!("--out {}", args.out.display()))?;
    let overlap = text::overlap_warning(&analyzed.summary);
    eprint!(
        "{}",
        text::warning_lines(overlap.iter().chain(&written.warnings))
    );
    if !args.files.quiet {
        print!(
            "{}",
            text::analyze_text(&analyzed.summary, &args.out, &written.files)
        );
    }
    Ok(())
}

/// The box of `--box` and `--periodic` for a bed file, checked (`packbed
/// analyze` and `packbed fragment`).
pub fn box_hint(container: Option<&Numbers>, periodic: bool) -> Result<Option<BoxHint>> {
    let hint = match (container, periodic) {
        (Some(size), periodic) => BoxHint {
            size: size.clone(),
            periodic,
        },
        (None, true) => bail!("--periodic needs --box W,H or W,D,H"),
        (None, false) => return Ok(None),
    };
    check_box_hint(&hint).map_err(|e| anyhow::anyhow!("{}", e.within("--box").message()))?;
    Ok(Some(hint))
}
