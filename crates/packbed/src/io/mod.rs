//! Files: what a run writes (`particles.csv`, `contacts.csv`, `wall_contacts.csv`,
//! `summary.json`), written atomically. Layouts are in `spec/interfaces.md`.

pub mod atomic;
pub mod export;
mod finite;
pub mod read;
pub mod summary;
pub mod tables;

pub use atomic::Staging;
pub use summary::{AnalyzeSummary, RunSummary, Timing};

use crate::analysis::Contacts;
use crate::bed::Bed;
use crate::error::Result;
use std::path::{Path, PathBuf};

/// Names of the files [`write_run`] writes, in the order they appear.
pub const RUN_FILES: [&str; 4] = [
    "particles.csv",
    "contacts.csv",
    "wall_contacts.csv",
    "summary.json",
];

/// What a run writes besides its tables and summary: pictures, plots, exports.
#[derive(Clone, Debug, Default)]
pub struct RunExtras {
    /// Write `bed.png` (and `bed.svg` in 2D) and the plots.
    pub pictures: bool,
    /// Exports requested with `--export`.
    pub exports: Vec<export::Format>,
}

/// Writes the files of one run into `dir` (created if needed). Either all files
/// appear, or none does and a directory created for them is removed again.
pub fn write_run<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    contacts: &Contacts,
    summary: &RunSummary,
) -> Result<Vec<PathBuf>> {
    write_run_with(dir, bed, contacts, summary, &RunExtras::default())
}

/// [`write_run`] plus pictures, plots and exports, all in the same atomic
/// staging: a failure in any of them leaves no file of the run.
pub fn write_run_with<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    contacts: &Contacts,
    summary: &RunSummary,
    extras: &RunExtras,
) -> Result<Vec<PathBuf>> {
    // Rendered before touching the disk: a bad value must not leave a directory.
    let json = summary.to_json()?;
    let files = if extras.pictures || !extras.exports.is_empty() {
        crate::render::run_files::files(
            bed,
            contacts,
            summary.config.analysis.contact_tol,
            summary.config.analysis.chain_angle_from,
            extras,
        )?
    } else {
        Vec::new()
    };
    let mut out = Staging::new(dir)?;
    out.stage(RUN_FILES[0], |w| tables::write_particles(w, bed))?;
    out.stage(RUN_FILES[1], |w| tables::write_contacts(w, contacts))?;
    out.stage(RUN_FILES[2], |w| tables::write_wall_contacts(w, contacts))?;
    for (name, bytes) in &files {
        out.stage(name, |w| w.write_all(bytes))?;
    }
    // Last, so that a complete summary.json means a complete run.
    out.stage(RUN_FILES[3], |w| w.write_all(json.as_bytes()))?;
    out.commit()
}

/// Names of the files [`write_analysis`] writes: a run's files minus the bed.
pub const ANALYZE_FILES: [&str; 3] = ["contacts.csv", "wall_contacts.csv", "summary.json"];

/// Writes the files of `packbed analyze` into `dir`, atomically as [`write_run`],
/// with the pictures, plots and exports `extras` asks for.
pub fn write_analysis<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    contacts: &Contacts,
    summary: &AnalyzeSummary,
    extras: &RunExtras,
) -> Result<Vec<PathBuf>> {
    let json = summary.to_json()?;
    let files = if extras.pictures || !extras.exports.is_empty() {
        crate::render::run_files::files(
            bed,
            contacts,
            summary.settings.contact_tol,
            summary.settings.chain_angle_from,
            extras,
        )?
    } else {
        Vec::new()
    };
    let mut out = Staging::new(dir)?;
    out.stage(ANALYZE_FILES[0], |w| tables::write_contacts(w, contacts))?;
    out.stage(ANALYZE_FILES[1], |w| {
        tables::write_wall_contacts(w, contacts)
    })?;
    for (name, bytes) in &files {
        out.stage(name, |w| w.write_all(bytes))?;
    }
    out.stage(ANALYZE_FILES[2], |w| w.write_all(json.as_bytes()))?;
    out.commit()
}
