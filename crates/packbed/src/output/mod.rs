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
    #[cfg_attr(not(feature = "render"), allow(unused_mut))]
    let mut made = extra_files(
        bed,
        contacts,
        &summary.analysis,
        summary.config.analysis.contact_tol,
        summary.config.analysis.chain_angle_from,
        summary.config.analysis.length_unit,
        psd,
        extras,
    )?;
    let mut tables = vec![(
        RUN_FILES[0].to_string(),
        Content::Stream(Box::new(move |w| tables::write_particles(w, bed))),
    )];
    #[cfg(feature = "render")]
    if extras.pictures {
        let mut drawn: crate::render::run_files::Pictures = (Vec::new(), Vec::new());
        crate::render::run_files::filtration_plots(
            &mut drawn,
            summary.capture.as_ref(),
            summary.filtration.as_ref(),
            summary.config.analysis.length_unit.map(LengthUnit::symbol),
        );
        made.pictures.extend(drawn.0);
        made.missing.extend(drawn.1);
    }
    tables.extend(contact_tables(contacts));
    tables.extend(made.tables);
    if let Some(capture) = &summary.capture {
        use crate::io::capture::{
            write_capture, write_constrictions, write_filtrate, CAPTURE_FILES,
        };
        tables.push((
            CAPTURE_FILES[0].to_string(),
            Content::Stream(Box::new(move |w| write_filtrate(w, capture))),
        ));
        tables.push((
            CAPTURE_FILES[1].to_string(),
            Content::Stream(Box::new(move |w| write_capture(w, capture))),
        ));
        if !capture.constrictions.is_empty() {
            tables.push((
                CAPTURE_FILES[2].to_string(),
                Content::Stream(Box::new(move |w| write_constrictions(w, capture))),
            ));
        }
    }
    if let Some(f) = &summary.filtration {
        use crate::io::capture::{write_filtration, FILTRATION_FILE};
        tables.push((
            FILTRATION_FILE.to_string(),
            Content::Stream(Box::new(move |w| write_filtration(w, f))),
        ));
    }
    let summary = warned(summary, made.missing);
    stage_dir(dir, tables, made.pictures, summary, |n| {
        earlier_file(n, true)
    })
}

/// `contacts.csv` and `wall_contacts.csv`, written straight into their files.
fn contact_tables(contacts: &Contacts) -> [(String, Content<'_>); 2] {
    [
        (
            RUN_FILES[1].to_string(),
            Content::Stream(Box::new(move |w| tables::write_contacts(w, contacts))),
        ),
        (
            RUN_FILES[2].to_string(),
            Content::Stream(Box::new(move |w| tables::write_wall_contacts(w, contacts))),
        ),
    ]
}

/// `summary` with the `missing` pictures named under its warnings.
fn warned<S: WarnedSummary>(summary: &S, missing: Vec<String>) -> std::borrow::Cow<'_, S> {
    let mut summary = std::borrow::Cow::Borrowed(summary);
    if !missing.is_empty() {
        summary.to_mut().warnings_mut().extend(missing);
    }
    summary
}

/// Whether `name` is a file that `run`, `analyze` or `fragment` writes: in
/// a directory whose `summary.json` is packbed's, such a file that the new
/// run does not write is an earlier run's, and is removed. The bed files
/// (`particles.csv` and the exports) only when the new run writes a bed:
/// they may be the input of `analyze` or `fragment`.
pub fn earlier_file(name: &str, beds: bool) -> bool {
    use crate::io::pores::PORE_FILES;
    let picture = name
        .strip_suffix(".png")
        .or_else(|| name.strip_suffix(".svg"))
        .is_some_and(|stem| {
            stem.starts_with("plot_")
                || [
                    "bed",
                    "forces",
                    "breakage",
                    "agglomerates",
                    "agglomerates_agitated",
                ]
                .contains(&stem)
        });
    let bed = name == RUN_FILES[0]
        || [
            export::Format::Vtk,
            export::Format::Dump,
            export::Format::Xyz,
        ]
        .iter()
        .any(|f| f.file_name() == name);
    picture
        || (beds && bed)
        || RUN_FILES[1..].contains(&name)
        || FRAGMENT_FILES.contains(&name)
        || PORE_FILES.contains(&name)
        || crate::io::liquid::LIQUID_FILES.contains(&name)
        || crate::io::solid_bridges::DRYING_FILES.contains(&name)
        || name == crate::io::psd::PSD_FILE
        || crate::io::capture::CAPTURE_FILES.contains(&name)
        || name == crate::io::capture::FILTRATION_FILE
}

/// Whether `dir` holds a `summary.json` that packbed wrote (a JSON object
/// with `packbed_version`): its other files are then a run's, not the user's.
fn packbed_dir(dir: &Path) -> bool {
    std::fs::read(dir.join(RUN_FILES[3]))
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
        .is_some_and(|v| v.get("packbed_version").is_some())
}

/// Writes the files of `packbed analyze` into `dir`, atomically as [`write_run`],
/// with the pictures, plots and exports `extras` asks for.
pub fn write_analysis<const D: usize>(
    dir: &Path,
    bed: &Bed<D>,
    contacts: &Contacts,
    summary: &AnalyzeSummary,
    extras: &RunExtras,
) -> Result<Written> {
    let made = extra_files(
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
    let mut tables = Vec::from(contact_tables(contacts));
    tables.extend(made.tables);
    let summary = warned(summary, made.missing);
    stage_dir(dir, tables, made.pictures, summary, |n| {
        earlier_file(n, false)
    })
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

/// Stages the `tables`, the `pictures` and, last, so that a complete
/// `summary.json` means a complete directory, the summary; then commits them
/// together, removing the files of an earlier run (those `earlier` names, in
/// a directory whose `summary.json` is packbed's).
///
/// A full disk never costs the tables: a picture that cannot be written is
/// left out and named under `warnings` (and all pictures are, when the
/// summary then does not fit). A table that cannot be written ends the
/// write, but the complete tables before it are kept and named.
fn stage_dir<S: WarnedSummary>(
    dir: &Path,
    tables: Vec<(String, Content)>,
    pictures: Vec<(String, Vec<u8>)>,
    mut summary: std::borrow::Cow<'_, S>,
    earlier: impl Fn(&str) -> bool,
) -> Result<Written> {
    // Rendered before touching the disk: a bad value must not leave a directory.
    let mut json = summary.to_json()?;
    let replacing = packbed_dir(dir);
    let earlier = |name: &str| replacing && earlier(name);
    let mut out = Staging::new(dir)?;
    for (name, content) in &tables {
        let staged = match content {
            Content::Bytes(bytes) => out.stage(name, |w| w.write_all(bytes)),
            Content::Stream(write) => out.stage(name, |w| write(w)),
        };
        if let Err(e) = staged {
            return Err(keep_complete(out, e, &earlier));
        }
    }
    let mut missing = Vec::new();
    let staged = stage_pictures(&mut out, &pictures, &mut missing);
    if !missing.is_empty() {
        summary.to_mut().warnings_mut().extend(missing);
        json = summary.to_json()?;
    }
    if out
        .stage(RUN_FILES[3], |w| w.write_all(json.as_bytes()))
        .is_err()
    {
        // The pictures took the summary's room: they go, the summary stays.
        for name in &staged {
            out.unstage(name);
            let e = Error::Impossible(format!("no room left for {}", RUN_FILES[3]));
            summary
                .to_mut()
                .warnings_mut()
                .push(crate::error::picture_not_written(name, &e));
        }
        json = summary.to_json()?;
        if let Err(e) = out.stage(RUN_FILES[3], |w| w.write_all(json.as_bytes())) {
            return Err(keep_complete(out, e, &earlier));
        }
    }
    Ok(Written {
        files: out.commit_replacing(earlier)?,
        warnings: summary.warnings().clone(),
    })
}

/// Stages each picture; one that cannot be written (a full disk) is named in
/// `missing` instead. Returns the names staged.
pub(crate) fn stage_pictures(
    out: &mut Staging,
    pictures: &[(String, Vec<u8>)],
    missing: &mut Vec<String>,
) -> Vec<String> {
    let mut staged = Vec::new();
    for (name, bytes) in pictures {
        match out.stage(name, |w| w.write_all(bytes)) {
            Ok(()) => staged.push(name.clone()),
            Err(e) => missing.push(crate::error::picture_not_written(name, &e)),
        }
    }
    staged
}

/// The error `e` of a file that could not be written, after committing the
/// complete files staged before it: the bed of hours of work is kept even
/// when its contacts do not fit. An earlier run's files go (its summary
/// too: it would describe another bed). Nothing staged: `e` alone.
fn keep_complete(out: Staging, e: Error, earlier: &dyn Fn(&str) -> bool) -> Error {
    if out.is_empty() {
        // Dropped: the directory it created goes, an earlier run stays whole.
        return e;
    }
    match out.commit_replacing(earlier) {
        Ok(kept) if !kept.is_empty() => {
            let names: Vec<String> = kept
                .iter()
                .filter_map(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .collect();
            Error::Impossible(format!(
                "{e}; kept, complete: {} (no summary.json)",
                names.join(", ")
            ))
        }
        _ => e,
    }
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
    let mut drawn_files = Vec::new();
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
    if let Some(d) = &measures.liquid {
        use crate::io::liquid::{write_bridges, write_curve, LIQUID_FILES};
        let writers: [Stream; 2] = [
            Box::new(move |w| write_curve(w, d)),
            Box::new(move |w| write_bridges(w, d)),
        ];
        for (name, write) in LIQUID_FILES.iter().zip(writers) {
            out.push((name.to_string(), Content::Stream(write)));
        }
    }
    if let Some(d) = &measures.dried {
        use crate::io::solid_bridges::{write_agglomerates, write_bridges, DRYING_FILES};
        let writers: [Stream; 2] = [
            Box::new(move |w| write_bridges(w, d)),
            Box::new(move |w| write_agglomerates(w, d)),
        ];
        for (name, write) in DRYING_FILES.iter().zip(writers) {
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
        drawn_files = drawn.0;
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
    Ok(Extras {
        tables: out,
        pictures: drawn_files,
        missing,
    })
}

/// A file's contents for the staging: drawn beforehand, or written straight
/// into the staged file.
enum Content<'a> {
    Bytes(Vec<u8>),
    Stream(Stream<'a>),
}

type Stream<'a> = Box<dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()> + 'a>;

/// The extra files, in writing order.
struct Extras<'a> {
    /// Tables and exports.
    tables: Vec<(String, Content<'a>)>,
    /// Pictures and plots.
    pictures: Vec<(String, Vec<u8>)>,
    /// A warning for each picture that could not be drawn.
    missing: Vec<String>,
}

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
#[cfg_attr(not(feature = "render"), allow(dead_code))]
#[derive(Debug, Default)]
pub struct Drawn {
    /// `(file name, contents)`, in writing order.
    pub files: Vec<(String, Vec<u8>)>,
    /// "plot_x.png not written: why", one for each picture left out.
    pub missing: Vec<String>,
}

#[cfg_attr(not(feature = "render"), allow(dead_code))]
impl Drawn {
    /// Keeps the picture `name` if `made` is one, else says it is missing.
    pub(crate) fn keep(&mut self, name: String, made: Result<Vec<u8>>) {
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
    summary: &crate::io::summary::FragmentRunSummary,
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
    let tables: Vec<(String, Content)> = vec![
        (
            FRAGMENT_FILES[0].to_string(),
            Content::Stream(Box::new(move |w| {
                crate::io::fragmentation::write_bonds(w, frag)
            })),
        ),
        (
            FRAGMENT_FILES[1].to_string(),
            Content::Stream(Box::new(move |w| {
                crate::io::fragmentation::write_breakage(w, frag)
            })),
        ),
    ];
    stage_dir(dir, tables, files, summary, |n| earlier_file(n, false))
}

impl WarnedSummary for crate::io::summary::FragmentRunSummary {
    fn warnings(&self) -> &Vec<String> {
        &self.warnings
    }
    fn warnings_mut(&mut self) -> &mut Vec<String> {
        &mut self.warnings
    }
    fn to_json(&self) -> Result<String> {
        crate::io::summary::FragmentRunSummary::to_json(self)
    }
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
