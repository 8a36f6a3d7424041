//! The run configuration: the TOML schema of `spec/interfaces.md` (strict: unknown
//! keys are errors) and its validation into a [`Plan`] the engine can run.

mod edit;
pub mod fragmentation;

pub(crate) use edit::species_parameter;
pub use edit::{parse_numbers, BoxSpec, Edit, Overrides, SizeEdit, SWEEP_PARAMETERS};

use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use crate::species::{Orientation, Shape, SizeDist, SizeTable, Species, Within};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Deposition under gravity, or random sequential addition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Sequential drop-and-roll deposition.
    #[default]
    Deposit,
    /// Random sequential addition (no gravity).
    Rsa,
}

/// How the floor is prepared before deposition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BaseLayerKind {
    /// Random saturated layer on the floor, then a gap-filling sweep.
    #[default]
    Random,
    /// Bare floor.
    None,
}

/// The whole configuration file, as written by the user (defaults filled in).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// 2 or 3.
    #[serde(default = "default_dim")]
    pub dim: u8,
    /// Seed of the run's random generator.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// `deposit` or `rsa`.
    #[serde(default)]
    pub mode: Mode,
    /// The container.
    #[serde(default, rename = "box")]
    pub container: BoxConfig,
    /// When to stop, and the base layer.
    #[serde(default)]
    pub fill: FillConfig,
    /// The species, at least one.
    #[serde(default = "default_species")]
    pub species: Vec<SpeciesConfig>,
    /// Analysis settings.
    #[serde(default)]
    pub analysis: AnalysisConfig,
    /// Load and break every bed (`fragmentation.*` in its summary).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fragmentation: Option<fragmentation::FragmentationConfig>,
    /// Defaults of `packbed ensemble` (the replicate count); ignored by `run`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<EnsembleConfig>,
    /// Values of one parameter to run as separate ensembles (`packbed ensemble`
    /// only: `run` refuses a config with a sweep, since it builds one bed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepConfig>,
}

/// `[box]`: a preset, a cube of `diameters` large diameters, or explicit sizes.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxConfig {
    /// `"thesis"` (the default when nothing else is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// A cube (square in 2D) of side `diameters × 2 r_max`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameters: Option<Real>,
    /// Explicit width (x).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<Real>,
    /// Explicit depth (y, 3D only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<Real>,
    /// Explicit height (roof).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<Real>,
    /// Periodic side boundaries.
    #[serde(default)]
    pub periodic: bool,
}

/// `[fill]`: stop at the roof or after a count; base layer.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FillConfig {
    /// `"roof"` (default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<String>,
    /// Place exactly this many particles (the roof is ignored).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<u64>,
    /// Roof misses (particles that would stick out above the roof, discarded)
    /// tolerated in total before stopping; the next one stops the fill.
    #[serde(default = "default_roof_misses")]
    pub roof_misses: u64,
    /// `random` or `none`.
    #[serde(default)]
    pub base_layer: BaseLayerKind,
}

/// The source study kept dropping after a particle stuck out above the roof
/// and stopped only after many such misses; 100 in total reproduces its
/// published packing fractions in 2D and 3D (`spec/model.md`, "Filling").
pub const DEFAULT_ROOF_MISSES: u64 = 100;

fn default_roof_misses() -> u64 {
    DEFAULT_ROOF_MISSES
}

impl Default for FillConfig {
    fn default() -> Self {
        FillConfig {
            until: None,
            count: None,
            roof_misses: DEFAULT_ROOF_MISSES,
            base_layer: BaseLayerKind::Random,
        }
    }
}

/// `[[species]]`: one species.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeciesConfig {
    /// Optional name used in reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Fixed radius (or give `size`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<Real>,
    /// A size distribution instead of a fixed radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<SizeConfig>,
    /// Number ratio.
    #[serde(default = "default_ratio")]
    pub ratio: Real,
    /// `sphere` (default) or `chain`.
    #[serde(default = "default_shape")]
    pub shape: String,
    /// Beads per chain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beads: Option<u32>,
    /// Bead centre distance in radii.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<Real>,
    /// Chain orientation on entry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
}

/// `size = { dist = "...", ... }` or `size = { table = "psd.csv" }`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SizeConfig {
    /// `normal`, `lognormal` or `uniform`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dist: Option<String>,
    /// Normal: mean radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<Real>,
    /// Normal: standard deviation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sd: Option<Real>,
    /// Lognormal: median radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub median: Option<Real>,
    /// Lognormal: geometric standard deviation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gsd: Option<Real>,
    /// Uniform: smallest radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<Real>,
    /// Uniform: largest radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<Real>,
    /// A PSD table (relative to the config file): discrete sizes, sieve
    /// classes or a cumulative curve, as its header says ([`SizeTable`]).
    ///
    /// [`SizeTable`]: crate::species::SizeTable
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<PathBuf>,
    /// How sizes spread within a class of a table: `log-uniform` (default) or
    /// `uniform`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub within: Option<String>,
}

/// `[analysis]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisConfig {
    /// Contact tolerance relative to the smaller radius.
    #[serde(default = "default_contact_tol")]
    pub contact_tol: Real,
    /// Percolation: particles with `r >=` this are large (default: largest class).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub large_radius: Option<Real>,
    /// Bulk measures are null when the bulk region holds fewer bodies than this.
    #[serde(default = "default_bulk_min_bodies")]
    pub bulk_min_bodies: u64,
    /// Chain angles from the `vertical` (default) or the `horizontal`.
    #[serde(default, skip_serializing_if = "AngleFrom::is_vertical")]
    pub chain_angle_from: AngleFrom,
    /// The measures to compute (default: [`Measure::DEFAULT`], all but the pore space); the
    /// contacts are always found.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measures: Option<Vec<Measure>>,
    /// Density of the solid in kg/m³: the specific cake resistance and the
    /// solids' mass per area (needs `length_unit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solid_density: Option<Real>,
    /// The length of one unit of the bed's lengths (`m`, `mm`, `um`, `nm`):
    /// permeabilities in m² and the cake resistance in m/kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<LengthUnit>,
    /// `[analysis.flow]`: the flow through the pore network.
    #[serde(default, skip_serializing_if = "FlowConfig::is_default")]
    pub flow: FlowConfig,
}

/// `[analysis.flow]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlowConfig {
    /// Fluid viscosity (default 1; `k` does not depend on it).
    #[serde(default = "default_viscosity")]
    pub viscosity: Real,
    /// Axes to drive the flow along, of `x`, `y`, `z` (default: z, and x and y
    /// on periodic beds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<Vec<FlowAxis>>,
    /// The flow region `[z_lo, z_hi]` (default: the bulk slab).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slab: Option<[Real; 2]>,
}

/// An axis of `[analysis.flow] axes`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FlowAxis {
    /// Along x.
    X,
    /// Along y (3D).
    Y,
    /// Along z, through the cake.
    Z,
}

fn default_viscosity() -> Real {
    1.0
}

impl Default for FlowConfig {
    fn default() -> Self {
        FlowConfig {
            viscosity: default_viscosity(),
            axes: None,
            slab: None,
        }
    }
}

impl FlowConfig {
    /// True when nothing is set, so that configs which do not use it keep
    /// their serialised form.
    pub fn is_default(&self) -> bool {
        *self == FlowConfig::default()
    }

    fn check(&self) -> Result<()> {
        positive(self.viscosity, "analysis.flow.viscosity")?;
        if let Some(axes) = &self.axes {
            if axes.is_empty() {
                return Err(Error::config(
                    "analysis.flow.axes is empty: name at least one of x, y, z",
                ));
            }
        }
        if let Some([lo, hi]) = self.slab {
            if !(lo.is_finite() && hi.is_finite() && hi > lo) {
                return Err(Error::config(format!(
                    "analysis.flow.slab must be [z_lo, z_hi] with z_lo < z_hi, got [{lo}, {hi}]"
                )));
            }
        }
        Ok(())
    }
}

/// The length of one unit of a bed's lengths (`[analysis] length_unit`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LengthUnit {
    /// Metre.
    #[serde(rename = "m")]
    Metre,
    /// Millimetre.
    #[serde(rename = "mm")]
    Millimetre,
    /// Micrometre (`um` or `µm`).
    #[serde(rename = "um", alias = "µm", alias = "μm")]
    Micrometre,
    /// Nanometre.
    #[serde(rename = "nm")]
    Nanometre,
}

impl LengthUnit {
    /// The config name: `m`, `mm`, `um` or `nm`.
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Millimetre => "mm",
            LengthUnit::Micrometre => "um",
            LengthUnit::Nanometre => "nm",
        }
    }

    /// The symbol for axes and legends: `m`, `mm`, `µm`, `nm`.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Micrometre => "µm",
            u => u.name(),
        }
    }

    /// Metres per unit.
    pub fn metres(self) -> Real {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Millimetre => 1e-3,
            LengthUnit::Micrometre => 1e-6,
            LengthUnit::Nanometre => 1e-9,
        }
    }
}

/// A set of measures (a copyable value for the analysis options).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Measures(u8);

impl Measures {
    /// Every measure.
    pub fn all() -> Measures {
        Measures::of(&Measure::ALL)
    }

    /// The measures of a run that chooses none: all but the pore space, whose
    /// triangulation and flow solve cost more than the rest together on a
    /// large bed (BENCHMARKS.md) and are asked for by name.
    pub fn default_set() -> Measures {
        Measures::of(&Measure::DEFAULT)
    }

    /// These measures.
    pub fn of(list: &[Measure]) -> Measures {
        Measures(list.iter().fold(0, |bits, m| bits | m.bit()))
    }

    /// True when `m` is in the set.
    pub fn has(self, m: Measure) -> bool {
        self.0 & m.bit() != 0
    }

    /// The names of the default measures not in the set, in summary order
    /// (the measures asked for by name are not "left out" when absent).
    pub fn left_out(self) -> Vec<&'static str> {
        Measure::DEFAULT
            .into_iter()
            .filter(|&m| !self.has(m))
            .map(Measure::name)
            .collect()
    }
}

impl Default for Measures {
    fn default() -> Self {
        Measures::default_set()
    }
}

/// One measure of a bed that the user may choose (`[analysis] measures`,
/// `--measures`): e.g. a bed meant as the start of a DEM run needs no
/// percolation, the slowest measure of a large bed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Measure {
    /// `packing.*`: global, bulk, regional packing fractions and the profile.
    Packing,
    /// `coordination.*`: coordination numbers.
    Coordination,
    /// `percolation.*`: chains of large particles from wall to wall.
    Percolation,
    /// `voids.*`: the voids of the contact network (2D beds).
    Voids,
    /// `orientation.*`: chain orientation (beds with chains).
    Orientation,
    /// `segregation.*`: size segregation.
    Segregation,
    /// `pores.*`: the pores and constrictions of the regular triangulation.
    Pores,
    /// `permeability.*`: Stokes flow through the pore network.
    Permeability,
}

impl Measure {
    /// Every measure, in the order of `summary.json`.
    pub const ALL: [Measure; 8] = [
        Measure::Packing,
        Measure::Coordination,
        Measure::Percolation,
        Measure::Voids,
        Measure::Orientation,
        Measure::Segregation,
        Measure::Pores,
        Measure::Permeability,
    ];

    /// The measures computed when none are chosen: the first six of [`Measure::ALL`].
    pub const DEFAULT: [Measure; 6] = {
        let a = Measure::ALL;
        [a[0], a[1], a[2], a[3], a[4], a[5]]
    };

    /// The name in configs, options and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Measure::Packing => "packing",
            Measure::Coordination => "coordination",
            Measure::Percolation => "percolation",
            Measure::Voids => "voids",
            Measure::Orientation => "orientation",
            Measure::Segregation => "segregation",
            Measure::Pores => "pores",
            Measure::Permeability => "permeability",
        }
    }

    fn bit(self) -> u8 {
        1 << Measure::ALL.iter().position(|&m| m == self).unwrap_or(0)
    }

    /// `packing,coordination` → measures; `all` → every measure.
    pub fn parse_list(text: &str) -> std::result::Result<Vec<Measure>, String> {
        if text.trim() == "all" {
            return Ok(Measure::ALL.to_vec());
        }
        text.split(',')
            .map(|name| {
                let name = name.trim();
                if name == "all" {
                    // Accepting it would hide a list that meant something
                    // narrower; the message says how to write either.
                    return Err(format!(
                        "`all` cannot be part of a list (it already means every measure): \
                         give `all` alone, or only the measures wanted, as in `{}`",
                        text.split(',')
                            .map(str::trim)
                            .filter(|n| *n != "all")
                            .map(crate::error::echo)
                            .collect::<Vec<_>>()
                            .join(",")
                    ));
                }
                Measure::ALL
                    .into_iter()
                    .find(|m| m.name() == name)
                    .ok_or_else(|| {
                        let known: Vec<&str> = Measure::ALL.iter().map(|m| m.name()).collect();
                        format!(
                            "unknown measure `{}` (choose from {}, or all)",
                            crate::error::echo(name),
                            known.join(", ")
                        )
                    })
            })
            .collect()
    }
}

impl Default for AnalysisConfig {
    fn default() -> Self {
        AnalysisConfig {
            contact_tol: default_contact_tol(),
            large_radius: None,
            bulk_min_bodies: default_bulk_min_bodies(),
            chain_angle_from: AngleFrom::Vertical,
            measures: None,
            solid_density: None,
            length_unit: None,
            flow: FlowConfig::default(),
        }
    }
}

impl AnalysisConfig {
    /// Refuses a negative or non-finite contact tolerance and a threshold
    /// radius that is not positive.
    pub fn check(&self) -> Result<()> {
        self.check_naming(&|key| format!("analysis.{key}"))
    }

    /// [`Self::check`], each setting called what `name` makes of its key
    /// (`contact_tol`): the command names its options, not the config's keys.
    pub fn check_naming(&self, name: &dyn Fn(&str) -> String) -> Result<()> {
        if let Some(why) = contact_tol_problem(self.contact_tol, &name("contact_tol")) {
            return Err(Error::config(why));
        }
        if let Some(r) = self.large_radius {
            positive(r, &name("large_radius"))?;
        }
        self.flow.check()?;
        if let Some(rho) = self.solid_density {
            positive(rho, &name("solid_density"))?;
            if self.length_unit.is_none() {
                return Err(Error::config(format!(
                    "{} (kg/m³) needs {}, the length of one unit of the bed (m, mm, um or nm), \
                     to give the cake resistance in m/kg",
                    name("solid_density"),
                    name("length_unit")
                )));
            }
        }
        Ok(())
    }
}

fn default_bulk_min_bodies() -> u64 {
    BULK_MIN_BODIES
}

/// Default minimum of bodies in the bulk region for bulk measures: the source
/// study's small boxes hold about 4, whose packing fraction (up to 0.765, above
/// the densest packing) is noise, not a bulk value.
pub const BULK_MIN_BODIES: u64 = 50;

/// The direction chain angles are measured from (`analysis.chain_angle_from`,
/// `packbed analyze --chain-angle-from`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AngleFrom {
    /// From the vertical: signed −90°–90° in 2D, polar 0°–90° in 3D (default).
    #[default]
    Vertical,
    /// From the horizontal, as the source study: 0°–180° in 2D, 0°–90° in 3D.
    Horizontal,
}

impl AngleFrom {
    /// True for the default, so that configs which do not choose keep their
    /// serialised form (and ensemble fingerprints) unchanged.
    pub fn is_vertical(&self) -> bool {
        *self == AngleFrom::Vertical
    }

    /// The name used in configs and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            AngleFrom::Vertical => "vertical",
            AngleFrom::Horizontal => "horizontal",
        }
    }

    /// This convention's angle of an axis whose angle from vertical is `a`
    /// (signed in 2D, polar in 3D), degrees.
    pub fn convert(self, a: Real) -> Real {
        match self {
            AngleFrom::Vertical => a,
            AngleFrom::Horizontal => 90.0 - a,
        }
    }

    /// The range of the angles in dimension `d`, degrees.
    pub fn range(self, d: usize) -> (Real, Real) {
        match (self, d) {
            (AngleFrom::Vertical, 2) => (-90.0, 90.0),
            (AngleFrom::Horizontal, 2) => (0.0, 180.0),
            _ => (0.0, 90.0),
        }
    }
}

/// `[sweep]`: the parameter to vary and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// One of [`crate::ensemble::sweep::PARAMETERS`].
    pub parameter: String,
    /// The values, in the order the sweep runs and reports them.
    pub values: Vec<SweepValue>,
    /// Names of the values in tables and directory names (default: from the values).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub labels: Option<Vec<String>>,
}

/// One value of a swept parameter: a number, a list of numbers, or a text
/// (a PSD table's file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SweepValue {
    /// A single number.
    Number(f64),
    /// A list of numbers.
    List(Vec<f64>),
    /// A text: a file name.
    Text(String),
}

/// `[ensemble]`: defaults of `packbed ensemble` stored with the config.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnsembleConfig {
    /// Number of replicate beds (per sweep value) when `--runs` is not given.
    pub runs: u64,
}

fn default_dim() -> u8 {
    3
}
fn default_seed() -> u64 {
    1
}
fn default_ratio() -> Real {
    1.0
}
fn default_shape() -> String {
    "sphere".into()
}
fn default_contact_tol() -> Real {
    DEFAULT_CONTACT_TOL
}

/// The contact tolerance of every analysis unless told otherwise: a gap of at
/// most this, relative to the smaller radius, is a contact.
pub const DEFAULT_CONTACT_TOL: Real = 1e-6;
fn default_species() -> Vec<SpeciesConfig> {
    [20.0, 10.0]
        .iter()
        .map(|&r| SpeciesConfig {
            name: None,
            radius: Some(r),
            size: None,
            ratio: 1.0,
            shape: default_shape(),
            beads: None,
            spacing: None,
            orientation: None,
        })
        .collect()
}

impl Default for Config {
    fn default() -> Self {
        Config {
            dim: default_dim(),
            seed: default_seed(),
            mode: Mode::default(),
            container: BoxConfig::default(),
            fill: FillConfig::default(),
            species: default_species(),
            analysis: AnalysisConfig::default(),
            fragmentation: None,
            ensemble: None,
            sweep: None,
        }
    }
}

impl Config {
    /// Parses a TOML configuration; `origin` names the file in error messages.
    pub fn from_toml(text: &str, origin: &str) -> Result<Config> {
        // `FILE:LINE: what`, the shape of every error with a place in a file.
        toml::from_str(text).map_err(|e| {
            let message = e.message().trim().to_string();
            match e.span() {
                Some(s) => Error::Data {
                    path: origin.into(),
                    line: text[..s.start.min(text.len())].matches('\n').count() + 1,
                    message,
                },
                None => Error::config(format!("{origin}: {message}")),
            }
        })
    }

    /// Reads and parses a TOML configuration file.
    pub fn from_file(path: &Path) -> Result<Config> {
        let text = crate::input::read_text(path)?;
        let mut c = Config::from_toml(&text, &path.display().to_string())?;
        // PSD tables are relative to the config file, and so are the tables
        // a sweep goes through.
        if let Some(dir) = path.parent() {
            for s in &mut c.species {
                if let Some(SizeConfig { table: Some(t), .. }) = &mut s.size {
                    if t.is_relative() {
                        *t = dir.join(&*t);
                    }
                }
            }
            if let Some(sweep) = &mut c.sweep {
                if sweep.parameter.ends_with(".size.table") {
                    for v in &mut sweep.values {
                        if let SweepValue::Text(t) = v {
                            if Path::new(t.as_str()).is_relative() {
                                *t = dir.join(&*t).display().to_string();
                            }
                        }
                    }
                }
            }
        }
        Ok(c)
    }
}

/// When deposition stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fill {
    /// Until a particle would stick out above the roof, `misses` overflows tolerated.
    Roof {
        /// Overflows (each discarded) tolerated before stopping.
        misses: u64,
    },
    /// Exactly this many particles (spheres or bodies), roof ignored.
    Count(u64),
}

/// A plan of either dimension, as [`Config::planned`] makes it.
#[derive(Clone, Debug)]
pub enum AnyPlan {
    /// A 2D plan.
    D2(Plan<2>),
    /// A 3D plan.
    D3(Plan<3>),
}

impl AnyPlan {
    /// See [`Config::estimated_particles`].
    pub fn estimated_particles(&self) -> u64 {
        match self {
            AnyPlan::D2(p) => p.estimated_particles(),
            AnyPlan::D3(p) => p.estimated_particles(),
        }
    }

    /// See [`Plan::particles_at_most`].
    pub fn particles_at_most(&self) -> u64 {
        match self {
            AnyPlan::D2(p) => p.particles_at_most(),
            AnyPlan::D3(p) => p.particles_at_most(),
        }
    }
}

/// A validated configuration in the engine's terms, for dimension `D`.
#[derive(Clone, Debug)]
pub struct Plan<const D: usize> {
    /// Seed of the run.
    pub seed: u64,
    /// Deposit or RSA.
    pub mode: Mode,
    /// The box.
    pub container: Container<D>,
    /// Stop rule.
    pub fill: Fill,
    /// Base layer.
    pub base_layer: BaseLayerKind,
    /// The species, in config order.
    pub species: Vec<Species>,
    /// Contact tolerance relative to the smaller radius.
    pub contact_tol: Real,
    /// Percolation threshold radius.
    pub large_radius: Real,
}

pub use crate::math::LENGTH_RANGE;

/// Why lengths from `shortest` to `longest` cannot be worked with, if they
/// leave [`LENGTH_RANGE`].
pub(crate) fn length_scale_problem(shortest: Real, longest: Real) -> Option<String> {
    let (lo, hi) = LENGTH_RANGE;
    (shortest < lo || longest > hi).then(|| {
        format!(
            "lengths from {shortest:e} to {longest:e} are outside the range packbed computes \
             exactly in ({lo:e} to {hi:e}): choose other units"
        )
    })
}

/// Most beads of its own chain a bead may overlap on each side. The volume of
/// a chain and the checks of the bed visit every overlapping pair: a chain of
/// 100000 beads 1e-6 radii apart has 5e9 of them.
pub const MAX_OWN_OVERLAPS: u64 = 64;

/// How many beads of its chain a bead overlaps on each side: beads `k` apart
/// are `k * spacing` radii apart and overlap while that is below 2.
fn own_overlaps(beads: u32, spacing: Real) -> u64 {
    let reach = ((2.0 / spacing).ceil() - 1.0).max(0.0);
    (reach.min(u64::MAX as Real) as u64).min(beads.saturating_sub(1) as u64)
}

/// Largest contact tolerance, relative to the smaller radius. Beyond it two
/// spheres a radius apart would count as touching, and the contact search, sized
/// by the tolerance, grows with its cube.
pub const MAX_CONTACT_TOL: Real = 1.0;

/// Why the contact tolerance `tol` (named `what`) is refused, if it is.
pub fn contact_tol_problem(tol: Real, what: &str) -> Option<String> {
    if !(tol.is_finite() && tol >= 0.0) {
        Some(format!("{what} must be a non-negative number, got {tol}"))
    } else if tol > MAX_CONTACT_TOL {
        Some(format!(
            "{what} is {tol}, but at most {MAX_CONTACT_TOL}: it is a gap relative to the \
             smaller radius, and a larger gap no longer means touching"
        ))
    } else {
        None
    }
}

fn positive(v: Real, what: &str) -> Result<Real> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::config(format!(
            "{what} must be a positive number, got {v}"
        )))
    }
}

impl SpeciesConfig {
    fn resolve(&self, index: usize, metres_per_unit: Option<Real>) -> Result<Species> {
        let at = format!("species[{index}]");
        let size = match (&self.radius, &self.size) {
            (Some(_), Some(_)) => {
                return Err(Error::config(format!(
                    "{at}: give either `radius` or `size`, not both"
                )))
            }
            (None, None) => {
                return Err(Error::config(format!(
                    "{at}: missing `radius` (or a `size` distribution)"
                )))
            }
            (Some(r), None) => SizeDist::Fixed(positive(*r, &format!("{at}.radius"))?),
            (None, Some(s)) => s.resolve(&at, metres_per_unit)?,
        };
        if !(self.ratio.is_finite() && self.ratio >= 0.0) {
            return Err(Error::config(format!(
                "{at}.ratio must be a non-negative number, got {}",
                self.ratio
            )));
        }
        let shape = match self.shape.as_str() {
            "sphere" | "disc" => {
                if self.beads.is_some_and(|b| b != 1) {
                    return Err(Error::config(format!(
                        "{at}: `beads` needs shape = \"chain\""
                    )));
                }
                Shape::Sphere
            }
            "chain" => {
                let beads = self.beads.unwrap_or(1);
                if beads == 0 {
                    return Err(Error::config(format!("{at}.beads must be at least 1")));
                }
                let spacing = positive(self.spacing.unwrap_or(1.0), &format!("{at}.spacing"))?;
                let own = own_overlaps(beads, spacing);
                if own > MAX_OWN_OVERLAPS {
                    return Err(Error::config(format!(
                        "{at}: beads {spacing} radii apart overlap {own} beads of their own chain \
                         on each side, at most {MAX_OWN_OVERLAPS} (each overlap is work and memory \
                         of the analysis): give a spacing of at least {:.4} or at most {} beads",
                        2.0 / (MAX_OWN_OVERLAPS + 1) as Real,
                        MAX_OWN_OVERLAPS + 1
                    )));
                }
                let orientation = match self.orientation.as_deref() {
                    None | Some("vertical") => Orientation::Vertical,
                    Some("random") => Orientation::Random,
                    Some("horizontal") => Orientation::Horizontal,
                    Some(o) => {
                        return Err(Error::config(format!(
                        "{at}.orientation: unknown `{o}` (expected vertical, random or horizontal)"
                    )))
                    }
                };
                // One bead is a plain sphere: the same path, the same bed for a seed.
                if beads == 1 {
                    Shape::Sphere
                } else {
                    Shape::Chain {
                        beads,
                        spacing,
                        orientation,
                    }
                }
            }
            other => {
                return Err(Error::config(format!(
                    "{at}.shape: unknown shape `{other}` (expected \"sphere\" or \"chain\")"
                )))
            }
        };
        if let Some(o) = &self.orientation {
            if !["vertical", "random", "horizontal"].contains(&o.as_str()) {
                return Err(Error::config(format!(
                    "{at}.orientation: unknown `{o}` (expected vertical, random or horizontal)"
                )));
            }
        }
        Ok(Species {
            name: self.name.clone().unwrap_or_default(),
            shape,
            size,
            ratio: self.ratio,
        })
    }
}

impl SizeConfig {
    fn resolve(&self, at: &str, metres_per_unit: Option<Real>) -> Result<SizeDist> {
        let need = |v: Option<Real>, key: &str| -> Result<Real> {
            let v = v.ok_or_else(|| Error::config(format!("{at}.size: missing `{key}`")))?;
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(Error::config(format!(
                    "{at}.size.{key} must be a non-negative number, got {v}"
                )))
            }
        };
        if let Some(t) = &self.table {
            if self.dist.is_some() {
                return Err(Error::config(format!(
                    "{at}.size: give either `table` or `dist`, not both"
                )));
            }
            if self.min.is_some() || self.max.is_some() {
                return Err(Error::config(format!(
                    "{at}.size: `min`/`max` do not apply to a table (its rows bound it; leave out the rows you do not want)"
                )));
            }
            let within = match self.within.as_deref() {
                None | Some("log-uniform") => Within::LogUniform,
                Some("uniform") => Within::Uniform,
                Some(w) => {
                    return Err(Error::config(format!(
                        "{at}.size.within: unknown `{w}` (expected log-uniform or uniform)"
                    )))
                }
            };
            return SizeTable::read(t, within, metres_per_unit).map(SizeDist::Table);
        }
        if self.within.is_some() {
            return Err(Error::config(format!(
                "{at}.size.within applies to a `table`'s classes only"
            )));
        }
        let dist = self.dist.as_deref().ok_or_else(|| {
            Error::config(format!(
                "{at}.size: missing `dist` (normal, lognormal, uniform) or `table`"
            ))
        })?;
        let d = match dist {
            "normal" => {
                let mean = positive(need(self.mean, "mean")?, &format!("{at}.size.mean"))?;
                let sd = need(self.sd, "sd")?;
                let (lo, hi) = self.window(at, SizeDist::normal_window(mean, sd))?;
                bounded(
                    at,
                    SizeDist::Normal { mean, sd, lo, hi },
                    format!("normal(mean {mean}, sd {sd})"),
                )?
            }
            "lognormal" => {
                let median = positive(need(self.median, "median")?, &format!("{at}.size.median"))?;
                let gsd = need(self.gsd, "gsd")?;
                if gsd < 1.0 {
                    return Err(Error::config(format!(
                        "{at}.size.gsd must be >= 1 (a geometric standard deviation), got {gsd}"
                    )));
                }
                let (lo, hi) = self.window(at, SizeDist::lognormal_window(median, gsd))?;
                bounded(
                    at,
                    SizeDist::Lognormal {
                        median,
                        gsd,
                        lo,
                        hi,
                    },
                    format!("lognormal(median {median}, gsd {gsd})"),
                )?
            }
            "uniform" => {
                let min = positive(need(self.min, "min")?, &format!("{at}.size.min"))?;
                let max = need(self.max, "max")?;
                if max < min {
                    return Err(Error::config(format!(
                        "{at}.size: max ({max}) is smaller than min ({min})"
                    )));
                }
                SizeDist::Uniform { min, max }
            }
            other => {
                return Err(Error::config(format!(
                    "{at}.size.dist: unknown distribution `{other}` (expected normal, lognormal or uniform)"
                )))
            }
        };
        Ok(d)
    }

    /// The window `[min, max]` of a normal or lognormal: the bounds given, a
    /// missing one taken from the `default` truncation.
    fn window(&self, at: &str, default: (Real, Real)) -> Result<(Real, Real)> {
        let bound = |v: Option<Real>, key: &str| {
            v.map(|v| positive(v, &format!("{at}.size.{key}")))
                .transpose()
        };
        let (min, max) = (bound(self.min, "min")?, bound(self.max, "max")?);
        let k = crate::species::TRUNCATION_SIGMAS;
        match (min, max) {
            (Some(min), Some(max)) if max < min => Err(Error::config(format!(
                "{at}.size: max ({max}) is smaller than min ({min})"
            ))),
            (Some(min), None) if min > default.1 => Err(Error::config(format!(
                "{at}.size.min ({min}) is above the default upper end of the window ({}, +{k} sd); give `max` too",
                default.1
            ))),
            (None, Some(max)) if max < default.0 => Err(Error::config(format!(
                "{at}.size.max ({max}) is below the default lower end of the window ({}); give `min` too",
                default.0
            ))),
            (min, max) => Ok((min.unwrap_or(default.0), max.unwrap_or(default.1))),
        }
    }
}

/// `dist` (named `what`) if its window holds enough of it to draw from. A
/// distribution of no spread gets the window of its one radius, so that
/// `bounds()` (the grid, the box presets) is what is drawn, not the bounds given.
fn bounded(at: &str, dist: SizeDist, what: String) -> Result<SizeDist> {
    let (lo, hi) = dist.bounds();
    if lo == hi {
        // `min = max` asks for one radius, whatever the distribution.
        return Ok(dist);
    }
    let mass = dist.window_mass();
    if mass >= crate::species::MIN_WINDOW_MASS {
        return Ok(match dist {
            SizeDist::Normal { mean, sd, .. } if sd == 0.0 => SizeDist::Normal {
                mean,
                sd,
                lo: mean,
                hi: mean,
            },
            SizeDist::Lognormal { median, gsd, .. } if gsd == 1.0 => SizeDist::Lognormal {
                median,
                gsd,
                lo: median,
                hi: median,
            },
            d => d,
        });
    }
    Err(Error::config(format!(
        "{at}.size: the window [{lo}, {hi}] holds {} of {what} (at least {:e} needed); move `min`/`max` towards the distribution or widen them",
        if mass > 0.0 { format!("only {mass:.1e}") } else { "nothing".into() },
        crate::species::MIN_WINDOW_MASS
    )))
}

/// Peak bytes per particle of a run with the default measures: measured
/// (`/usr/bin/time -v`, maximum resident set, 10^6 equal particles) at 620 in
/// 2D and 860 in 3D, rounded up.
const BYTES_PER_PARTICLE: [u64; 2] = [768, 1024];

/// Extra peak bytes per particle of the pore space (`pores`,
/// `permeability`): 7.9 KB measured for 10^5 spheres with every measure.
const BYTES_PER_PARTICLE_PORES: u64 = 8192;

/// Address space a run takes whatever its size (the program, thread stacks,
/// the allocator's arenas): a 10^6-sphere run needs 1.2 GiB under `ulimit -v`
/// against its 0.84 GB resident.
const BYTES_FIXED: u64 = 192 << 20;

/// The peak memory of a run placing `particles` in `dim` dimensions and
/// computing `measures`, in bytes.
pub(crate) fn run_bytes(dim: u8, particles: Real, measures: &[Measure]) -> Real {
    let pores = measures
        .iter()
        .any(|m| matches!(m, Measure::Pores | Measure::Permeability));
    let per = BYTES_PER_PARTICLE[usize::from(dim == 3)]
        + if pores { BYTES_PER_PARTICLE_PORES } else { 0 };
    particles * per as Real + BYTES_FIXED as Real
}

impl Config {
    /// The largest particle extent that sets the thesis box: the largest radius.
    fn r_max(species: &[Species]) -> Real {
        species
            .iter()
            .map(|s| s.size.bounds().1)
            .fold(0.0, Real::max)
    }

    /// Validates the configuration for its own dimension (see [`Config::plan`]).
    pub fn validate(&self) -> Result<()> {
        self.planned().map(drop)
    }

    /// The plan of this config in its own dimension: validated once, its PSD
    /// tables read once, then passed down to the deposition.
    pub fn planned(&self) -> Result<AnyPlan> {
        match self.dim {
            2 => self.plan::<2>().map(AnyPlan::D2),
            3 => self.plan::<3>().map(AnyPlan::D3),
            d => Err(Error::config(format!("dim must be 2 or 3, got {d}"))),
        }
    }

    /// Validates the configuration for dimension `D` (which must equal `self.dim`).
    pub fn plan<const D: usize>(&self) -> Result<Plan<D>> {
        if D != self.dim as usize {
            return Err(Error::config(format!(
                "dim is {}, but a {D}D plan was asked for",
                self.dim
            )));
        }
        if let Some(sw) = &self.sweep {
            return Err(Error::config(format!(
                "this config has a [sweep] over `{}` ({} values), which needs `packbed ensemble`; `packbed run` builds one bed (remove the [sweep] table, or set the parameter, to run one value)",
                sw.parameter,
                sw.values.len()
            )));
        }
        if self.species.is_empty() {
            return Err(Error::config("at least one [[species]] is needed"));
        }
        let species = self
            .species
            .iter()
            .enumerate()
            .map(|(i, s)| s.resolve(i, self.analysis.length_unit.map(LengthUnit::metres)))
            .collect::<Result<Vec<_>>>()?;
        let total: Real = species.iter().map(|s| s.ratio).sum();
        if total <= 0.0 {
            return Err(Error::config("the species ratios sum to zero"));
        }
        let species = name_species(species);
        let r_max = Self::r_max(&species);
        let container = self.container.resolve::<D>(&species, r_max)?;
        let fill = match (&self.fill.until, self.fill.count) {
            (Some(_), Some(_)) => {
                return Err(Error::config(
                    "fill: give either `until = \"roof\"` or `count`, not both",
                ))
            }
            (_, Some(0)) => return Err(Error::config("fill.count must be at least 1")),
            (_, Some(n)) => Fill::Count(n),
            (Some(u), None) if u != "roof" => {
                return Err(Error::config(format!(
                    "fill.until: unknown value `{u}` (expected \"roof\", or use `count = N`)"
                )))
            }
            _ => Fill::Roof {
                misses: self.fill.roof_misses,
            },
        };
        chains_fit(&species, &container)?;
        let r_min = species
            .iter()
            .map(|s| s.size.bounds().0)
            .fold(Real::INFINITY, Real::min);
        let longest = container.size.0.iter().copied().fold(r_max, Real::max);
        if let Some(why) = length_scale_problem(r_min, longest) {
            return Err(Error::config(format!("radii and box: {why}")));
        }
        // Refuse requests that cannot fit in memory, before allocating anything.
        // Beads, not bodies: each bead of a chain is a particle of the bed.
        let beads = species
            .iter()
            .map(|s| Real::from(s.shape.beads()))
            .fold(1.0, Real::max);
        let estimate = match fill {
            Fill::Count(n) => n as Real * beads,
            Fill::Roof { .. } => roof_at_most(&container, r_min),
        };
        let measures = self
            .analysis
            .measures
            .as_deref()
            .unwrap_or(&Measure::DEFAULT);
        // RSA spreads the bed through the whole box; a deposited bed lies on
        // the floor, as tall as its particles make it.
        let extent = (0..D)
            .filter(|&k| k + 1 < D || self.mode == Mode::Rsa)
            .map(|k| container.size[k])
            .fold(0.0, Real::max);
        if let Some(why) = pore_space_extent_problem(measures, extent / (2.0 * r_min)) {
            return Err(Error::Impossible(format!("this box: {why}")));
        }
        let memory = crate::input::memory_budget_bytes() as Real;
        let needed = run_bytes(self.dim, estimate, measures);
        if needed > memory {
            return Err(Error::Impossible(format!(
                "this run would place up to {estimate:.3e} particles and need about {:.2} GB, more than the {:.2} GB packbed may use (the least of the machine's memory, `ulimit -v` and the cgroup's `memory.max`)",
                needed / 1e9,
                memory / 1e9
            )));
        }
        // The most particles memory holds, whatever the measures.
        let budget = (memory - BYTES_FIXED as Real).max(0.0)
            / BYTES_PER_PARTICLE[usize::from(D == 3)] as Real;
        // Every roof overflow costs a whole drop, so misses get the bound the
        // particle count has: beyond it a run would go on for days (RSA ignores
        // them).
        if let (Fill::Roof { misses }, Mode::Deposit) = (fill, self.mode) {
            let most = budget as u64;
            if misses > most {
                return Err(Error::config(format!(
                    "fill.roof_misses must be at most {most} (as many drops as fill.count may place on this machine), got {misses}"
                )));
            }
        }
        self.analysis.check()?;
        if let Some(f) = &self.fragmentation {
            f.check()?;
        }
        let tol = self.analysis.contact_tol;
        let large_radius = self.analysis.large_radius.unwrap_or(r_max);
        Ok(Plan {
            seed: self.seed,
            mode: self.mode,
            container,
            fill,
            base_layer: self.fill.base_layer,
            species,
            contact_tol: tol,
            large_radius,
        })
    }
}

impl Config {
    /// How many particles the run will place: exact for `count`, a guess for
    /// the roof (box volume × typical packing ÷ mean particle volume), 0 when
    /// the config is invalid. For progress bars.
    pub fn estimated_particles(&self) -> u64 {
        match self.dim {
            2 | 3 => self.planned().map_or(0, |p| p.estimated_particles()),
            _ => 0,
        }
    }
}

/// The most particles a box filled to its roof can hold: its volume in balls
/// of the smallest radius (more than any packing of them holds).
fn roof_at_most<const D: usize>(container: &Container<D>, r_min: Real) -> Real {
    container.volume() / crate::math::ball_volume::<D>(r_min) + 1.0
}

impl<const D: usize> Plan<D> {
    /// An upper bound on the particles the run will place, where
    /// [`Plan::estimated_particles`] is a guess. They differ most for RSA: it
    /// rejects large sizes more than small ones and fills the last gaps with
    /// whatever fits, so a mix of radii 70 and 2 estimated at 34 particles
    /// placed 462,134.
    pub fn particles_at_most(&self) -> u64 {
        match self.fill {
            Fill::Count(_) => self.estimated_particles(),
            Fill::Roof { .. } => {
                let r_min = self
                    .species
                    .iter()
                    .map(|s| s.size.bounds().0)
                    .fold(Real::INFINITY, Real::min);
                let n = roof_at_most(&self.container, r_min);
                if n.is_finite() {
                    n as u64
                } else {
                    u64::MAX
                }
            }
        }
    }

    /// See [`Config::estimated_particles`].
    pub fn estimated_particles(&self) -> u64 {
        if let Fill::Count(n) = self.fill {
            // The last body may overshoot the count by all but one of its beads
            // (one chain of 34444 beads for a count of 54).
            let beads = self
                .species
                .iter()
                .map(|s| s.shape.beads())
                .max()
                .unwrap_or(1);
            return n.saturating_add(beads as u64 - 1);
        }
        // Mean volume per particle (bead), weighting each species by its ratio
        // and its beads per body.
        let (mut beads, mut volume) = (0.0, 0.0);
        for s in &self.species {
            let n = Real::from(s.shape.beads());
            beads += s.ratio * n;
            volume += s.ratio * n * crate::math::ball_volume::<D>(s.size.median());
        }
        if beads <= 0.0 || volume <= 0.0 {
            return 0;
        }
        // Typical packing fractions of deposited beds, 2D and 3D.
        let typical = if D == 2 { 0.8 } else { 0.6 };
        let n = self.container.volume() * typical / (volume / beads);
        if n.is_finite() {
            n as u64
        } else {
            0
        }
    }
}

/// Refuses chains longer than the box is wide: such a chain cannot lie flat
/// between the walls (it would end up standing through the floor or sticking
/// out above the roof), and across periodic sides it would overlap its own image.
fn chains_fit<const D: usize>(species: &[Species], container: &Container<D>) -> Result<()> {
    for s in species {
        let Shape::Chain { beads, spacing, .. } = s.shape else {
            continue;
        };
        if s.ratio == 0.0 {
            continue; // never drawn
        }
        let r = s.size.bounds().1;
        let length = (beads - 1) as Real * spacing * r + 2.0 * r;
        let narrowest = (0..D - 1)
            .map(|k| container.size[k])
            .fold(Real::INFINITY, Real::min);
        if length > narrowest {
            let sides = if D == 3 { "width and depth" } else { "width" };
            return Err(Error::config(format!(
                "species `{}`: a chain of {beads} beads of radius {r} is {} long, longer than the box is wide ({}); it could not lie flat in it: give a box whose {sides} are at least {}",
                s.name,
                fmt_len(length),
                fmt_size(&container.size),
                fmt_len(length)
            )));
        }
    }
    Ok(())
}

fn fmt_len(v: Real) -> String {
    let t = format!("{v:.6}");
    t.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Gives unnamed species a name: "large"/"small" for two sizes, else "s0", "s1", ….
fn name_species(mut species: Vec<Species>) -> Vec<Species> {
    let unnamed = species.iter().all(|s| s.name.is_empty());
    if unnamed && species.len() == 2 {
        let (a, b) = (species[0].size.median(), species[1].size.median());
        if a != b {
            let (big, small) = if a > b { (0, 1) } else { (1, 0) };
            species[big].name = "large".into();
            species[small].name = "small".into();
            return species;
        }
    }
    for (i, s) in species.iter_mut().enumerate() {
        if s.name.is_empty() {
            s.name = format!("s{i}");
        }
    }
    species
}

/// Refuses a bed of `particles` particles (read from a file) that this
/// machine could not analyse: the bound deposition puts on a run (3D, the
/// default measures). [`check_analysis`] checks again once the measures are
/// known.
pub fn check_particles(particles: usize, what: &str) -> Result<()> {
    check_analysis(particles, 3, &Measure::DEFAULT, what)
}

/// The widest spread of a bed whose pore space packbed computes, in smallest
/// particle diameters. The exact triangulation's arithmetic grows with the
/// spread of the coordinates it compares: 80 spheres spread through a box
/// 1e26 diameters tall took 28 s (found by the config fuzz target). No real
/// bed comes near: a floor 1e6 diameters wide holds 1e12 particles.
pub const PORE_SPACE_MAX_DIAMETERS: Real = 1e6;

/// Why the pore measures, when `measures` asks for them, cannot be computed
/// for a bed spread over `diameters` smallest diameters; `None` if they can.
pub fn pore_space_extent_problem(measures: &[Measure], diameters: Real) -> Option<String> {
    let pores = measures
        .iter()
        .any(|m| matches!(m, Measure::Pores | Measure::Permeability));
    let within = diameters <= PORE_SPACE_MAX_DIAMETERS;
    (pores && !within).then(|| {
        format!(
            "the pore measures (pores, permeability) are for beds spread over at most \
             {PORE_SPACE_MAX_DIAMETERS:e} smallest diameters, and this one spans {diameters:.3e} \
             (leave them out of the measures)"
        )
    })
}

/// Refuses to analyse a bed of `particles` particles in `dim` dimensions with
/// `measures` when that would need more memory than packbed may use (the pore
/// space costs about eight times the rest).
pub fn check_analysis(particles: usize, dim: u8, measures: &[Measure], what: &str) -> Result<()> {
    let memory = crate::input::memory_budget_bytes() as Real;
    let needed = run_bytes(dim, particles as Real, measures);
    if needed > memory {
        return Err(Error::Impossible(format!(
            "{what} holds {particles} particles and would need about {:.2} GB to analyse \
             with these measures, more than the {:.2} GB packbed may use",
            needed / 1e9,
            memory / 1e9
        )));
    }
    Ok(())
}

impl BoxConfig {
    fn resolve<const D: usize>(&self, species: &[Species], r_max: Real) -> Result<Container<D>> {
        let explicit = self.width.is_some() || self.depth.is_some() || self.height.is_some();
        let chosen = [self.preset.is_some(), self.diameters.is_some(), explicit]
            .iter()
            .filter(|&&b| b)
            .count();
        if chosen > 1 {
            return Err(Error::config(
                "box: give one of `preset`, `diameters` or `width`/`depth`/`height`",
            ));
        }
        let mut size = Vector::<D>::zero();
        if let Some(n) = self.diameters {
            let n = positive(n, "box.diameters")?;
            for k in 0..D {
                size[k] = n * 2.0 * r_max;
            }
        } else if explicit {
            let w = positive(
                self.width
                    .ok_or_else(|| Error::config("box: missing `width`"))?,
                "box.width",
            )?;
            let h = positive(
                self.height
                    .ok_or_else(|| Error::config("box: missing `height`"))?,
                "box.height",
            )?;
            size[0] = w;
            size[D - 1] = h;
            if D == 3 {
                size[1] = positive(self.depth.unwrap_or(w), "box.depth")?;
            } else if self.depth.is_some() {
                return Err(Error::config("box.depth is only for dim = 3"));
            }
        } else {
            match self.preset.as_deref().unwrap_or("thesis") {
                "thesis" => {
                    // 2D: 15 large diameters; 3D: 6. 2D chains stretch the box by beads/2.
                    let mut side = if D == 2 { 30.0 * r_max } else { 12.0 * r_max };
                    if D == 2 {
                        let beads = species.iter().map(|s| s.shape.beads()).max().unwrap_or(1);
                        if beads > 2 {
                            side *= beads as Real / 2.0;
                        }
                    }
                    for k in 0..D {
                        size[k] = side;
                    }
                }
                other => {
                    return Err(Error::config(format!(
                        "box.preset: unknown preset `{other}` (expected \"thesis\")"
                    )))
                }
            }
        }
        for k in 0..D {
            if size[k] < 2.0 * r_max {
                return Err(Error::config(format!(
                    "the box ({}) is smaller than the largest particle (diameter {})",
                    fmt_size(&size),
                    2.0 * r_max
                )));
            }
        }
        Ok(Container {
            size,
            periodic: self.periodic,
        })
    }
}

fn fmt_size<const D: usize>(s: &Vector<D>) -> String {
    s.0.iter()
        .map(|v| format!("{v}"))
        .collect::<Vec<_>>()
        .join(" × ")
}

#[cfg(test)]
mod bounds_tests {
    use super::*;

    #[test]
    fn contact_tol_above_one_radius_is_refused_with_why() {
        assert_eq!(contact_tol_problem(0.0, "t"), None);
        assert_eq!(contact_tol_problem(1.0, "t"), None);
        let why = contact_tol_problem(10.0, "analysis.contact_tol").unwrap();
        assert!(
            why.contains("at most 1") && why.contains("touching"),
            "{why}"
        );
        let config = AnalysisConfig {
            contact_tol: 10.0,
            ..AnalysisConfig::default()
        };
        let e = config.check().unwrap_err().to_string();
        assert!(e.contains("analysis.contact_tol is 10"), "{e}");
    }

    #[test]
    fn beads_overlapping_their_own_chain_are_counted() {
        assert_eq!(own_overlaps(5, 1.0), 1);
        assert_eq!(own_overlaps(5, 2.0), 0);
        assert_eq!(own_overlaps(100, 0.5), 3);
        assert_eq!(own_overlaps(100_000, 1e-6), 99_999);
        assert_eq!(own_overlaps(3, 1e-300), 2);
        assert_eq!(own_overlaps(66, 2.0 / 65.0), 64);
    }

    #[test]
    fn a_count_estimate_includes_the_last_chains_overshoot() {
        let mut c = Config::default();
        c.apply(&Edit::Count(54)).unwrap();
        assert_eq!(c.estimated_particles(), 54);
        c.apply(&Edit::Beads(5)).unwrap();
        assert_eq!(c.estimated_particles(), 58);
    }

    #[test]
    fn the_pore_space_of_a_bed_spread_too_thin_is_refused_before_the_work() {
        let all = [Measure::Pores];
        assert_eq!(pore_space_extent_problem(&all, 1e6), None);
        assert!(pore_space_extent_problem(&all, 1.1e6).is_some());
        assert!(pore_space_extent_problem(&all, Real::NAN).is_some());
        assert_eq!(pore_space_extent_problem(&Measure::DEFAULT, 1e26), None);
        // RSA fills its box: a column 1e26 diameters tall is refused with the
        // pore measures; deposited, the same box holds a bed on its floor.
        let mut c = Config::default();
        for e in [
            Edit::Radii(vec![50.0]),
            Edit::Box("200,1e28".parse().unwrap()),
            Edit::Periodic(true),
            Edit::Count(80),
            Edit::Measures(vec![Measure::Pores]),
        ] {
            c.apply(&e).unwrap();
        }
        assert!(c.validate().is_ok());
        c.apply(&Edit::Mode(Mode::Rsa)).unwrap();
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("spans 1.000e26"), "{e}");
    }
}
