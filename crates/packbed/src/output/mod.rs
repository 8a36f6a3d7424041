//! The output directory of one run or analysis: tables, `summary.json`,
//! pictures, plots and exports, staged together so that either all appear or
//! none does. Above [`crate::io`] (the files) and [`crate::render`] (the
//! pictures), so that neither needs the other.

use crate::analysis::psd::PsdSummary;
use crate::analysis::{coordination, Contacts};
use crate::bed::Bed;
use crate::config::LengthUnit;
use crate::error::{Error, Result};
use crate::io::summary::{AnalyzeSummary, RunSummary};
use crate::io::{export, tables, Staging};
#[cfg(feature = "render")]
use crate::render::run_files::pictures;
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

/// What a writer wrote, and the warnings its `summary.json` holds: what an
/// optional stage or a picture could not do, the run kept all the same.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// The files, in writing order.
    pub files: Vec<PathBuf>,
    /// One line each, as under `warnings` in `summary.json`.
    pub warnings: Vec<String>,
}

/// Writes the files of one run into `dir` (created if needed). Either all files
/// appear, or none does and a directory created for them is removed again.
pub fn write_run<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    contacts: &Contacts,
    summary: &RunSummary,
) -> Result<Vec<PathBuf>> {
    write_run_with(dir, bed, contacts, summary, &RunExtras::default()).map(|w| w.files)
}

/// [`write_run`] plus pictures, plots and exports, all in the same atomic
/// staging. A picture that cannot be drawn (after hours of deposition, say)
/// is left out and named under `warnings`; any other failure leaves no file.
pub fn write_run_with<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    contacts: &Contacts,
    summary: &RunSummary,
    extras: &RunExtras,
) -> Result<Written> {
    let psd = summary
        .psd
        .as_ref()
        .map(|p| (p, summary.config.analysis.length_unit));
    let (files, missing) = extra_files(
        bed,
        contacts,
        &summary.analysis,
        summary.config.analysis.contact_tol,
        summary.config.analysis.chain_angle_from,
        summary.config.analysis.length_unit,
        psd,
        extras,
    )?;
    stage_dir(dir, Some(bed), contacts, files, missing, summary)
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
) -> Result<Written> {
    let (files, missing) = extra_files(
        bed,
        contacts,
        &summary.analysis,
        summary.settings.contact_tol,
        summary.settings.chain_angle_from,
        // The summary of `analyze` does not record a unit.
        None,
        None,
        extras,
    )?;
    stage_dir::<D, _>(dir, None, contacts, files, missing, summary)
}

/// A `summary.json` that names under `warnings` what its directory lacks.
trait WarnedSummary: Clone {
    fn warnings(&self) -> &Vec<String>;
    fn warnings_mut(&mut self) -> &mut Vec<String>;
    fn to_json(&self) -> Result<String>;
}

impl WarnedSummary for RunSummary {
    fn warnings(&self) -> &Vec<String> {
        &self.warnings
    }
    fn warnings_mut(&mut self) -> &mut Vec<String> {
        &mut self.warnings
    }
    fn to_json(&self) -> Result<String> {
        RunSummary::to_json(self)
    }
}

impl WarnedSummary for AnalyzeSummary {
    fn warnings(&self) -> &Vec<String> {
        &self.warnings
    }
    fn warnings_mut(&mut self) -> &mut Vec<String> {
        &mut self.warnings
    }
    fn to_json(&self) -> Result<String> {
        AnalyzeSummary::to_json(self)
    }
}

/// Stages the tables (`particles.csv` only with a bed), the extra files and,
/// last, so that a complete `summary.json` means a complete directory, the
/// summary, naming the `missing` pictures; then commits them together.
fn stage_dir<const D: usize, S: WarnedSummary>(
    dir: &Path,
    bed: Option<&Bed<D>>,
    contacts: &Contacts,
    files: Vec<(String, Content)>,
    missing: Vec<String>,
    summary: &S,
) -> Result<Written> {
    let mut summary = std::borrow::Cow::Borrowed(summary);
    if !missing.is_empty() {
        summary.to_mut().warnings_mut().extend(missing);
    }
    // Rendered before touching the disk: a bad value must not leave a directory.
    let json = summary.to_json()?;
    let mut out = Staging::new(dir)?;
    if let Some(bed) = bed {
        out.stage(RUN_FILES[0], |w| tables::write_particles(w, bed))?;
    }
    out.stage(RUN_FILES[1], |w| tables::write_contacts(w, contacts))?;
    out.stage(RUN_FILES[2], |w| tables::write_wall_contacts(w, contacts))?;
    for (name, content) in &files {
        match content {
            Content::Bytes(bytes) => out.stage(name, |w| w.write_all(bytes))?,
            Content::Stream(write) => out.stage(name, |w| write(w))?,
        }
    }
    out.stage(RUN_FILES[3], |w| w.write_all(json.as_bytes()))?;
    Ok(Written {
        files: out.commit()?,
        warnings: summary.warnings().clone(),
    })
}

/// `(file name, contents)` of the pictures, plots and exports `extras` asks
/// for, in writing order, and a warning for each picture that could not be
/// drawn.
// The settings come from either a run's or an analysis' summary, which share
// no type to pass instead.
#[allow(clippy::too_many_arguments)]
fn extra_files<'a, const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    measures: &'a crate::analysis::Summary,
    contact_tol: crate::math::Real,
    angle_from: crate::analysis::orientation::AngleFrom,
    length_unit: Option<LengthUnit>,
    psd: Option<(&PsdSummary, Option<LengthUnit>)>,
    extras: &RunExtras,
) -> Result<Extras<'a>> {
    let mut out = Vec::new();
    let mut missing = Vec::new();
    if let Some((p, _)) = psd {
        let mut buf = Vec::new();
        crate::io::psd::write_psd(&mut buf, p).map_err(|e| Error::Io {
            path: crate::io::psd::PSD_FILE.into(),
            source: e,
        })?;
        out.push((crate::io::psd::PSD_FILE.to_string(), Content::Bytes(buf)));
    }
    if let Some(t) = &measures.pore_tables {
        // Written straight into their staged files, not drawn beforehand:
        // at 10^6 spheres their text is some 5 GB (a 7.3 GB peak for
        // `analyze`).
        use crate::io::pores::{write_network_vtp, write_pores, write_throats, PORE_FILES};
        let size: Vec<f64> = bed.container.size.0.to_vec();
        let writers: [Stream; 3] = [
            Box::new(move |w| write_pores(w, t)),
            Box::new(move |w| write_throats(w, t)),
            Box::new(move |w| write_network_vtp(w, t, &size)),
        ];
        for (name, write) in PORE_FILES.iter().zip(writers) {
            out.push((name.to_string(), Content::Stream(write)));
        }
    }
    if extras.pictures {
        // Only the PSD plot, a picture of the `render` feature, adds to it.
        #[cfg_attr(not(feature = "render"), allow(unused_mut))]
        let mut drawn = pictures(
            bed,
            contacts,
            measures,
            contact_tol,
            angle_from,
            length_unit,
        )?;
        #[cfg(feature = "render")]
        if let Some((p, unit)) = psd {
            crate::render::run_files::psd_plot(&mut drawn, p, unit.map(LengthUnit::symbol));
        }
        out.extend(drawn.0.into_iter().map(|(n, b)| (n, Content::Bytes(b))));
        missing.extend(drawn.1);
    }
    if !extras.exports.is_empty() {
        let z = coordination(bed, contacts);
        for f in &extras.exports {
            let mut buf = Vec::new();
            f.write(&mut buf, bed, &z).map_err(|e| Error::Io {
                path: f.file_name().into(),
                source: e,
            })?;
            out.push((f.file_name().to_string(), Content::Bytes(buf)));
        }
    }
    Ok((out, missing))
}

/// A file's contents for the staging: drawn beforehand, or written straight
/// into the staged file.
enum Content<'a> {
    Bytes(Vec<u8>),
    Stream(Stream<'a>),
}

type Stream<'a> = Box<dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()> + 'a>;

/// The extra files, in writing order, and a warning for each picture left
/// out.
type Extras<'a> = (Vec<(String, Content<'a>)>, Vec<String>);

/// Refuses an output directory that cannot be created or written, before the
/// work, so that a long run does not fail at its very end.
pub fn check_out_dir(out: &Path) -> Result<()> {
    let existing = out
        .ancestors()
        .find(|a| a.as_os_str().is_empty() || a.exists());
    if let Some(a) = existing {
        if !a.as_os_str().is_empty() && !a.is_dir() {
            return Err(Error::Impossible(format!(
                "{} exists and is not a directory",
                a.display()
            )));
        }
    }
    crate::io::atomic::probe_dir(out)
}

/// Writes one file (a picture, say) through a temporary file and a rename, so
/// that it appears whole or not at all.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| Error::Impossible(format!("{}: not a file name", path.display())))?;
    let mut s = Staging::new(dir)?;
    s.stage(name, |w| w.write_all(bytes))?;
    s.commit().map(drop)
}

/// Without the `render` feature a build has no pictures: asking for them is
/// an error, not a silent omission.
#[cfg(not(feature = "render"))]
// The type of `render::run_files::Pictures`, which this build does not have.
#[allow(clippy::type_complexity)]
pub(crate) fn pictures<const D: usize>(
    _: &Bed<D>,
    _: &Contacts,
    _: &crate::analysis::Summary,
    _: crate::math::Real,
    _: crate::analysis::orientation::AngleFrom,
    _: Option<crate::config::LengthUnit>,
) -> Result<(Vec<(String, Vec<u8>)>, Vec<String>)> {
    Err(no_pictures())
}

/// The pictures of a run that could be drawn, and a warning for each that
/// could not: a picture never costs the run its bed and measures.
#[derive(Debug, Default)]
pub struct Drawn {
    /// `(file name, contents)`, in writing order.
    pub files: Vec<(String, Vec<u8>)>,
    /// "plot_x.png not written: why", one for each picture left out.
    pub missing: Vec<String>,
}

impl Drawn {
    /// Keeps the picture `name` if `made` is one, else says it is missing.
    pub fn keep(&mut self, name: String, made: Result<Vec<u8>>) {
        match made {
            Ok(bytes) => self.files.push((name, bytes)),
            Err(e) => self
                .missing
                .push(crate::error::picture_not_written(&name, &e)),
        }
    }
}

/// The error of a build without the `render` feature asked for pictures.
#[cfg(not(feature = "render"))]
pub(crate) fn no_pictures() -> Error {
    Error::Impossible(
        "this packbed was built without pictures (the `render` feature); ask for no pictures"
            .into(),
    )
}

/// Names of the tables [`write_fragmentation`] writes (pictures aside).
pub const FRAGMENT_FILES: [&str; 3] = ["bonds.csv", "breakage.csv", "summary.json"];

/// Writes the files of `packbed fragment` into `dir`, atomically: the bond
/// and breakage tables, the force and breakage pictures (with `pictures`),
/// and last `summary.json`.
pub fn write_fragmentation<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    frag: &crate::mechanics::Fragmentation<D>,
    summary: &crate::io::summary::FragmentSummary,
    pictures: bool,
) -> Result<Written> {
    // The breakage may have taken minutes: pictures that cannot be drawn
    // are left out and named, not the loss of the tables.
    let mut summary = std::borrow::Cow::Borrowed(summary);
    let files = match fragmentation_pictures(bed, frag, pictures) {
        Ok(files) => files,
        Err(e) => {
            summary.to_mut().warnings.push(format!(
                "pictures forces.png|svg and breakage.png|svg not written ({e}); the tables are complete"
            ));
            Vec::new()
        }
    };
    let json = summary.to_json()?;
    let mut out = Staging::new(dir)?;
    out.stage(FRAGMENT_FILES[0], |w| {
        crate::io::fragmentation::write_bonds(w, frag)
    })?;
    out.stage(FRAGMENT_FILES[1], |w| {
        crate::io::fragmentation::write_breakage(w, frag)
    })?;
    for (name, bytes) in &files {
        out.stage(name, |w| w.write_all(bytes))?;
    }
    out.stage(FRAGMENT_FILES[2], |w| w.write_all(json.as_bytes()))?;
    Ok(Written {
        files: out.commit()?,
        warnings: summary.warnings.clone(),
    })
}

#[cfg(feature = "render")]
fn fragmentation_pictures<const D: usize>(
    bed: &Bed<D>,
    frag: &crate::mechanics::Fragmentation<D>,
    pictures: bool,
) -> Result<Vec<(String, Vec<u8>)>> {
    if pictures {
        crate::render::fragmentation_pictures(bed, frag)
    } else {
        Ok(Vec::new())
    }
}

/// Without the `render` feature there are no pictures: asked for, they are
/// the error that [`write_fragmentation`] turns into a warning, not a silent
/// omission.
#[cfg(not(feature = "render"))]
fn fragmentation_pictures<const D: usize>(
    _bed: &Bed<D>,
    _frag: &crate::mechanics::Fragmentation<D>,
    pictures: bool,
) -> Result<Vec<(String, Vec<u8>)>> {
    if pictures {
        Err(no_pictures())
    } else {
        Ok(Vec::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_picture_that_cannot_be_drawn_is_a_warning_naming_it() {
        let mut d = Drawn::default();
        d.keep("a.png".into(), Ok(vec![1]));
        d.keep("b.png".into(), Err(Error::Impossible("too small".into())));
        assert_eq!(d.files, [("a.png".to_string(), vec![1])]);
        assert_eq!(
            d.missing,
            ["picture b.png not written (too small); the other files are complete"]
        );
    }
}
