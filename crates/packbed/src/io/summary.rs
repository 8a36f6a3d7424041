//! `summary.json`: what was asked (the config as used), what was built (box,
//! counts, species) and what was measured (the analysis summary), with timings.
//!
//! The keys of [`SUMMARY_KEYS`] are a contract with users' scripts
//! (`docs/reference/formats.md`, "The contract keys"): add keys freely, never
//! rename one.

use crate::analysis::psd::PsdSummary;
use crate::analysis::{Overlaps, Summary};
use crate::bed::Bed;
use crate::config::{Config, Mode};
use crate::deposit::DepositReport;
use crate::error::{Error, Result};
use crate::io::read::ReadReport;
use crate::math::Real;
use crate::mechanics::FragmentationSummary;
use crate::species::Shape;
use serde::Serialize;

/// JSON pointers every run's `summary.json` holds: the keys scripts rely on
/// (`docs/reference/formats.md`), checked on the library's summary and the command's.
pub const SUMMARY_KEYS: &[&str] = &[
    "/dim",
    "/seed",
    "/box/width",
    "/box/depth",
    "/box/height",
    "/box/periodic",
    "/counts/particles",
    "/counts/bodies",
    "/counts/redrops",
    "/counts/base_layer",
    "/counts/dropped",
    "/counts/roof_overflows",
    "/packing/global",
    "/packing/bulk",
    "/coordination/mean",
    "/coordination/mean_bulk",
    "/timing/deposit_seconds",
    "/timing/analysis_seconds",
    "/timing/total_seconds",
    "/species/0/name",
    "/species/0/size",
    "/species/0/ratio",
    "/species/0/placed",
    "/config/dim",
    "/config/seed",
    "/config/box/periodic",
    "/config/species/1/radius",
    "/config/box/preset",
    "/config/fill/until",
    "/config/analysis/contact_tol",
];

/// What a replicate's summary carries to prove it belongs to its ensemble
/// (built and checked in `ensemble::proof`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplicateProof {
    /// The fingerprint of the config the replicate was built from, its seed
    /// and `[ensemble]` table left out.
    pub config_hash: String,
    /// The measures the summary holds (`cake`, `packing`, …), in its order.
    pub measures: Vec<&'static str>,
}

/// The whole of `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// Version of packbed that wrote the file.
    pub packbed_version: &'static str,
    /// What an optional stage could not do, the run kept all the same
    /// (absent when nothing went wrong).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Every measure of the analysis (`cake.*` first, `packing.*`, …): what a
    /// reader opens the file for, at its top.
    #[serde(flatten)]
    pub analysis: Summary,
    /// 2 or 3.
    pub dim: u8,
    /// Seed of the run.
    pub seed: u64,
    /// Deposit or RSA.
    pub mode: Mode,
    /// The container as built.
    #[serde(rename = "box")]
    pub container: BoxSummary,
    /// Particle counts.
    pub counts: Counts,
    /// The size distribution placed against the one requested (runs whose
    /// species draw from a distribution).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub psd: Option<PsdSummary>,
    /// Forces and breakage under load (with a `[fragmentation]` table).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fragmentation: Option<FragmentationSummary>,
    /// The compaction after settling (with a `[compaction]` table).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compaction: Option<crate::deposit::compaction::CompactionReport>,
    /// What the filter medium let through, held and left above it (beds
    /// with a `medium = true` feed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub capture: Option<crate::analysis::capture::CaptureSummary>,
    /// The filtration curve through medium and cake (a `[filtration]` table).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub filtration: Option<crate::analysis::filtration::FiltrationSummary>,
    /// Wall times.
    pub timing: Timing,
    /// The species, in config order (the `species` column of `particles.csv`).
    pub species: Vec<SpeciesSummary>,
    /// The configuration as used: overrides applied, defaults filled in.
    pub config: Config,
    /// A replicate of an ensemble: the proof that it belongs to it (absent
    /// for `packbed run`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub proof: Option<ReplicateProof>,
}

/// `box.*`.
#[derive(Clone, Debug, Serialize)]
pub struct BoxSummary {
    /// Extent along x.
    pub width: Real,
    /// Extent along y (3D only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub depth: Option<Real>,
    /// Roof height.
    pub height: Real,
    /// Periodic side boundaries.
    pub periodic: bool,
    /// Where the box of an analysed bed file came from: `options` (`--box`,
    /// which wins over a box in the file), `file` or `summary.json` (beside a
    /// `particles.csv`). Absent for a run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<&'static str>,
}

impl BoxSummary {
    /// The box of `bed`; `source` says where an analysed file's box came from.
    pub(crate) fn of<const D: usize>(bed: &Bed<D>, source: Option<&'static str>) -> Self {
        let size = bed.container.size;
        BoxSummary {
            width: size[0],
            depth: (D == 3).then(|| size[1]),
            height: size[D - 1],
            periodic: bed.container.periodic,
            source,
        }
    }
}

/// `counts.*`.
#[derive(Clone, Debug, Serialize)]
pub struct Counts {
    /// Spheres or beads in the bed (rows of `particles.csv`).
    pub particles: u64,
    /// Rigid bodies (a sphere is a body of one bead).
    pub bodies: u64,
    /// Particles dropped again because they found no rest.
    pub redrops: u64,
    /// Particles placed by the base layer.
    pub base_layer: u64,
    /// Particles placed by drop and roll.
    pub dropped: u64,
    /// Particles discarded above the roof.
    pub roof_overflows: u64,
}

/// `timing.*`, in seconds of wall time.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Timing {
    /// Deposition.
    pub deposit_seconds: f64,
    /// Analysis.
    pub analysis_seconds: f64,
    /// The whole run, file writing included up to the summary itself.
    pub total_seconds: f64,
    /// The regular triangulation alone (part of the analysis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangulation_seconds: Option<f64>,
    /// The pore network built on the triangulation (part of the analysis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub network_seconds: Option<f64>,
}

/// One entry of `species`.
#[derive(Clone, Debug, Serialize)]
pub struct SpeciesSummary {
    /// Name ("large", "small", or from the config).
    pub name: String,
    /// Size, e.g. `r = 10` or `r ~ lognormal(median 10, gsd 2) in [1.25, 80] (±3 sd)`
    /// (a distribution with the window it is truncated to; [`SizeDist::describe`]).
    ///
    /// [`SizeDist::describe`]: crate::species::SizeDist::describe
    pub size: String,
    /// `sphere`, or `chain of 5 beads, spacing 1`.
    pub shape: String,
    /// Number ratio as configured.
    pub ratio: Real,
    /// Bodies of this species in the bed.
    pub placed: u64,
    /// Spheres or beads of this species in the bed.
    pub particles: u64,
}

impl RunSummary {
    /// Gathers the summary of a finished run.
    pub fn new<const D: usize>(
        config: &Config,
        bed: &Bed<D>,
        report: &DepositReport,
        analysis: &Summary,
        timing: Timing,
    ) -> RunSummary {
        let psd = crate::analysis::psd::size_distribution(bed);
        let mut warnings = analysis.warnings.clone();
        warnings.extend(psd.iter().filter_map(|p| p.departure.warning()));
        warnings.extend(unitless_tables(bed, config.analysis.length_unit));
        warnings.extend(analysis.cake.iter().flat_map(|c| c.implausible()));
        warnings.extend(report.compaction.and_then(|c| c.warning()));
        RunSummary {
            packbed_version: env!("CARGO_PKG_VERSION"),
            warnings,
            dim: D as u8,
            seed: config.seed,
            mode: config.mode,
            container: BoxSummary::of(bed, None),
            counts: Counts {
                particles: bed.len() as u64,
                bodies: bed.body_count() as u64,
                redrops: report.redrops,
                base_layer: report.base_layer,
                dropped: report.dropped,
                roof_overflows: report.roof_overflows,
            },
            analysis: analysis.clone(),
            psd,
            fragmentation: None,
            compaction: report.compaction,
            capture: capture(config, bed, report),
            filtration: None,
            timing,
            species: species_summaries(bed),
            config: config_as_used(config),
            proof: None,
        }
    }

    /// The JSON text, refused if any number in it is NaN or infinite.
    pub fn to_json(&self) -> Result<String> {
        json_text(self, "the run's results")
    }
}

/// The capture of a bed built with a filter medium.
fn capture<const D: usize>(
    config: &Config,
    bed: &Bed<D>,
    report: &DepositReport,
) -> Option<crate::analysis::capture::CaptureSummary> {
    let medium = crate::analysis::capture::medium_species(&config.feeds, bed);
    crate::analysis::capture::capture(
        bed,
        &medium,
        &report.filtrate,
        report.medium_lift,
        crate::analysis::capture::mesh_mid_plane::<D>(&config.feeds),
    )
}

/// A warning for each size table of `bed`'s species that names no unit in a
/// bed with a length unit: its sizes are read in the bed's unit, and a table
/// in mm read as µm builds a cake a thousand times too fine without an
/// implausible figure (a 0.2 µm powder is a possible cake).
fn unitless_tables<const D: usize>(
    bed: &Bed<D>,
    unit: Option<crate::config::LengthUnit>,
) -> Vec<String> {
    let Some(unit) = unit.map(|u| u.name()) else {
        return Vec::new();
    };
    bed.species_info
        .iter()
        .filter_map(|s| match &s.size {
            crate::species::SizeDist::Table(t) if t.unit.is_none() => Some(format!(
                "species `{}`: the header of {} names no unit, so its sizes are read in the \
                 bed's length_unit, {unit}; name the unit in the header (e.g. `{}_{unit}`) to \
                 be sure",
                crate::error::echo(&s.name),
                crate::error::echo(&t.source.file_name().unwrap_or_default().to_string_lossy()),
                t.size_word
            )),
            _ => None,
        })
        .collect()
}

/// `summary.json` of `packbed analyze`: the keys of a run's summary that a bed
/// file can tell (no seed, config or deposition counts), with the same layout.
#[derive(Clone, Debug, Serialize)]
pub struct AnalyzeSummary {
    /// Version of packbed that wrote the file.
    pub packbed_version: &'static str,
    /// Pictures that could not be drawn, the analysis kept all the same
    /// (absent when nothing went wrong).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Every measure of the analysis (`cake.*` first, `packing.*`, …).
    #[serde(flatten)]
    pub analysis: Summary,
    /// The bed file analysed.
    pub source: String,
    /// 2 or 3.
    pub dim: u8,
    /// The container.
    #[serde(rename = "box")]
    pub container: BoxSummary,
    /// Particle counts.
    pub counts: AnalyzeCounts,
    /// The settings of the analysis.
    pub settings: AnalyzeSettings,
    /// What the checks of the input found (the bed is analysed all the same).
    pub checks: Checks,
    /// Wall times.
    pub timing: AnalyzeTiming,
}

/// `counts.*` of `packbed analyze`.
#[derive(Clone, Debug, Serialize)]
pub struct AnalyzeCounts {
    /// Spheres or beads.
    pub particles: u64,
    /// Rigid bodies.
    pub bodies: u64,
}

/// `checks.*` of `packbed analyze`: findings about the input bed that do not
/// stop the analysis.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Checks {
    /// Pairs of particles of different bodies overlapping by more than
    /// [`crate::analysis::contacts::OVERLAP_TOL`] of the smaller radius.
    pub overlapping_pairs: u64,
    /// The worst overlap relative to the smaller radius of its pair (0: none).
    pub max_overlap: Real,
    /// Centres moved into `[0, W)` along periodic sides.
    pub wrapped_centres: u64,
}

/// `settings.*` of `packbed analyze`.
#[derive(Clone, Debug, Serialize)]
pub struct AnalyzeSettings {
    /// Contact tolerance relative to the smaller radius.
    pub contact_tol: Real,
    /// Percolation threshold radius given (`null`: the default, the largest of
    /// the species' volume-median radii).
    pub large_radius: Option<Real>,
    /// The direction chain angles are measured from.
    pub chain_angle_from: crate::analysis::orientation::AngleFrom,
}

/// `timing.*` of `packbed analyze`, seconds of wall time.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct AnalyzeTiming {
    /// Reading the bed file.
    pub read_seconds: f64,
    /// Analysis.
    pub analysis_seconds: f64,
    /// The regular triangulation alone (part of the analysis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangulation_seconds: Option<f64>,
    /// The pore network built on the triangulation (part of the analysis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub network_seconds: Option<f64>,
}

impl Checks {
    fn of(overlaps: &Overlaps, read: &ReadReport) -> Checks {
        Checks {
            overlapping_pairs: overlaps.overlapping_pairs,
            max_overlap: overlaps.max_overlap,
            wrapped_centres: read.wrapped,
        }
    }
}

impl AnalyzeSummary {
    /// Gathers the summary of an analysed bed file.
    pub(crate) fn new<const D: usize>(
        source: &str,
        bed: &Bed<D>,
        read: &ReadReport,
        overlaps: &Overlaps,
        settings: AnalyzeSettings,
        analysis: &Summary,
        timing: AnalyzeTiming,
    ) -> AnalyzeSummary {
        AnalyzeSummary {
            packbed_version: env!("CARGO_PKG_VERSION"),
            warnings: analysis
                .warnings
                .iter()
                .cloned()
                .chain(analysis.cake.iter().flat_map(|c| c.implausible()))
                .collect(),
            source: source.to_string(),
            dim: D as u8,
            container: BoxSummary::of(bed, Some(read.box_source.name())),
            counts: AnalyzeCounts {
                particles: bed.len() as u64,
                bodies: bed.body_count() as u64,
            },
            settings,
            checks: Checks::of(overlaps, read),
            analysis: analysis.clone(),
            timing,
        }
    }

    /// The JSON text, refused if any number in it is NaN or infinite.
    pub(crate) fn to_json(&self) -> Result<String> {
        json_text(self, "the results")
    }
}

fn species_summaries<const D: usize>(bed: &Bed<D>) -> Vec<SpeciesSummary> {
    let n = bed.species_info.len();
    let mut particles = vec![0u64; n];
    let mut placed = vec![0u64; n];
    let mut last_body = None;
    for (&s, &b) in bed.species.iter().zip(&bed.bodies) {
        let s = s as usize;
        if s >= n {
            continue;
        }
        particles[s] += 1;
        // Beads of one body are consecutive rows, so a new body starts where the
        // body index changes.
        if last_body != Some(b) {
            placed[s] += 1;
            last_body = Some(b);
        }
    }
    bed.species_info
        .iter()
        .enumerate()
        .map(|(i, s)| SpeciesSummary {
            name: s.name.clone(),
            size: s.size.describe(),
            shape: match s.shape {
                Shape::Sphere => "sphere".into(),
                Shape::Chain {
                    beads,
                    spacing,
                    orientation,
                } => {
                    format!(
                        "chain of {beads} beads, spacing {spacing}, entering {}",
                        orientation.name()
                    )
                }
            },
            ratio: s.ratio,
            placed: placed[i],
            particles: particles[i],
        })
        .collect()
}

/// The config with the implicit choices spelled out, so that the summary alone
/// tells how the bed was made.
pub(crate) fn config_as_used(config: &Config) -> Config {
    let mut c = config.clone();
    let b = &mut c.container;
    if b.preset.is_none()
        && b.diameters.is_none()
        && b.width.is_none()
        && b.depth.is_none()
        && b.height.is_none()
    {
        b.preset = Some("thesis".into());
    }
    if c.fill.until.is_none() && c.fill.count.is_none() {
        c.fill.until = Some("roof".into());
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use crate::math::Vector;

    #[test]
    fn fragment_forces_say_what_they_are_relative_to() {
        use crate::mechanics::Load;
        let n = force_note(Load::Shear, 240.0, Some(120.0));
        assert!(n.contains("relative to a total load F = 1"), "{n}");
        // A shear stress τ on the top face: F = τ·A with A = 240 × 120.
        assert!(n.contains("F = τ·A") && n.contains("28800"), "{n}");
        let n = force_note(Load::Compression, 50.0, None);
        assert!(n.contains("F = p·A") && n.contains("per unit depth"), "{n}");
        assert!(n.contains("width 50"), "{n}");
        let n = force_note(Load::Gravity, 50.0, None);
        assert!(n.contains("weight"), "{n}");
    }

    fn small_run() -> (Config, Bed<3>) {
        let config = Config::default();
        let plan = config.plan::<3>().unwrap();
        let mut bed = Bed::new(
            Container {
                size: Vector([240.0; 3]),
                periodic: false,
            },
            plan.species.clone(),
        );
        bed.push(Vector([20.0, 20.0, 20.0]), 20.0, 0);
        bed.push(Vector([60.0, 20.0, 10.0]), 10.0, 1);
        bed.push(Vector([90.0, 20.0, 10.0]), 10.0, 1);
        (config, bed)
    }

    #[test]
    fn keys_of_the_contract() {
        let (config, bed) = small_run();
        let s = RunSummary::new(
            &config,
            &bed,
            &DepositReport::default(),
            &crate::analysis::analyze(&bed, 1e-6).1,
            Timing::default(),
        );
        let v: serde_json::Value = serde_json::from_str(&s.to_json().unwrap()).unwrap();
        for key in SUMMARY_KEYS {
            assert!(v.pointer(key).is_some(), "missing {key}");
        }
        assert_eq!(v["counts"]["particles"], 3);
        assert_eq!(v["species"][1]["placed"], 2);
        assert_eq!(v["species"][0]["name"], "large");
    }

    #[test]
    fn nan_is_refused_with_its_key() {
        let (config, bed) = small_run();
        let mut analysis = crate::analysis::analyze(&bed, 1e-6).1;
        analysis.coordination.as_mut().unwrap().mean_bulk = Some(f64::NAN);
        let s = RunSummary::new(
            &config,
            &bed,
            &DepositReport::default(),
            &analysis,
            Timing::default(),
        );
        let e = s.to_json().unwrap_err().to_string();
        assert!(e.contains("coordination.mean_bulk"), "{e}");
    }
}

/// `summary.json` of `packbed fragment`: the bed file, its box and counts, the
/// settings, and `fragmentation.*`.
#[derive(Clone, Debug, Serialize)]
pub struct FragmentRunSummary {
    /// Version of packbed that wrote the file.
    pub packbed_version: &'static str,
    /// Pictures that could not be drawn, the tables kept all the same
    /// (absent when nothing went wrong).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The bed file.
    pub source: String,
    /// 2 or 3.
    pub dim: u8,
    /// The container.
    #[serde(rename = "box")]
    pub container: BoxSummary,
    /// Particle counts.
    pub counts: AnalyzeCounts,
    /// The settings of the fragmentation.
    pub settings: FragmentSettings,
    /// What the checks of the input found.
    pub checks: Checks,
    /// The forces and the breakage.
    pub fragmentation: FragmentationSummary,
    /// What the forces are relative to and how to scale them to a stress.
    pub force_note: String,
    /// Wall times.
    pub timing: FragmentTiming,
}

/// What the forces of a fragmentation are relative to (a total load of 1)
/// and how a stress on the bed gives the total force that scales them, for
/// the load `load` on a box `width` wide (and `depth` deep in 3D).
pub fn force_note(load: crate::mechanics::Load, width: Real, depth: Option<Real>) -> String {
    use crate::mechanics::Load;
    let total = crate::mechanics::TOTAL;
    let area = match depth {
        Some(d) => {
            let a = width * d;
            format!("its area A = width × depth = {width} × {d} = {a} (length units²)")
        }
        None => format!("per unit depth of the 2D bed, A = its width {width} (length units)"),
    };
    let what = match load {
        Load::Shear => format!(
            "F is the shear force on the top bodies (balanced by the bottom ones); a shear stress τ on the bed's top face gives F = τ·A, {area}"
        ),
        Load::Compression => format!(
            "F is the downward force on the top bodies; a pressure p on the bed's top face gives F = p·A, {area}"
        ),
        Load::Gravity => {
            "F is the bed's weight (ρ_s·g·solid volume); its weight per floor area is the stress on the floor".to_string()
        }
    };
    format!(
        "forces are relative to a total load F = {total}: the springs are linear, so under a total load F every force scales by F and the breaking order stays the same; {what}"
    )
}

/// `settings.*` of `packbed fragment`.
#[derive(Clone, Debug, Serialize)]
pub struct FragmentSettings {
    /// The load.
    pub load: crate::mechanics::Load,
    /// Breaks asked for: a number, or `"failure"`.
    pub breaks: String,
    /// `k_t / k_n`.
    pub kt_over_kn: Real,
    /// Contact tolerance relative to the smaller radius (bonds are contacts).
    pub contact_tol: Real,
}

/// `timing.*` of `packbed fragment`, seconds of wall time.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct FragmentTiming {
    /// Reading the bed file.
    pub read_seconds: f64,
    /// Contacts, network, loads and the first solve.
    pub first_solve_seconds: f64,
    /// The breaks after it.
    pub breakage_seconds: f64,
}

impl FragmentRunSummary {
    /// Gathers the summary of a fragmented bed file.
    pub(crate) fn new<const D: usize>(
        source: &str,
        bed: &Bed<D>,
        read: &ReadReport,
        overlaps: &Overlaps,
        settings: FragmentSettings,
        fragmentation: &FragmentationSummary,
        timing: FragmentTiming,
    ) -> FragmentRunSummary {
        FragmentRunSummary {
            packbed_version: env!("CARGO_PKG_VERSION"),
            warnings: Vec::new(),
            source: source.to_string(),
            dim: D as u8,
            container: BoxSummary::of(bed, Some(read.box_source.name())),
            counts: AnalyzeCounts {
                particles: bed.len() as u64,
                bodies: bed.body_count() as u64,
            },
            settings,
            checks: Checks::of(overlaps, read),
            fragmentation: fragmentation.clone(),
            force_note: force_note(
                fragmentation.load,
                bed.container.size[0],
                (D == 3).then(|| bed.container.size[1]),
            ),
            timing,
        }
    }

    /// The JSON text, refused if any number in it is NaN or infinite.
    pub fn to_json(&self) -> Result<String> {
        json_text(self, "the results")
    }
}

/// The pretty JSON text of a summary, refused if any number in it is NaN or
/// infinite (`what` names what becomes unusable).
fn json_text<T: Serialize>(summary: &T, what: &str) -> Result<String> {
    if let Some(key) = super::finite::first_non_finite(summary) {
        return Err(Error::Impossible(format!(
            "summary.json: `{key}` is not a finite number; {what} are unusable (please report this bug)"
        )));
    }
    let mut text = serde_json::to_string_pretty(summary)
        .map_err(|e| Error::Impossible(format!("summary.json: {e}")))?;
    text.push('\n');
    Ok(text)
}
