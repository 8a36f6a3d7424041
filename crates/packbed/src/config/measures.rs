//! `[analysis]`: the measures a run computes and their settings (contact
//! tolerance, bulk slab, flow, length unit, orientation reference).

use super::positive;
use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// `[analysis]`. With the `cli` feature these are options of `packbed
/// analyze` (the contact tolerance and the flow aside), their documentation
/// its help.
// The fields' order is the keys' order in a config's echo and in an
// ensemble's fingerprint: changing it would change both.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields)]
pub struct AnalysisConfig {
    /// Contact tolerance relative to the smaller radius.
    #[serde(default = "default_contact_tol")]
    #[cfg_attr(feature = "cli", arg(skip = DEFAULT_CONTACT_TOL))]
    pub contact_tol: Real,
    /// Percolation threshold: particles with radius >= R count as large
    /// (default: the largest of the species' volume-median radii).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(
        feature = "cli",
        arg(long = "large", value_name = "R", allow_hyphen_values = true)
    )]
    pub large_radius: Option<Real>,
    /// Bulk measures are null when the bulk region holds fewer bodies.
    #[serde(default = "default_bulk_min_bodies")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", default_value_t = BULK_MIN_BODIES))]
    pub bulk_min_bodies: u64,
    /// Measure chain angles from the vertical (default) or from the horizontal
    /// (as the source study did).
    #[serde(default, skip_serializing_if = "AngleFrom::is_vertical")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "FROM", default_value = "vertical", value_parser = super::named::<AngleFrom>(&["vertical", "horizontal"])))]
    pub chain_angle_from: AngleFrom,
    /// Measures to compute, e.g. packing,coordination (default: packing,
    /// coordination, percolation, voids, orientation, segregation; add pores
    /// and permeability for the pore space, or all). Contacts are always found.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "LIST", value_parser = Measure::parse_list))]
    pub measures: Option<super::MeasureList>,
    /// Density of the solid in kg/m³ (with --length-unit): the specific cake
    /// resistance and the solids' mass per area.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "KG_PER_M3"))]
    pub solid_density: Option<Real>,
    /// The length of one unit of the bed file's lengths: permeabilities in m².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "UNIT", value_parser = super::named::<LengthUnit>(&["m", "mm", "um", "nm"])))]
    pub length_unit: Option<LengthUnit>,
    /// `[analysis.flow]`: the flow through the pore network.
    #[serde(default, skip_serializing_if = "FlowConfig::is_default")]
    #[cfg_attr(feature = "cli", arg(skip))]
    pub flow: FlowConfig,
    /// `[analysis.drainage]`: gas displacing the liquid from the pore network.
    #[serde(default, skip_serializing_if = "DrainageConfig::is_default")]
    #[cfg_attr(feature = "cli", arg(skip))]
    pub drainage: DrainageConfig,
    /// `[analysis.drying]`: the solid the drying cake leaves and the
    /// agglomerates it binds.
    #[serde(default, skip_serializing_if = "DryingConfig::is_default")]
    #[cfg_attr(feature = "cli", arg(skip))]
    pub drying: DryingConfig,
}

/// `[analysis.drying]`: the solid dissolved in the cake's liquid. The
/// defaults are a mother liquor saturated at 50 kg/m³ of an organic solid
/// (crystals of 1,500 kg/m³, about 4 MPa in tension).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DryingConfig {
    /// Dissolved solid, kg per m³ of liquid (default 50).
    #[serde(default = "default_concentration")]
    pub concentration: Real,
    /// Its solubility, kg/m³ (default: the concentration, a saturated
    /// mother liquor; a washed cake's liquid is below it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solubility: Option<Real>,
    /// Density of its crystals, kg/m³ (default 1500).
    #[serde(default = "default_crystal_density")]
    pub crystal_density: Real,
    /// A solid bridge is a bond when its neck radius is at least this
    /// fraction of the pair's harmonic mean radius (default 0.05).
    #[serde(default = "default_min_neck")]
    pub min_neck: Real,
    /// Tensile strength of the solid, Pa (default 3.9e6).
    #[serde(default = "default_tensile_strength")]
    pub tensile_strength: Real,
    /// `[analysis.drying.agitation]`: the dried cake loaded until its
    /// weakest bridges break (none when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub agitation: Option<AgitationConfig>,
}

/// `[analysis.drying.agitation]`: the load an agitated dryer puts on the
/// dried cake, as `packbed fragment` loads a bed, and how hard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AgitationConfig {
    /// shear (default), compression or gravity.
    #[serde(default)]
    pub load: crate::config::fragmentation::Load,
    /// The load's total over the bed's cross-section, Pa (default 1e4).
    #[serde(default = "default_agitation_stress")]
    pub stress: Real,
    /// Tangential over normal spring stiffness (default 1).
    #[serde(default = "default_kt_over_kn")]
    pub kt_over_kn: Real,
    /// The most bridges broken (each break re-solves the bed; default 10000).
    #[serde(default = "default_max_breaks")]
    pub max_breaks: u64,
}

/// The default agitation: 10 kPa, the weight of about a metre of dried
/// cake (bulk density ~1,000 kg/m³) that an agitated dryer's blade turns.
pub const DEFAULT_AGITATION_STRESS: Real = 1e4;

fn default_agitation_stress() -> Real {
    DEFAULT_AGITATION_STRESS
}

fn default_kt_over_kn() -> Real {
    1.0
}

fn default_max_breaks() -> u64 {
    10_000
}

impl Default for AgitationConfig {
    fn default() -> Self {
        AgitationConfig {
            load: Default::default(),
            stress: DEFAULT_AGITATION_STRESS,
            kt_over_kn: 1.0,
            max_breaks: default_max_breaks(),
        }
    }
}

impl AgitationConfig {
    /// What is wrong with the agitation's settings, in one line.
    pub(crate) fn problem(&self) -> Option<String> {
        if !(self.stress.is_finite() && self.stress >= 0.0) {
            return Some(format!(
                "drying.agitation.stress (Pa) must be finite and at least 0, got {}",
                self.stress
            ));
        }
        if !(self.kt_over_kn.is_finite() && self.kt_over_kn >= 0.0) {
            return Some(format!(
                "drying.agitation.kt_over_kn must be finite and at least 0, got {}",
                self.kt_over_kn
            ));
        }
        None
    }
}

/// The default liquid's solute: a mother liquor saturated at 50 kg/m³.
pub const DEFAULT_CONCENTRATION: Real = 50.0;
/// The density of organic crystals (1.2–1.6 g/cm³): 1,500 kg/m³.
pub const DEFAULT_CRYSTAL_DENSITY: Real = 1500.0;
/// A bond's smallest neck: 5 % of the pair's harmonic mean radius.
pub const DEFAULT_MIN_NECK: Real = 0.05;
/// Rock salt's practical breaking stress, 0.4 kgf/mm² (about 4 MPa).
pub const DEFAULT_TENSILE_STRENGTH: Real = 3.9e6;

fn default_concentration() -> Real {
    DEFAULT_CONCENTRATION
}

fn default_crystal_density() -> Real {
    DEFAULT_CRYSTAL_DENSITY
}

fn default_min_neck() -> Real {
    DEFAULT_MIN_NECK
}

fn default_tensile_strength() -> Real {
    DEFAULT_TENSILE_STRENGTH
}

/// What is wrong with a drying's settings (concentration and solubility in
/// kg/m³, crystal density in kg/m³, the smallest bond neck, the tensile
/// strength in Pa), in one line; `None` when nothing is.
pub fn drying_problem(
    concentration: Real,
    solubility: Real,
    crystal_density: Real,
    min_neck: Real,
    tensile_strength: Real,
) -> Option<String> {
    let nonneg = |x: Real, name: &str| {
        (!(x.is_finite() && x >= 0.0))
            .then(|| format!("drying: {name} must be finite and at least 0, got {x}"))
    };
    nonneg(concentration, "concentration (kg/m³)")
        .or_else(|| {
            (!(crystal_density.is_finite() && crystal_density > 0.0)).then(|| {
                format!(
                    "drying: crystal_density (kg/m³) must be finite and positive, got {crystal_density}"
                )
            })
        })
        .or_else(|| nonneg(min_neck, "min_neck"))
        .or_else(|| nonneg(tensile_strength, "tensile_strength (Pa)"))
        .or_else(|| {
            // NaN is refused too: `> 0` is false for it.
            (solubility.is_nan() || solubility <= 0.0)
                .then(|| format!("drying: solubility (kg/m³) must be positive, got {solubility}"))
        })
        .or_else(|| {
            (concentration > solubility).then(|| {
                format!(
                    "drying: the concentration {concentration} kg/m³ is above the solubility \
                     {solubility} kg/m³ (a liquid cannot hold more than it dissolves): lower the \
                     concentration or raise the solubility"
                )
            })
        })
}

impl Default for DryingConfig {
    fn default() -> Self {
        DryingConfig {
            concentration: default_concentration(),
            solubility: None,
            crystal_density: default_crystal_density(),
            min_neck: default_min_neck(),
            tensile_strength: default_tensile_strength(),
            agitation: None,
        }
    }
}

impl DryingConfig {
    /// True when nothing is set.
    pub(crate) fn is_default(&self) -> bool {
        *self == DryingConfig::default()
    }

    /// The solubility the drying uses: the one given, else the
    /// concentration (a saturated liquid), `+∞` for a liquid with nothing
    /// dissolved (no solubility to reach).
    pub(crate) fn solubility_or_default(&self) -> Real {
        self.solubility.unwrap_or(if self.concentration > 0.0 {
            self.concentration
        } else {
            Real::INFINITY
        })
    }

    fn check(&self) -> Result<()> {
        match drying_problem(
            self.concentration,
            self.solubility_or_default(),
            self.crystal_density,
            self.min_neck,
            self.tensile_strength,
        )
        .or_else(|| self.agitation.as_ref().and_then(AgitationConfig::problem))
        {
            Some(why) => Err(Error::config(format!("analysis.{why}"))),
            None => Ok(()),
        }
    }
}

/// `[analysis.drainage]`: the liquid, its wetting and the pressure the
/// liquid left in the cake is reported at. The defaults are water on clean
/// glass at 20 °C.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrainageConfig {
    /// Surface tension of the liquid, N/m (default 0.0728, water).
    #[serde(default = "default_surface_tension")]
    pub surface_tension: Real,
    /// Contact angle of the liquid on the particles, degrees, in [0, 90)
    /// (default 0).
    #[serde(default)]
    pub contact_angle: Real,
    /// Liquid cut off from the outlet stays in the cake (default true);
    /// false: it leaves through films, the bound the literature compares.
    #[serde(default = "default_true")]
    pub trapping: bool,
    /// The throats' entry-pressure model: `msp` (default) or `inscribed`.
    #[serde(default)]
    pub entry: EntryModel,
    /// Where the liquid is reported (`liquid.csv`, the residual
    /// saturation): at this capillary pressure, in Pa (needs
    /// `[analysis] length_unit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<Real>,
    /// The same as `P_c·d32/γ` (default: twice the breakthrough pressure).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reduced_pressure: Option<Real>,
    /// Rows of the capillary pressure–saturation curve (default 60).
    #[serde(default = "default_points")]
    pub points: usize,
    /// Relative permeabilities of both phases on every 6th row of the curve
    /// (with the permeability measure; default false: two solves of the flow
    /// a row).
    #[serde(default)]
    pub relative_permeability: bool,
}

/// How a throat's capillary entry pressure follows from its shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EntryModel {
    /// Mayer–Stowe–Princen: the force balance of the throat's section,
    /// the liquid left in its corners counted.
    #[default]
    Msp,
    /// Haines: the inscribed circle of the constriction, `2γ cos θ / r_c`.
    Inscribed,
}

impl EntryModel {
    /// The name in configs and summaries.
    pub(crate) fn name(self) -> &'static str {
        match self {
            EntryModel::Msp => "msp",
            EntryModel::Inscribed => "inscribed",
        }
    }
}

fn default_surface_tension() -> Real {
    0.0728
}

fn default_true() -> bool {
    true
}

fn default_points() -> usize {
    60
}

impl Default for DrainageConfig {
    fn default() -> Self {
        DrainageConfig {
            surface_tension: default_surface_tension(),
            contact_angle: 0.0,
            trapping: true,
            entry: EntryModel::default(),
            pressure: None,
            reduced_pressure: None,
            points: default_points(),
            relative_permeability: false,
        }
    }
}

impl DrainageConfig {
    /// True when nothing is set.
    pub(crate) fn is_default(&self) -> bool {
        *self == DrainageConfig::default()
    }

    fn check(&self, length_unit: Option<LengthUnit>) -> Result<()> {
        if !(self.surface_tension.is_finite() && self.surface_tension > 0.0) {
            return Err(Error::config(format!(
                "analysis.drainage.surface_tension must be a positive number of N/m, got {}",
                self.surface_tension
            )));
        }
        let theta = self.contact_angle;
        if !(theta.is_finite() && theta >= 0.0) {
            return Err(Error::config(format!(
                "analysis.drainage.contact_angle must be in [0, 90) degrees, got {theta}"
            )));
        }
        if theta >= 90.0 {
            return Err(Error::config(format!(
                "analysis.drainage.contact_angle {theta} degrees: at 90 or more the liquid does \
                 not wet the particles, and gas displacing it is not a drainage"
            )));
        }
        if let Some(p) = self.pressure {
            positive(p, "analysis.drainage.pressure")?;
            if length_unit.is_none() {
                return Err(Error::config(
                    "analysis.drainage.pressure (Pa) needs analysis.length_unit, the length of \
                     one unit of the bed; or give analysis.drainage.reduced_pressure (P_c d32 / \
                     surface tension)",
                ));
            }
        }
        if let Some(p) = self.reduced_pressure {
            positive(p, "analysis.drainage.reduced_pressure")?;
        }
        if self.pressure.is_some() && self.reduced_pressure.is_some() {
            return Err(Error::config(
                "analysis.drainage: give pressure or reduced_pressure, not both",
            ));
        }
        if !(2..=100_000).contains(&self.points) {
            return Err(Error::config(format!(
                "analysis.drainage.points must be between 2 and 100000, got {}",
                self.points
            )));
        }
        Ok(())
    }
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
    /// Which length sets a throat's conductance `c · A_f ℓ² / (2 μ L)`: the
    /// constriction radius (default) or the throat region's hydraulic radius
    /// (Chareyre et al.'s model as published).
    #[serde(default)]
    pub conductance: Conductance,
    /// The one constant factor `c` on every throat's conductance (default:
    /// the model's, [`Conductance::default_factor`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductance_factor: Option<Real>,
}

/// The length `ℓ` of a throat's conductance `g = c · A_f ℓ² / (2 μ L)`.
///
/// Chareyre et al.'s hydraulic radius (void volume over solid surface of the
/// throat region) grows with the pore space: on loose beds it overstates `k`
/// twice (2.0–2.1× the correlations on random sequential addition beds at
/// `φ` = 0.38, 3.0× Zick & Homsy's simple cubic array at `φ` = 0.216) while
/// it is 1.28× on deposited beds, so no one factor holds both within 25 %.
/// The constriction radius is what the throat lets through: with one factor
/// fixed on Zick & Homsy's touching array it is within 10 % of their exact
/// Stokes values from `φ` = 0.216 to 0.524 and within 16 % of the
/// correlations on random beds from `φ` = 0.38 to 0.62 (docs/design/conductance.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Conductance {
    /// `ℓ` = the constriction radius of the throat.
    #[default]
    Constriction,
    /// `ℓ` = `R_h` = void volume / solid surface of the throat region
    /// (Chareyre et al. 2012; Yade's flow engine).
    HydraulicRadius,
}

impl Conductance {
    /// The factor `c` fixed once for this model from published Stokes
    /// references, never tuned per bed (`docs/reference/pores.md`, "The conductance"):
    /// - constriction: 0.55 ≈ 1/1.826, the model with `c` = 1 giving 1.826×
    ///   Zick & Homsy's touching simple cubic array (exact Stokes flow);
    /// - hydraulic radius: 0.89 = 1/√(0.979 · 1.29), leaving Zick & Homsy's
    ///   array (0.979× with `c` = 1) and van der Hoef et al.'s random arrays
    ///   at the packing of deposited beds (1.29×) equally far off.
    pub(crate) fn default_factor(self) -> Real {
        match self {
            Conductance::Constriction => 0.55,
            Conductance::HydraulicRadius => 0.89,
        }
    }

    /// The name in configs and summaries.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Conductance::Constriction => "constriction",
            Conductance::HydraulicRadius => "hydraulic_radius",
        }
    }
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
            conductance: Conductance::default(),
            conductance_factor: None,
        }
    }
}

impl FlowConfig {
    /// True when nothing is set, so that configs which do not use it keep
    /// their serialised form.
    pub(crate) fn is_default(&self) -> bool {
        *self == FlowConfig::default()
    }

    fn check(&self) -> Result<()> {
        positive(self.viscosity, "analysis.flow.viscosity")?;
        if let Some(c) = self.conductance_factor {
            positive(c, "analysis.flow.conductance_factor")?;
        }
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
    pub(crate) fn name(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Millimetre => "mm",
            LengthUnit::Micrometre => "um",
            LengthUnit::Nanometre => "nm",
        }
    }

    /// The symbol for axes and legends: `m`, `mm`, `µm`, `nm`.
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Micrometre => "µm",
            u => u.name(),
        }
    }

    /// Metres per unit.
    pub(crate) fn metres(self) -> Real {
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
pub struct Measures(u16);

impl Measures {
    /// Every measure.
    pub fn all() -> Measures {
        Measures::of(&Measure::ALL)
    }

    /// The measures of a run that chooses none: all but the pore space, whose
    /// triangulation and flow solve cost more than the rest together on a
    /// large bed (BENCHMARKS.md) and are asked for by name.
    pub(crate) fn default_set() -> Measures {
        Measures::of(&Measure::DEFAULT)
    }

    /// These measures.
    pub(crate) fn of(list: &[Measure]) -> Measures {
        Measures(list.iter().fold(0, |bits, m| bits | m.bit()))
    }

    /// True when `m` is in the set.
    pub(crate) fn has(self, m: Measure) -> bool {
        self.0 & m.bit() != 0
    }

    /// The names of the default measures not in the set, in summary order
    /// (the measures asked for by name are not "left out" when absent).
    pub(crate) fn left_out(self) -> Vec<&'static str> {
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
    /// `drainage.*`: gas displacing the liquid, and where the liquid stays.
    Drainage,
    /// `agglomeration.*`: the drained cake dried, its solid bridges and
    /// agglomerates (computes the drainage).
    Agglomeration,
}

impl Measure {
    /// Every measure, in the order of `summary.json`.
    pub const ALL: [Measure; 10] = [
        Measure::Packing,
        Measure::Coordination,
        Measure::Percolation,
        Measure::Voids,
        Measure::Orientation,
        Measure::Segregation,
        Measure::Pores,
        Measure::Permeability,
        Measure::Drainage,
        Measure::Agglomeration,
    ];

    /// The measures computed when none are chosen: the first six of [`Measure::ALL`].
    pub const DEFAULT: [Measure; 6] = {
        let a = Measure::ALL;
        [a[0], a[1], a[2], a[3], a[4], a[5]]
    };

    /// The name in configs, options and `summary.json`.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Measure::Packing => "packing",
            Measure::Coordination => "coordination",
            Measure::Percolation => "percolation",
            Measure::Voids => "voids",
            Measure::Orientation => "orientation",
            Measure::Segregation => "segregation",
            Measure::Pores => "pores",
            Measure::Permeability => "permeability",
            Measure::Drainage => "drainage",
            Measure::Agglomeration => "agglomeration",
        }
    }

    fn bit(self) -> u16 {
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
            drainage: DrainageConfig::default(),
            drying: DryingConfig::default(),
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
        self.drainage.check(self.length_unit)?;
        self.drying.check()?;
        // The displaced liquid leaves the drainage's slab downwards (the
        // filter medium): a slab from the floor has nothing below it.
        let drains = self
            .measures
            .as_ref()
            .is_some_and(|m| m.contains(&Measure::Drainage) || m.contains(&Measure::Agglomeration));
        if let (true, Some([lo, _])) = (drains, self.flow.slab) {
            if lo <= 0.0 {
                return Err(Error::config(format!(
                    "analysis.flow.slab starts at {lo}, on the floor: the drainage's liquid leaves \
                     the slab downwards and the bed has no outlet below it; start the slab above \
                     the first layer of particles"
                )));
            }
        }
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
    pub(crate) fn is_vertical(&self) -> bool {
        *self == AngleFrom::Vertical
    }

    /// The name used in configs and in `summary.json`.
    pub(crate) fn name(self) -> &'static str {
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
    pub(crate) fn range(self, d: usize) -> (Real, Real) {
        match (self, d) {
            (AngleFrom::Vertical, 2) => (-90.0, 90.0),
            (AngleFrom::Horizontal, 2) => (0.0, 180.0),
            _ => (0.0, 90.0),
        }
    }
}

fn default_contact_tol() -> Real {
    DEFAULT_CONTACT_TOL
}

/// The contact tolerance of every analysis unless told otherwise: a gap of at
/// most this, relative to the smaller radius, is a contact.
pub const DEFAULT_CONTACT_TOL: Real = 1e-6;

/// Largest contact tolerance, relative to the smaller radius. Beyond it two
/// spheres a radius apart would count as touching, and the contact search, sized
/// by the tolerance, grows with its cube.
pub const MAX_CONTACT_TOL: Real = 1.0;

/// Why the contact tolerance `tol` (named `what`) is refused, if it is.
pub fn contact_tol_problem(tol: Real, what: &str) -> Option<String> {
    // Shortest form: `1e300` is echoed as typed, not as 301 digits.
    let shown = crate::math::display_length(tol);
    if !(tol.is_finite() && tol >= 0.0) {
        Some(format!("{what} must be a non-negative number, got {shown}"))
    } else if tol > MAX_CONTACT_TOL {
        Some(format!(
            "{what} is {shown}, but at most {MAX_CONTACT_TOL}: it is a gap relative to the \
             smaller radius, and a larger gap no longer means touching"
        ))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measure_lists_are_read_by_name_or_all() {
        assert_eq!(
            Measure::parse_list("packing, pores").unwrap(),
            [Measure::Packing, Measure::Pores]
        );
        assert_eq!(Measure::parse_list(" all ").unwrap(), Measure::ALL);
        let e = Measure::parse_list("all,packing").unwrap_err();
        assert!(
            e.contains("give `all` alone") && e.contains("`packing`"),
            "{e}"
        );
        let e = Measure::parse_list("packing,porez").unwrap_err();
        assert!(e.contains("unknown measure `porez`"), "{e}");
        for m in Measure::ALL {
            assert_eq!(Measure::parse_list(m.name()).unwrap(), [m]);
        }
    }

    #[test]
    fn the_default_set_leaves_out_the_pore_space() {
        let d = Measures::default_set();
        assert!(Measure::DEFAULT.iter().all(|&m| d.has(m)));
        assert!(!d.has(Measure::Pores) && !d.has(Measure::Permeability));
        // What is left out is named against the default set.
        assert!(d.left_out().is_empty() && Measures::all().left_out().is_empty());
        let only = Measures::of(&[Measure::Packing, Measure::Pores]);
        assert_eq!(only.left_out().len(), Measure::DEFAULT.len() - 1);
        assert!(!only.left_out().contains(&"packing"));
    }

    #[test]
    fn analysis_settings_are_checked_with_their_names() {
        assert!(AnalysisConfig::default().check().is_ok());
        let bad = AnalysisConfig {
            contact_tol: -1.0,
            ..AnalysisConfig::default()
        };
        let e = bad
            .check_naming(&|s| format!("--{}", s.replace('_', "-")))
            .unwrap_err();
        assert!(e.to_string().contains("contact"), "{e}");
    }

    #[test]
    fn the_conductance_factor_is_read_and_checked() {
        let default = FlowConfig::default();
        assert_eq!(default.conductance, Conductance::Constriction);
        assert_eq!(default.conductance_factor, None);
        let read: FlowConfig = toml::from_str("conductance_factor = 1.0").unwrap();
        assert_eq!(read.conductance_factor, Some(1.0));
        assert!(read.check().is_ok() && !read.is_default());
        let read: FlowConfig = toml::from_str("conductance = \"hydraulic_radius\"").unwrap();
        assert_eq!(read.conductance, Conductance::HydraulicRadius);
        assert!(!read.is_default());
        let e = toml::from_str::<FlowConfig>("conductance = \"tube\"").unwrap_err();
        assert!(e.to_string().contains("constriction"), "{e}");
        for bad in [0.0, -0.5, Real::NAN, Real::INFINITY] {
            let e = FlowConfig {
                conductance_factor: Some(bad),
                ..FlowConfig::default()
            }
            .check()
            .unwrap_err();
            assert!(e.to_string().contains("conductance_factor"), "{e}");
        }
    }
}
