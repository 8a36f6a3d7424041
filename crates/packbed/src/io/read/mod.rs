//! Readers of bed files: packbed's `particles.csv` (box from the `summary.json`
//! beside it), plain CSV or whitespace `x y [z] r` tables with or without a
//! header, LAMMPS dumps, extended XYZ and packbed's own `bed.vtu`.
//!
//! One entry point, [`read_bed`]: the format is recognised from the content
//! (and the extension for VTK), the dimension from the columns or box. The box
//! comes from the file where it has one, else from the caller's [`BoxHint`].
//! Every problem is an [`Error::Data`](crate::error::Error::Data) naming the file and the 1-based line.
//!
//! Modules: [`report`] (the box hint and what reading found), one per format
//! (`table`, `lammps`, `xyz`, `vtu`), and the checks every format
//! shares (`checks`) on the particles collected in `raw`.

mod checks;
mod lammps;
pub(crate) mod medium;
mod raw;
pub mod report;
mod table;
mod vtu;
mod xyz;

pub use report::{BoxHint, BoxSource, ReadReport};

use crate::bed::AnyBed;
use crate::error::Result;
use raw::Reader;
use std::path::Path;

/// Reads a bed file. `box_hint` is used when the file carries no box (plain
/// tables; `particles.csv` without a `summary.json` beside it).
pub fn read_bed(path: &Path, box_hint: Option<&BoxHint>) -> Result<AnyBed> {
    read_bed_report(path, box_hint).map(|(bed, _)| bed)
}

/// [`read_bed`], also telling where the box came from. A given `box_hint` wins
/// over a box in the file (or in the `summary.json` beside it).
pub fn read_bed_report(path: &Path, box_hint: Option<&BoxHint>) -> Result<(AnyBed, ReadReport)> {
    read_bed_for(path, box_hint, &crate::config::Measure::DEFAULT)
}

/// [`read_bed_report`] of a bed to be analysed with `measures`: a bed this
/// machine could not analyse with them is refused once its particles are
/// counted, quoting the estimate for those measures (the pore space's
/// included when they ask for it).
pub fn read_bed_for(
    path: &Path,
    box_hint: Option<&BoxHint>,
    measures: &[crate::config::Measure],
) -> Result<(AnyBed, ReadReport)> {
    let text = crate::input::read_text(path)?;
    let r = Reader { path };
    let first = text
        .lines()
        .enumerate()
        .find(|(_, l)| !l.trim().is_empty())
        .map(|(k, l)| (k, l.trim().to_string()));
    let Some((first_line, first)) = first else {
        return Err(r.err(1, "the file is empty"));
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let raw = if first.starts_with("ITEM:") {
        r.dump(&text)?
    } else if first.starts_with("<?xml") || first.starts_with("<VTKFile") || ext == "vtu" {
        r.vtu(&text)?
    } else if first.parse::<u64>().is_ok()
        && text
            .lines()
            .nth(first_line + 1)
            .is_some_and(|l| l.contains('='))
    {
        r.xyz(&text, first_line)?
    } else {
        r.table(&text, box_hint)?
    };
    drop(text);
    crate::config::check_analysis(raw.pos.len(), 3, measures, 1.0, &path.display().to_string())?;
    r.finish(raw, box_hint)
}
