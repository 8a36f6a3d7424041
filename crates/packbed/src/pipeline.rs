//! One bed from start to finish: config → deposition → analysis → run summary
//! ([`run_bed`]), or bed file → analysis → analysis summary ([`analyze_file`]).
//! `packbed run` and every replicate of an ensemble go through [`run_bed`], so a
//! replicate's `summary.json` is exactly what `run` would write for its seed.

use crate::analysis::{Contacts, Summary};
use crate::bed::{each_dim, AnyBed, Bed};
use crate::config::{AnalysisConfig, Config, Measure};
use crate::deposit::DepositReport;
use crate::deposit::Progress;
use crate::error::{Error, Result};
use crate::io::read::{read_bed_for, BoxHint, ReadReport};
use crate::io::summary::{
    AnalyzeSettings, AnalyzeTiming, FragmentRunSummary, FragmentSettings, FragmentTiming,
};
use crate::io::{AnalyzeSummary, RunSummary, Timing};
use crate::mechanics::{self, Fragmentation};
use crate::output::{RunExtras, Written};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A built and analysed bed with its summary.
#[derive(Clone, Debug)]
pub struct FinishedBed {
    /// The bed.
    pub bed: AnyBed,
    /// Particle and wall contacts found by the analysis.
    pub contacts: Contacts,
    /// Everything `summary.json` holds.
    pub summary: RunSummary,
}

/// Builds the bed of `config` (validated here), analyses it and gathers its
/// summary; `progress` is called with the number of particles placed so far.
pub fn run_bed(config: &Config, progress: &mut dyn FnMut(u64)) -> Result<FinishedBed> {
    run_bed_or_stop(config, &mut |n| {
        progress(n);
        ControlFlow::Continue(())
    })
}

/// [`run_bed`] that stops with [`Error::Interrupted`](crate::Error::Interrupted)
/// when `progress` breaks (checked every 4096 particles).
pub fn run_bed_or_stop(config: &Config, progress: &mut Progress) -> Result<FinishedBed> {
    run_planned(config, &planned(config)?, progress)
}

/// The plan of `config` ([`Config::planned`]) with the files it names read:
/// a medium's bed file (`[[feeds]]` with `file`), its particles checked
/// against the box and each other. A run plans its config here, once,
/// before any work or output.
pub fn planned(config: &Config) -> Result<crate::config::AnyPlan> {
    let mut plan = config.planned()?;
    crate::io::read::medium::read_media(&mut plan, flow_needed(config).as_ref())?;
    Ok(plan)
}

/// The flow settings a filtration solves with, when `config` asks for one:
/// then a medium read from a file must let fluid through.
fn flow_needed(config: &Config) -> Option<crate::analysis::pores::FlowOptions> {
    config
        .filtration
        .as_ref()
        .map(|_| config.analysis.flow.options())
}

/// [`run_bed_or_stop`] of `config` planned already (`plan` is
/// [`planned`]`(config)`): a run plans its config once.
pub fn run_planned(
    config: &Config,
    plan: &crate::config::AnyPlan,
    progress: &mut Progress,
) -> Result<FinishedBed> {
    let start = Instant::now();
    // A plan of `Config::planned` alone has not read a medium's file yet.
    let read;
    let plan = if crate::io::read::medium::unread(plan) {
        let mut p = plan.clone();
        crate::io::read::medium::read_media(&mut p, flow_needed(config).as_ref())?;
        read = p;
        &read
    } else {
        plan
    };
    let (bed, deposit) = crate::deposit::build_planned(plan, progress)?;
    let (contacts, summary) = each_dim!(&bed, b => analyse(config, b, &deposit, start)?);
    Ok(FinishedBed {
        bed,
        contacts,
        summary,
    })
}

fn analyse<const D: usize>(
    config: &Config,
    bed: &Bed<D>,
    deposit: &DepositReport,
    start: Instant,
) -> Result<(Contacts, RunSummary)> {
    let t = Instant::now();
    let (contacts, analysis) = analyze_agitated(bed, &config.analysis)?;
    // Breakage is a late, optional stage: when it cannot be done (a bed with
    // no bonds or no body to load) the bed and its measures are kept and the
    // summary says what is missing, rather than the whole run being lost.
    let mut warnings = Vec::new();
    let fragmentation = match &config.fragmentation {
        Some(options) => match mechanics::fragment(bed, &contacts, options) {
            Ok(f) => Some(f.summary),
            Err(Error::Interrupted) => return Err(Error::Interrupted),
            Err(e) => {
                warnings.push(format!(
                    "fragmentation: {e}; the bed and its measures are kept, without breakage"
                ));
                None
            }
        },
        None => None,
    };
    let timing = Timing {
        deposit_seconds: deposit.deposit_seconds,
        analysis_seconds: t.elapsed().as_secs_f64(),
        total_seconds: start.elapsed().as_secs_f64(),
        triangulation_seconds: analysis.triangulation_seconds,
        network_seconds: analysis.network_seconds,
    };
    let mut summary = RunSummary::new(config, bed, deposit, &analysis, timing);
    summary.fragmentation = fragmentation;
    if let (Some(options), Some(capture)) = (&config.filtration, &summary.capture) {
        let a = &config.analysis;
        // The config holds both for a filtration (`Config::plan`).
        let unit = a.length_unit.map_or(1.0, |u| u.metres());
        let rho = a.solid_density.unwrap_or(1.0);
        let medium = crate::analysis::capture::medium_species(&config.feeds, bed);
        let wires = crate::analysis::capture::mesh_species(&config.feeds, bed);
        let mesh = config
            .feeds
            .iter()
            .find_map(|f| f.mesh)
            .and_then(|m| m.resolve("mesh").ok());
        let flow = a.flow.options();
        match crate::analysis::filtration::filtration(
            bed,
            &crate::analysis::filtration::Medium {
                species: &medium,
                mesh: mesh.as_ref().map(|m| (m, &wires[..])),
            },
            capture,
            options,
            unit,
            rho,
            &flow,
        ) {
            Ok(f) => {
                // The curve is part of the analysis' time and the run's.
                summary.timing.analysis_seconds += f.seconds;
                summary.timing.total_seconds = start.elapsed().as_secs_f64();
                summary.filtration = Some(f);
            }
            Err(e) => warnings.push(format!(
                "filtration: {e}; the bed and its capture are kept, without the curve"
            )),
        }
    }
    summary.warnings.extend(warnings);
    Ok((contacts, summary))
}

impl FinishedBed {
    /// Writes the run's files (`output::RUN_FILES`) into `dir`, atomically.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        self.write_with(dir, &RunExtras::default()).map(|w| w.files)
    }

    /// Writes the run's files plus pictures, plots and exports, atomically;
    /// a picture that cannot be drawn is a warning (see `Written`).
    pub fn write_with(&self, dir: &Path, extras: &RunExtras) -> Result<Written> {
        each_dim!(&self.bed, b => {
            crate::output::write_run_with(dir, b, &self.contacts, &self.summary, extras)
        })
    }
}

/// A bed read from a file and analysed, with its summary.
#[derive(Clone, Debug)]
pub struct AnalyzedBed {
    /// The bed as read.
    pub bed: AnyBed,
    /// Particle and wall contacts found by the analysis.
    pub contacts: Contacts,
    /// Everything the analysis' `summary.json` holds.
    pub summary: AnalyzeSummary,
}

/// Reads the bed file at `path` (any format [`crate::read_bed_report`] knows; `hint`
/// is the box for files without one, and wins over a box in the file) and
/// analyses it with `settings`.
pub fn analyze_file(
    path: &Path,
    hint: Option<&BoxHint>,
    settings: &AnalysisConfig,
) -> Result<AnalyzedBed> {
    settings.check()?;
    let measures = settings.measures.as_deref().unwrap_or(&Measure::DEFAULT);
    let (bed, read, read_seconds) = read_timed(path, hint, measures)?;
    analyze_read_bed(
        &path.display().to_string(),
        bed,
        &read,
        settings,
        read_seconds,
    )
}

/// Analyses a bed already read (from `source`, as `read` reports it) with
/// `settings`, as [`analyze_file`] does after reading.
pub fn analyze_read_bed(
    source: &str,
    bed: AnyBed,
    read: &ReadReport,
    settings: &AnalysisConfig,
    read_seconds: f64,
) -> Result<AnalyzedBed> {
    settings.check()?;
    let measures = settings.measures.as_deref().unwrap_or(&Measure::DEFAULT);
    let points =
        each_dim!(&bed, b => crate::config::pore_points_per_particle(&b.container, b.r_max()));
    crate::config::check_analysis(bed.len(), bed.dim(), measures, points, source)?;
    let spread = each_dim!(&bed, b => spread_in_diameters(b));
    if let Some(why) = crate::config::pore_space_extent_problem(measures, spread) {
        return Err(Error::Impossible(format!("{source}: {why}")));
    }
    let (contacts, summary) =
        each_dim!(&bed, b => analyze_read(source, b, read, settings, read_seconds))?;
    Ok(AnalyzedBed {
        bed,
        contacts,
        summary,
    })
}

/// The contacts and measures of a bed in memory, with `settings`: the
/// measures `summary.json` holds, without its counts, timing or config.
pub fn analyze_bed(bed: &AnyBed, settings: &AnalysisConfig) -> Result<(Contacts, Summary)> {
    settings.check()?;
    each_dim!(bed, b => analyze_agitated(b, settings))
}

/// The analysis of `bed` with `settings`, then, when they ask for it, the
/// agitation of its dried cake ([`mechanics::agitation`]: it needs the
/// mechanics, a floor above the analysis). An agitation that cannot be done
/// (no body to load) leaves the dried cake unagitated and says why in
/// `agglomeration.note`, rather than losing the bed.
fn analyze_agitated<const D: usize>(
    bed: &Bed<D>,
    settings: &AnalysisConfig,
) -> Result<(Contacts, Summary)> {
    let (contacts, mut summary) = crate::analysis::analyze_with(bed, &settings.options());
    // The dried cake is taken only when there is an agitation to give it.
    let Some(options) = &settings.drying.agitation else {
        return Ok((contacts, summary));
    };
    let Some(dried) = summary.dried.take() else {
        return Ok((contacts, summary));
    };
    let mut drying = std::sync::Arc::try_unwrap(dried).unwrap_or_else(|d| (*d).clone());
    match mechanics::agitation::agitate(bed, &contacts, &mut drying, options) {
        Ok(()) => {}
        Err(Error::Interrupted) => return Err(Error::Interrupted),
        Err(e) => {
            let note = format!("agitation: {e}");
            drying.summary.note = Some(match drying.summary.note.take() {
                Some(n) => format!("{n}; {note}"),
                None => note,
            });
        }
    }
    summary.agglomeration = Some(drying.summary.clone());
    summary.dried = Some(std::sync::Arc::new(drying));
    Ok((contacts, summary))
}

/// Reads the bed file at `path` after checking the caller's box `hint`; also
/// returns the seconds the reading took.
fn read_timed(
    path: &Path,
    hint: Option<&BoxHint>,
    measures: &[Measure],
) -> Result<(AnyBed, ReadReport, f64)> {
    if let Some(h) = hint {
        check_box_hint(h).map_err(|e| e.within("box"))?;
    }
    let t = Instant::now();
    let (bed, read) = read_bed_for(path, hint, measures)?;
    Ok((bed, read, t.elapsed().as_secs_f64()))
}

/// True if the picture file `out` is an SVG, false for a PNG; any other
/// extension is refused (before any work).
pub fn picture_is_svg(out: &Path) -> Result<bool> {
    match out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg") => Ok(true),
        Some("png") => Ok(false),
        _ => Err(Error::Impossible(
            "the picture must end in .png or .svg".into(),
        )),
    }
}

/// `packbed render`: the bed file `path` (its box from `hint` if it has none)
/// read and drawn into `out` ([`render_to`]). `given_3d` names the 3D view
/// and cut-away the caller was given: a 2D bed refuses them rather than
/// ignore them without a word.
#[cfg(feature = "render")]
pub fn render_file(
    path: &Path,
    hint: Option<&BoxHint>,
    out: &Path,
    opts: &crate::render::RenderOptions,
    given_3d: &[&str],
    chains: Option<crate::analysis::LargeRule>,
) -> Result<()> {
    let bed = crate::io::read::read_bed(path, hint)?;
    if bed.dim() == 2 && !given_3d.is_empty() {
        return Err(Error::Impossible(format!(
            "{}: {} is a 2D bed (views and cut-aways are for 3D beds)",
            given_3d.join(" and "),
            path.display()
        )));
    }
    render_to(&bed, out, opts, chains)
}

/// `packbed render`: `bed` drawn into the picture file `out` (PNG, or SVG for
/// 2D beds). `chains`: colour by the percolation analysis' chains, large
/// particles by this rule, instead of `opts.color`.
#[cfg(feature = "render")]
pub fn render_to(
    bed: &AnyBed,
    out: &Path,
    opts: &crate::render::RenderOptions,
    chains: Option<crate::analysis::LargeRule>,
) -> Result<()> {
    use crate::render;
    let svg = picture_is_svg(out)?;
    let mut opts = opts.clone();
    if let Some(large) = chains {
        let classes = each_dim!(bed, b => {
            let contacts = crate::analysis::find_contacts(b, opts.contact_tol);
            render::chain_classes(b, &contacts, large)
        });
        opts.color = render::ColorBy::Classes(classes);
    }
    let bytes = if svg {
        render::render_svg(bed, &opts)?.into_bytes()
    } else {
        render::render_png(bed, &opts)?
    };
    crate::output::write_file(out, &bytes)
}

/// The widest side of the box around the particles' centres, in smallest
/// diameters (0 for an empty bed).
fn spread_in_diameters<const D: usize>(bed: &Bed<D>) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    for c in &bed.centres {
        for k in 0..D {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let d_min = 2.0 * bed.r_min();
    let widest = (0..D).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    if d_min.is_nan() || d_min <= 0.0 {
        0.0
    } else {
        widest / d_min
    }
}

/// Refuses a box given by the caller unless it has two or three positive sizes.
pub fn check_box_hint(hint: &BoxHint) -> Result<()> {
    if !(2..=3).contains(&hint.size.len()) {
        return Err(Error::config(format!(
            "give W,H (2D) or W,D,H (3D), got {} sizes",
            hint.size.len()
        )));
    }
    match hint.size.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        Some(v) => Err(Error::config(format!("sizes must be positive, got {v}"))),
        None => Ok(()),
    }
}

fn analyze_read<const D: usize>(
    source: &str,
    bed: &Bed<D>,
    read: &ReadReport,
    settings: &AnalysisConfig,
    read_seconds: f64,
) -> Result<(Contacts, AnalyzeSummary)> {
    let t = Instant::now();
    let (contacts, analysis) = analyze_agitated(bed, settings)?;
    let overlaps = crate::analysis::overlaps(bed, &contacts);
    let timing = AnalyzeTiming {
        read_seconds,
        analysis_seconds: t.elapsed().as_secs_f64(),
        triangulation_seconds: analysis.triangulation_seconds,
        network_seconds: analysis.network_seconds,
    };
    let recorded = AnalyzeSettings {
        contact_tol: settings.contact_tol,
        large_radius: settings.large_radius,
        chain_angle_from: settings.chain_angle_from,
    };
    let summary = AnalyzeSummary::new(source, bed, read, &overlaps, recorded, &analysis, timing);
    Ok((contacts, summary))
}

impl AnalyzedBed {
    /// Writes the analysis files (`contacts.csv`, `wall_contacts.csv`, `summary.json`) plus pictures,
    /// plots and exports into `dir`, atomically.
    pub fn write_with(&self, dir: &Path, extras: &RunExtras) -> Result<Written> {
        each_dim!(&self.bed, b => {
            crate::output::write_analysis(dir, b, &self.contacts, &self.summary, extras)
        })
    }
}

/// The fragmentation of either dimension.
#[derive(Clone, Debug)]
pub enum AnyFragmentation {
    /// Of a 2D bed.
    D2(Fragmentation<2>),
    /// Of a 3D bed.
    D3(Fragmentation<3>),
}

/// A bed read from a file, loaded and broken (`packbed fragment`).
#[derive(Clone, Debug)]
pub struct FragmentedBed {
    /// The bed as read.
    pub bed: AnyBed,
    /// Forces, loads and breaks.
    pub fragmentation: AnyFragmentation,
    /// Everything its `summary.json` holds.
    pub summary: FragmentRunSummary,
}

/// Reads the bed file at `path` (as [`analyze_file`] does), finds its contacts
/// (`contact_tol` relative to the smaller radius), loads it and breaks its
/// bonds as `options` say.
pub fn fragment_file(
    path: &Path,
    hint: Option<&BoxHint>,
    options: &mechanics::FragmentationConfig,
    contact_tol: crate::math::Real,
) -> Result<FragmentedBed> {
    fragment_file_with(path, hint, options, contact_tol, &mut |_| {})
}

/// [`fragment_file`], telling `progress` the bonds broken after each break.
pub fn fragment_file_with(
    path: &Path,
    hint: Option<&BoxHint>,
    options: &mechanics::FragmentationConfig,
    contact_tol: crate::math::Real,
    progress: &mut dyn FnMut(u64),
) -> Result<FragmentedBed> {
    options.check()?;
    if let Some(why) = crate::config::contact_tol_problem(contact_tol, "contact_tol") {
        return Err(Error::config(why));
    }
    let (bed, read, read_seconds) = read_timed(path, hint, &Measure::DEFAULT)?;
    fragment_bed(
        &path.display().to_string(),
        bed,
        &read,
        options,
        contact_tol,
        read_seconds,
        progress,
    )
}

/// Loads and breaks a bed already read (from `source`, as `read` reports it),
/// as [`fragment_file`] does after reading.
pub fn fragment_read_bed(
    source: &str,
    bed: AnyBed,
    read: &ReadReport,
    options: &mechanics::FragmentationConfig,
    contact_tol: crate::math::Real,
    read_seconds: f64,
) -> Result<FragmentedBed> {
    fragment_bed(
        source,
        bed,
        read,
        options,
        contact_tol,
        read_seconds,
        &mut |_| {},
    )
}

fn fragment_bed(
    source: &str,
    bed: AnyBed,
    read: &ReadReport,
    options: &mechanics::FragmentationConfig,
    contact_tol: crate::math::Real,
    read_seconds: f64,
    progress: &mut dyn FnMut(u64),
) -> Result<FragmentedBed> {
    options.check()?;
    if let Some(why) = crate::config::contact_tol_problem(contact_tol, "contact_tol") {
        return Err(Error::config(why));
    }
    let t = (read, options, contact_tol, read_seconds);
    let (fragmentation, summary) = match &bed {
        AnyBed::D2(b) => {
            let (f, s) = fragment_read(source, b, t, progress)?;
            (AnyFragmentation::D2(f), s)
        }
        AnyBed::D3(b) => {
            let (f, s) = fragment_read(source, b, t, progress)?;
            (AnyFragmentation::D3(f), s)
        }
    };
    Ok(FragmentedBed {
        bed,
        fragmentation,
        summary,
    })
}

fn fragment_read<const D: usize>(
    source: &str,
    bed: &Bed<D>,
    (read, options, contact_tol, read_seconds): (
        &ReadReport,
        &mechanics::FragmentationConfig,
        crate::math::Real,
        f64,
    ),
    progress: &mut dyn FnMut(u64),
) -> Result<(Fragmentation<D>, FragmentRunSummary)> {
    let contacts = crate::analysis::find_contacts(bed, contact_tol);
    let overlaps = crate::analysis::overlaps(bed, &contacts);
    let frag = mechanics::fragment_with(bed, &contacts, options, progress)?;
    let timing = FragmentTiming {
        read_seconds,
        first_solve_seconds: frag.first_solve_seconds,
        breakage_seconds: frag.breakage_seconds,
    };
    let settings = FragmentSettings {
        load: options.load,
        breaks: options.breaks.to_string(),
        kt_over_kn: options.kt_over_kn,
        contact_tol,
    };
    let summary = FragmentRunSummary::new(
        source,
        bed,
        read,
        &overlaps,
        settings,
        &frag.summary,
        timing,
    );
    Ok((frag, summary))
}

impl FragmentedBed {
    /// Writes `bonds.csv`, `breakage.csv`, the pictures (with `pictures`) and
    /// `summary.json` into `dir`, atomically.
    pub fn write(&self, dir: &Path, pictures: bool) -> Result<Written> {
        match (&self.bed, &self.fragmentation) {
            (AnyBed::D2(b), AnyFragmentation::D2(f)) => {
                crate::output::write_fragmentation(dir, b, f, &self.summary, pictures)
            }
            (AnyBed::D3(b), AnyFragmentation::D3(f)) => {
                crate::output::write_fragmentation(dir, b, f, &self.summary, pictures)
            }
            _ => Err(Error::Impossible(
                "a bed and its fragmentation of different dimensions (please report this bug)"
                    .into(),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_picture_is_png_or_svg_by_its_extension() {
        assert!(!picture_is_svg(Path::new("a/bed.png")).unwrap());
        assert!(picture_is_svg(Path::new("bed.SVG")).unwrap());
        for bad in ["bed.jpg", "bed", "png"] {
            assert!(picture_is_svg(Path::new(bad)).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_replicates_are_those_asked_for_else_the_configs() {
        let mut c = Config::default();
        assert_eq!(crate::ensemble::runs_of(Some(7), &c).unwrap(), 7);
        let e = crate::ensemble::runs_of(None, &c).unwrap_err();
        assert!(
            matches!(
                e,
                Error::Setting {
                    setting: "runs",
                    ..
                }
            ),
            "{e}"
        );
        c.ensemble = Some(crate::config::EnsembleConfig { runs: 12 });
        assert_eq!(crate::ensemble::runs_of(None, &c).unwrap(), 12);
    }
}
