//! `filtrate.csv` (one row per body that passed the filter medium),
//! `capture.csv` (the grade-efficiency classes) and `constrictions.csv`
//! (the medium's constrictions beside the slurry's sizes) of a bed built
//! with a medium (`docs/reference/formats.md`, "capture.csv,
//! constrictions.csv and filtrate.csv").

use crate::analysis::capture::CaptureSummary;
use serde::Serialize;
use std::io::Write;

/// The files' names: `[filtrate, capture, constrictions]`.
pub const CAPTURE_FILES: [&str; 3] = ["filtrate.csv", "capture.csv", "constrictions.csv"];

#[derive(Serialize)]
struct FiltrateRow {
    species: u32,
    radius: f64,
    beads: u32,
    x: f64,
    y: f64,
}

/// Writes `filtrate.csv`: species, radius, beads and where each body left
/// (`y` is 0 in 2D).
pub fn write_filtrate(w: &mut dyn Write, capture: &CaptureSummary) -> std::io::Result<()> {
    let mut out = csv::WriterBuilder::new().has_headers(false).from_writer(w);
    out.write_record(["species", "radius", "beads", "x", "y"])?;
    for f in &capture.filtrate {
        out.serialize(FiltrateRow {
            species: f.species,
            radius: f.radius,
            beads: f.beads,
            x: f.at[0],
            y: f.at[1],
        })
        .map_err(std::io::Error::other)?;
    }
    out.flush()
}

/// Writes `capture.csv`: one row per size class (`grade_efficiency` empty
/// for an empty class).
pub fn write_capture(w: &mut dyn Write, capture: &CaptureSummary) -> std::io::Result<()> {
    let mut out = csv::WriterBuilder::new().has_headers(false).from_writer(w);
    out.write_record([
        "d_lo",
        "d_hi",
        "fed",
        "passed",
        "lodged",
        "cake",
        "grade_efficiency",
    ])?;
    for c in &capture.classes {
        out.serialize(c).map_err(std::io::Error::other)?;
    }
    out.flush()
}

/// Writes `constrictions.csv`: the medium's constriction diameters and the
/// slurry's diameters, one row per class of one log-spaced axis.
pub fn write_constrictions(w: &mut dyn Write, capture: &CaptureSummary) -> std::io::Result<()> {
    let mut out = csv::WriterBuilder::new().has_headers(false).from_writer(w);
    out.write_record([
        "d_lo",
        "d_hi",
        "constrictions",
        "constrictions_finer",
        "slurry",
        "slurry_finer",
    ])?;
    for c in &capture.constrictions {
        out.serialize(c).map_err(std::io::Error::other)?;
    }
    out.flush()
}

/// `filtration.csv`'s name.
pub const FILTRATION_FILE: &str = "filtration.csv";

/// Writes `filtration.csv`: one row per checkpoint of the filtration, SI.
pub fn write_filtration(
    w: &mut dyn Write,
    f: &crate::analysis::filtration::FiltrationSummary,
) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    for row in &f.checkpoints {
        out.serialize(row).map_err(std::io::Error::other)?;
    }
    out.flush()
}
