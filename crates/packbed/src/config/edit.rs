//! Editing a config: the one home of the changes that the command's options
//! (`--radii 10,20`), a sweep's values (`parameter = "radii"`) and the Python
//! keywords make to a [`Config`]. They all go through [`Config::apply`], so an
//! option and a sweep of the same setting give the same config.

use super::{Config, Measure, Mode, SweepValue};
use crate::error::{Error, Result};
use crate::math::Real;
use std::path::Path;
use std::str::FromStr;

/// One change to a config. Edits are applied before validation, so every
/// check of the config applies to them too.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// The dimension, 2 or 3.
    Dim(u8),
    /// The seed of the run's random generator.
    Seed(u64),
    /// Deposition or random sequential addition.
    Mode(Mode),
    /// One species per radius. With as many radii as species, each species
    /// keeps its other settings; otherwise the species become copies of the
    /// first one (its shape and beads kept, so a chain config stays chains)
    /// with these radii and ratio 1.
    Radii(Vec<Real>),
    /// The number ratios, one per species.
    Ratio(Vec<Real>),
    /// Every species becomes a rigid chain of this many beads.
    Beads(u32),
    /// The box (its periodic setting is kept).
    Box(BoxSpec),
    /// Periodic side boundaries.
    Periodic(bool),
    /// Place exactly this many particles (the roof is ignored).
    Count(u64),
    /// Roof misses tolerated in total before the fill stops.
    RoofMisses(u64),
    /// Percolation threshold: particles with radius at least this are large.
    LargeRadius(Real),
    /// The radius of one species (0-based).
    SpeciesRadius(usize, Real),
    /// The number ratio of one species (0-based).
    SpeciesRatio(usize, Real),
    /// One setting of a species' size distribution (0-based).
    SpeciesSize(usize, SizeEdit),
    /// The measures to compute (the others are left out of the summary).
    Measures(Vec<Measure>),
    /// One setting of `[analysis.drying]`: a sweep over the solute.
    Drying(DryingEdit),
    /// The capillary pressure `[analysis.drainage]` reports the liquid at,
    /// in Pa; it replaces a `reduced_pressure`.
    DrainagePressure(Real),
    /// The same as `P_c·d32/γ`; it replaces a `pressure`.
    DrainageReducedPressure(Real),
    /// One key of `[settling]`: a sweep over how particles come to rest.
    Settling(SettlingEdit),
    /// One key of `[filtration]`: a sweep over pressures or slurries.
    Filtration(FiltrationEdit),
    /// The bodies of one entry of `[[feeds]]` (0-based): a sweep over a
    /// medium's depth or a slurry's amount.
    FeedCount(usize, u64),
    /// `feeds[K].mass_per_area`: a feed's amount as kg of solids per m².
    FeedMass(usize, Real),
    /// One key of `[compaction]` (the table is added when the config has
    /// none): a sweep from the settled bed toward the compacted one.
    Compaction(CompactionEdit),
}

/// A change to `[compaction]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CompactionEdit {
    /// Most steps (0: the settled bed).
    Steps(u32),
    /// How far a free sphere falls in one step, in mean diameters.
    Step(Real),
    /// The descent, as a share of the step, below which the step is refined.
    Until(Real),
    /// The contacts' friction coefficient.
    Friction(Real),
}

/// A change to `[filtration]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FiltrationEdit {
    /// A constant pressure drop, Pa (it replaces a flow rate).
    Pressure(Real),
    /// A constant flux, m/s (it replaces a pressure).
    FlowRate(Real),
    /// The solids deposited per filtrate volume, kg/m³.
    Concentration(Real),
    /// The filtrate's viscosity, Pa s.
    Viscosity(Real),
}

/// A change to `[settling]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SettlingEdit {
    /// Stop at the k-th contact.
    Contacts(u8),
    /// The probability of sticking at each new contact.
    Sticking(Real),
    /// The friction angle, degrees.
    FrictionAngle(Real),
    /// The diameter at which half the contacts stick.
    CohesionDiameter(Real),
    /// The cohesion law's exponent.
    CohesionExponent(Real),
    /// The restitution of an impact (momentum).
    Restitution(Real),
    /// The fall before the first impact (momentum).
    DropHeight(Real),
    /// The sliding friction coefficient (momentum).
    SlidingFriction(Real),
    /// Whether a blocked climb rolls on over its blocker (momentum).
    ClimbOver(bool),
}

/// A change to `[analysis.drying]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DryingEdit {
    /// The dissolved solid, kg/m³ (a washed cake's liquid is diluted).
    Concentration(Real),
    /// Its solubility, kg/m³.
    Solubility(Real),
    /// A bond's smallest neck, in the pair's harmonic mean radius.
    MinNeck(Real),
    /// The solid's tensile strength, Pa.
    TensileStrength(Real),
    /// The agitation's stress, Pa (an agitation with its other keys at
    /// their defaults when the config has none).
    AgitationStress(Real),
}

/// A change to a species' size distribution: a sweep over distributions.
#[derive(Clone, Debug, PartialEq)]
pub enum SizeEdit {
    /// The median of a lognormal.
    Median(Real),
    /// The geometric standard deviation of a lognormal.
    Gsd(Real),
    /// The mean of a normal.
    Mean(Real),
    /// The standard deviation of a normal.
    Sd(Real),
    /// A PSD table in place of the species' size.
    Table(std::path::PathBuf),
}

/// A box as the command and the sweeps give it: `thesis`, `diameters=N`, or
/// the sizes `W,H` (2D) / `W,D,H` (3D).
#[derive(Clone, Debug, PartialEq)]
pub enum BoxSpec {
    /// The source study's box for the species.
    Thesis,
    /// A cube (square) of this many largest diameters.
    Diameters(Real),
    /// Explicit sizes: `[W, H]` or `[W, D, H]`.
    Size(Vec<Real>),
}

/// `10, 20,30` → numbers; the error names the part that is not a number.
pub fn parse_numbers(text: &str) -> std::result::Result<Vec<Real>, String> {
    text.split(',')
        .map(|f| {
            let f = f.trim();
            f.parse::<Real>()
                .map_err(|_| format!("`{f}` is not a number"))
        })
        .collect()
}

impl FromStr for BoxSpec {
    type Err = String;

    fn from_str(text: &str) -> std::result::Result<BoxSpec, String> {
        let text = text.trim();
        if text == "thesis" {
            return Ok(BoxSpec::Thesis);
        }
        if let Some(n) = text.strip_prefix("diameters=") {
            return match parse_numbers(n)?.as_slice() {
                [d] => Ok(BoxSpec::Diameters(*d)),
                _ => Err(format!("`{text}`: give one number after diameters=")),
            };
        }
        match parse_numbers(text) {
            Ok(v) if (2..=3).contains(&v.len()) => Ok(BoxSpec::Size(v)),
            Ok(v) => Err(format!(
                "`{text}` has {} numbers; give W,H (2D) or W,D,H (3D)",
                v.len()
            )),
            Err(_) => Err(format!("`{text}` is not thesis, W,H, W,D,H or diameters=N")),
        }
    }
}

/// The parameters a sweep can vary, with the form of their values.
pub const SWEEP_PARAMETERS: [(&str, &str); 40] = [
    ("ratio", "a list with one number ratio per species, e.g. [1, 2]"),
    (
        "radii",
        "a list of radii, e.g. [10, 20] (the species' other settings kept when the count matches, else copies of the first species)",
    ),
    ("box.diameters", "a number: a cube (square) of that many largest diameters"),
    ("box.size", "a list [W, H] (2D) or [W, D, H] (3D)"),
    ("fill.count", "a whole number of particles"),
    ("fill.roof_misses", "a whole number"),
    ("analysis.large_radius", "a radius"),
    ("species[K].radius", "a radius for species K (0-based)"),
    ("species[K].ratio", "a number ratio for species K (0-based)"),
    ("species[K].size.median", "the median radius of species K's lognormal"),
    ("species[K].size.gsd", "the geometric standard deviation of species K's lognormal"),
    ("species[K].size.mean", "the mean radius of species K's normal"),
    ("species[K].size.sd", "the standard deviation of species K's normal"),
    (
        "species[K].size.table",
        "a PSD table file for species K, e.g. \"batch-a.csv\" (relative to the config)",
    ),
    (
        "analysis.drying.concentration",
        "the dissolved solid, kg/m³ (a washing sweep dilutes it)",
    ),
    ("analysis.drying.solubility", "the solute's solubility, kg/m³"),
    (
        "analysis.drying.min_neck",
        "a bond's smallest neck, in the pair's harmonic mean radius",
    ),
    ("analysis.drying.tensile_strength", "the solid's tensile strength, Pa"),
    (
        "analysis.drying.agitation.stress",
        "the agitation's stress on the dried cake, Pa",
    ),
    ("settling.contacts", "stop at the k-th contact: 1, 2 or 3"),
    ("settling.sticking", "the probability of sticking at each new contact, 0 to 1"),
    ("settling.friction_angle", "the friction angle in degrees, 0 to 90"),
    (
        "settling.cohesion_diameter",
        "the diameter at which half the contacts stick, a length",
    ),
    (
        "settling.cohesion_exponent",
        "the cohesion law's exponent n, > 0 (needs cohesion_diameter)",
    ),
    (
        "settling.restitution",
        "the restitution of an impact (momentum), 0 to 1",
    ),
    (
        "settling.drop_height",
        "the fall before the first impact (momentum), a length",
    ),
    (
        "settling.sliding_friction",
        "the sliding friction coefficient of the momentum rule, >= 0",
    ),
    (
        "settling.climb_over",
        "true or false: a blocked climb rolls on over its blocker (momentum)",
    ),
    (
        "compaction.steps",
        "a whole number: most compaction steps (0 keeps the settled bed)",
    ),
    (
        "compaction.step",
        "how far a free sphere falls in one compaction step, mean diameters, (0, 0.25]",
    ),
    (
        "compaction.friction",
        "the friction coefficient of the compaction's contacts, 0 to 10",
    ),
    (
        "compaction.until",
        "the compaction's descent, as a share of the step, below which the step is refined",
    ),
    (
        "analysis.drainage.pressure",
        "the deliquoring capillary pressure, Pa (needs analysis.length_unit)",
    ),
    (
        "analysis.drainage.reduced_pressure",
        "the deliquoring pressure as P_c·d32/γ",
    ),
    (
        "filtration.pressure",
        "the filtration's constant pressure drop, Pa (it replaces a flow_rate)",
    ),
    (
        "filtration.flow_rate",
        "the filtration's constant flux, m/s (it replaces a pressure)",
    ),
    (
        "filtration.concentration",
        "the solids deposited per filtrate volume, kg/m³",
    ),
    ("filtration.viscosity", "the filtrate's viscosity, Pa s"),
    (
        "feeds[K].count",
        "a whole number of bodies for feed K (0-based): a medium's depth, a slurry's amount",
    ),
    (
        "feeds[K].mass_per_area",
        "feed K's amount as kg of solids per m² of filter (it replaces its count)",
    ),
];

/// `feeds[K].key` → (K, key).
pub(crate) fn feed_parameter(p: &str) -> Option<(usize, &str)> {
    let rest = p.strip_prefix("feeds[")?;
    let (k, key) = rest.split_once("].")?;
    Some((k.parse().ok()?, key))
}

/// `species[K].key` → (K, key).
pub(crate) fn species_parameter(p: &str) -> Option<(usize, &str)> {
    let rest = p.strip_prefix("species[")?;
    let (k, key) = rest.split_once("].")?;
    Some((k.parse().ok()?, key))
}

impl Edit {
    /// The edit that sets a sweep `parameter` (one of `SWEEP_PARAMETERS`) to
    /// `value`.
    pub(crate) fn from_sweep(
        parameter: &str,
        value: &SweepValue,
    ) -> std::result::Result<Edit, String> {
        if let (SweepValue::Text(t), false) = (value, parameter.ends_with(".size.table")) {
            return Err(format!("expected a number, got the text \"{t}\""));
        }
        if parameter == "settling.climb_over" {
            return match value {
                SweepValue::Flag(b) => Ok(Edit::Settling(SettlingEdit::ClimbOver(*b))),
                _ => Err("expected true or false".into()),
            };
        }
        if let SweepValue::Flag(b) = value {
            return Err(format!("expected a number, got {b}"));
        }
        let list = || match value {
            SweepValue::Number(x) => vec![*x],
            SweepValue::List(v) => v.clone(),
            SweepValue::Text(_) | SweepValue::Flag(_) => Vec::new(),
        };
        let one = || match value {
            SweepValue::Number(x) => Ok(*x),
            SweepValue::List(v) if v.len() == 1 => Ok(v[0]),
            SweepValue::List(v) => Err(format!("expected one number, got a list of {}", v.len())),
            SweepValue::Text(t) => Err(format!("expected a number, got the text \"{t}\"")),
            SweepValue::Flag(b) => Err(format!("expected a number, got {b}")),
        };
        Ok(match parameter {
            "ratio" => Edit::Ratio(list()),
            "radii" => Edit::Radii(list()),
            "box.diameters" => Edit::Box(BoxSpec::Diameters(one()?)),
            "box.size" => match list() {
                v if (2..=3).contains(&v.len()) => Edit::Box(BoxSpec::Size(v)),
                v => return Err(format!("give [W, H] or, in 3D, [W, D, H]; got {v:?}")),
            },
            "fill.count" => Edit::Count(whole(one()?)?),
            "fill.roof_misses" => Edit::RoofMisses(whole(one()?)?),
            "analysis.large_radius" => Edit::LargeRadius(one()?),
            "analysis.drying.concentration" => Edit::Drying(DryingEdit::Concentration(one()?)),
            "analysis.drying.solubility" => Edit::Drying(DryingEdit::Solubility(one()?)),
            "analysis.drying.min_neck" => Edit::Drying(DryingEdit::MinNeck(one()?)),
            "analysis.drying.agitation.stress" => {
                Edit::Drying(DryingEdit::AgitationStress(one()?))
            }
            "analysis.drying.tensile_strength" => {
                Edit::Drying(DryingEdit::TensileStrength(one()?))
            }
            "settling.contacts" => match whole(one()?)? {
                k @ 1..=3 => Edit::Settling(SettlingEdit::Contacts(k as u8)),
                k => return Err(format!("settling.contacts must be 1, 2 or 3, got {k}")),
            },
            "settling.sticking" => Edit::Settling(SettlingEdit::Sticking(one()?)),
            "settling.friction_angle" => Edit::Settling(SettlingEdit::FrictionAngle(one()?)),
            "settling.cohesion_diameter" => {
                Edit::Settling(SettlingEdit::CohesionDiameter(one()?))
            }
            "settling.cohesion_exponent" => {
                Edit::Settling(SettlingEdit::CohesionExponent(one()?))
            }
            "settling.restitution" => Edit::Settling(SettlingEdit::Restitution(one()?)),
            "settling.drop_height" => Edit::Settling(SettlingEdit::DropHeight(one()?)),
            "settling.sliding_friction" => {
                Edit::Settling(SettlingEdit::SlidingFriction(one()?))
            }
            "compaction.steps" => match whole(one()?)? {
                n if n <= u64::from(u32::MAX) => Edit::Compaction(CompactionEdit::Steps(n as u32)),
                n => return Err(format!("compaction.steps must be at most {}, got {n}", u32::MAX)),
            },
            "compaction.step" => Edit::Compaction(CompactionEdit::Step(one()?)),
            "compaction.until" => Edit::Compaction(CompactionEdit::Until(one()?)),
            "compaction.friction" => Edit::Compaction(CompactionEdit::Friction(one()?)),
            "analysis.drainage.pressure" => Edit::DrainagePressure(one()?),
            "analysis.drainage.reduced_pressure" => Edit::DrainageReducedPressure(one()?),
            "filtration.pressure" => Edit::Filtration(FiltrationEdit::Pressure(one()?)),
            "filtration.flow_rate" => Edit::Filtration(FiltrationEdit::FlowRate(one()?)),
            "filtration.concentration" => {
                Edit::Filtration(FiltrationEdit::Concentration(one()?))
            }
            "filtration.viscosity" => Edit::Filtration(FiltrationEdit::Viscosity(one()?)),
            _ if feed_parameter(parameter).is_some() => match feed_parameter(parameter) {
                Some((k, "count")) => Edit::FeedCount(k, whole(one()?)?),
                Some((k, "mass_per_area")) => Edit::FeedMass(k, one()?),
                _ => {
                    return Err(format!(
                        "{parameter}: a feed sweeps its count or its mass_per_area"
                    ))
                }
            },
            _ => match species_parameter(parameter) {
                Some((k, "radius")) => Edit::SpeciesRadius(k, one()?),
                Some((k, "ratio")) => Edit::SpeciesRatio(k, one()?),
                Some((k, "size.median")) => Edit::SpeciesSize(k, SizeEdit::Median(one()?)),
                Some((k, "size.gsd")) => Edit::SpeciesSize(k, SizeEdit::Gsd(one()?)),
                Some((k, "size.mean")) => Edit::SpeciesSize(k, SizeEdit::Mean(one()?)),
                Some((k, "size.sd")) => Edit::SpeciesSize(k, SizeEdit::Sd(one()?)),
                Some((k, "size.table")) => match value {
                    SweepValue::Text(t) => Edit::SpeciesSize(k, SizeEdit::Table(t.into())),
                    _ => return Err("expected a file name in quotes, e.g. \"psd.csv\"".into()),
                },
                Some(_) => {
                    return Err(format!(
                        "{parameter}: a species sweeps its radius, ratio, or size.median, size.gsd, size.mean, size.sd, size.table"
                    ))
                }
                None => return Err(format!("unknown parameter `{parameter}`")),
            },
        })
    }
}

fn whole(x: Real) -> std::result::Result<u64, String> {
    if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < 2f64.powi(63) {
        Ok(x as u64)
    } else {
        Err(format!("expected a whole number, got {x}"))
    }
}

impl Config {
    /// Applies one edit. The config is left unchanged when the edit cannot
    /// apply (a ratio list of the wrong length, box sizes of another
    /// dimension); the error names the setting, never a command-line option.
    pub fn apply(&mut self, edit: &Edit) -> Result<()> {
        match edit {
            Edit::Dim(d) => self.dim = *d,
            Edit::Seed(s) => self.seed = *s,
            Edit::Mode(m) => self.mode = *m,
            Edit::Radii(radii) => self.set_radii(radii)?,
            Edit::Ratio(ratios) => {
                if ratios.len() != self.species.len() {
                    return Err(Error::config(format!(
                        "{} values but there are {} species: give one ratio per species",
                        ratios.len(),
                        self.species.len()
                    )));
                }
                for (s, &r) in self.species.iter_mut().zip(ratios) {
                    s.ratio = r;
                }
            }
            Edit::Beads(n) => {
                for s in &mut self.species {
                    s.shape = "chain".into();
                    s.beads = Some(*n);
                }
            }
            Edit::Box(spec) => self.set_box(spec)?,
            Edit::Periodic(p) => self.container.periodic = *p,
            Edit::Count(n) => {
                self.fill.count = Some(*n);
                self.fill.until = None;
            }
            Edit::RoofMisses(n) => self.fill.roof_misses = *n,
            Edit::LargeRadius(r) => self.analysis.large_radius = Some(*r),
            Edit::SpeciesRadius(k, r) => {
                let s = self.species_mut(*k)?;
                s.radius = Some(*r);
                s.size = None;
            }
            Edit::SpeciesRatio(k, r) => self.species_mut(*k)?.ratio = *r,
            Edit::SpeciesSize(k, e) => {
                let s = self.species_mut(*k)?;
                if let SizeEdit::Table(t) = e {
                    s.radius = None;
                    let within = s.size.as_ref().and_then(|z| z.within.clone());
                    let pan_min = s.size.as_ref().and_then(|z| z.pan_min);
                    s.size = Some(super::SizeConfig {
                        table: Some(t.clone()),
                        within,
                        pan_min,
                        ..Default::default()
                    });
                    return Ok(());
                }
                let Some(size) = s.size.as_mut().filter(|z| z.dist.is_some()) else {
                    return Err(Error::config(format!(
                        "species[{k}] has no size distribution (`size = {{ dist = ... }}`) to change"
                    )));
                };
                match e {
                    SizeEdit::Median(x) => size.median = Some(*x),
                    SizeEdit::Gsd(x) => size.gsd = Some(*x),
                    SizeEdit::Mean(x) => size.mean = Some(*x),
                    SizeEdit::Sd(x) => size.sd = Some(*x),
                    SizeEdit::Table(_) => {}
                }
            }
            Edit::Measures(m) => self.analysis.measures = Some(m.clone()),
            Edit::Drying(e) => {
                let d = &mut self.analysis.drying;
                match *e {
                    DryingEdit::Concentration(x) => d.concentration = x,
                    DryingEdit::Solubility(x) => d.solubility = Some(x),
                    DryingEdit::MinNeck(x) => d.min_neck = x,
                    DryingEdit::TensileStrength(x) => d.tensile_strength = x,
                    DryingEdit::AgitationStress(x) => {
                        d.agitation.get_or_insert_with(Default::default).stress = x
                    }
                }
            }
            Edit::DrainagePressure(p) => {
                let d = &mut self.analysis.drainage;
                (d.pressure, d.reduced_pressure) = (Some(*p), None);
            }
            Edit::DrainageReducedPressure(p) => {
                let d = &mut self.analysis.drainage;
                (d.pressure, d.reduced_pressure) = (None, Some(*p));
            }
            Edit::Filtration(e) => {
                let Some(f) = self.filtration.as_mut() else {
                    return Err(Error::config(
                        "the config has no [filtration] table to change",
                    ));
                };
                match *e {
                    FiltrationEdit::Pressure(p) => (f.pressure, f.flow_rate) = (Some(p), None),
                    FiltrationEdit::FlowRate(q) => (f.pressure, f.flow_rate) = (None, Some(q)),
                    FiltrationEdit::Concentration(c) => f.concentration = c,
                    FiltrationEdit::Viscosity(v) => f.viscosity = v,
                }
            }
            Edit::FeedCount(k, n) => {
                let feeds = self.feeds.len();
                let Some(f) = self.feeds.get_mut(*k) else {
                    return Err(Error::config(format!(
                        "the config has {feeds} [[feeds]] entries, no feeds[{k}]"
                    )));
                };
                (f.count, f.mass_per_area) = (*n, None);
            }
            Edit::FeedMass(k, m) => {
                let feeds = self.feeds.len();
                let Some(f) = self.feeds.get_mut(*k) else {
                    return Err(Error::config(format!(
                        "the config has {feeds} [[feeds]] entries, no feeds[{k}]"
                    )));
                };
                (f.count, f.mass_per_area) = (0, Some(*m));
            }
            Edit::Settling(e) => {
                let s = &mut self.settling;
                match *e {
                    SettlingEdit::Contacts(k) => s.contacts = Some(k),
                    SettlingEdit::Sticking(p) => s.sticking = Some(p),
                    SettlingEdit::CohesionDiameter(d) => s.cohesion_diameter = Some(d),
                    SettlingEdit::CohesionExponent(n) => s.cohesion_exponent = Some(n),
                    SettlingEdit::FrictionAngle(a) => s.friction_angle = Some(a),
                    SettlingEdit::Restitution(e) => s.restitution = Some(e),
                    SettlingEdit::DropHeight(h) => s.drop_height = Some(h),
                    SettlingEdit::SlidingFriction(mu) => s.sliding_friction = Some(mu),
                    SettlingEdit::ClimbOver(b) => s.climb_over = Some(b),
                }
            }
            Edit::Compaction(e) => {
                let c = self.compaction.get_or_insert_with(Default::default);
                match *e {
                    CompactionEdit::Steps(n) => c.steps = Some(n),
                    CompactionEdit::Step(x) => c.step = Some(x),
                    CompactionEdit::Until(x) => c.until = Some(x),
                    CompactionEdit::Friction(x) => c.friction = Some(x),
                }
            }
        }
        Ok(())
    }

    fn species_mut(&mut self, k: usize) -> Result<&mut super::SpeciesConfig> {
        let n = self.species.len();
        self.species
            .get_mut(k)
            .ok_or_else(|| Error::config(format!("the config has only {n} species")))
    }

    fn set_radii(&mut self, radii: &[Real]) -> Result<()> {
        if radii.is_empty() {
            return Err(Error::config("give at least one radius"));
        }
        if radii.len() == self.species.len() {
            for (s, &r) in self.species.iter_mut().zip(radii) {
                s.radius = Some(r);
                s.size = None;
            }
            return Ok(());
        }
        let template = self.species[0].clone();
        self.species = radii
            .iter()
            .map(|&r| super::SpeciesConfig {
                name: None,
                radius: Some(r),
                size: None,
                ratio: 1.0,
                ..template.clone()
            })
            .collect();
        Ok(())
    }

    fn set_box(&mut self, spec: &BoxSpec) -> Result<()> {
        let mut b = super::BoxConfig {
            periodic: self.container.periodic,
            ..Default::default()
        };
        match spec {
            BoxSpec::Thesis => b.preset = Some("thesis".into()),
            BoxSpec::Diameters(n) => b.diameters = Some(*n),
            BoxSpec::Size(v) => match (v.as_slice(), self.dim) {
                ([w, h], _) => (b.width, b.height) = (Some(*w), Some(*h)),
                ([w, d, h], 3) => {
                    (b.width, b.depth, b.height) = (Some(*w), Some(*d), Some(*h));
                }
                ([_, _, _], dim) => {
                    return Err(Error::config(format!(
                        "W,D,H is for dim 3, but dim is {dim}: give W,H"
                    )))
                }
                _ => {
                    return Err(Error::config(format!(
                        "{} sizes; give W,H (2D) or W,D,H (3D)",
                        v.len()
                    )))
                }
            },
        }
        self.container = b;
        Ok(())
    }
}

/// The common settings a caller may override on top of a config file (the
/// options of `packbed run`, the keywords of `packbed.deposit`), applied in a
/// fixed order: dimension, seed, mode, radii, ratio, beads, box, periodic,
/// count, large radius, measures. With the `cli` feature these are the
/// command's options, their documentation its help.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct Overrides {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[cfg_attr(feature = "cli", arg(long, value_parser = clap::value_parser!(u8).range(2..=3)))]
    pub dim: Option<u8>,
    /// Radii of the species, e.g. 10,20 (one species per radius).
    #[cfg_attr(feature = "cli", arg(long, value_name = "R,R,...", allow_hyphen_values = true, value_parser = parse_numbers))]
    pub radii: Option<Numbers>,
    /// Number ratios of the species, e.g. 1,2 (one per species).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N,N,...", allow_hyphen_values = true, value_parser = parse_numbers))]
    pub ratio: Option<Numbers>,
    /// Make every species a rigid chain of N beads.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "N", allow_negative_numbers = true)
    )]
    pub beads: Option<u32>,
    /// Box: thesis | W,H | W,D,H | diameters=N.
    #[cfg_attr(
        feature = "cli",
        arg(long = "box", value_name = "BOX", allow_hyphen_values = true)
    )]
    pub container: Option<BoxSpec>,
    /// Periodic side boundaries (no side walls).
    #[cfg_attr(feature = "cli", arg(long))]
    pub periodic: bool,
    /// Place exactly N particles (the roof is ignored).
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "N", allow_negative_numbers = true)
    )]
    pub count: Option<u64>,
    /// Seed of the random generator.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "S", allow_negative_numbers = true)
    )]
    pub seed: Option<u64>,
    /// deposit (drop and roll) or rsa (random sequential addition).
    #[cfg_attr(feature = "cli", arg(long, value_parser = named::<Mode>(&["deposit", "rsa"])))]
    pub mode: Option<Mode>,
    /// Percolation threshold: particles with radius >= R count as large.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "R", allow_hyphen_values = true)
    )]
    pub large: Option<Real>,
    /// Measures to compute, e.g. packing,coordination (default: packing,
    /// coordination, percolation, voids, orientation, segregation; add pores
    /// and permeability for the pore space, or all).
    #[cfg_attr(feature = "cli", arg(long, value_name = "LIST", value_parser = Measure::parse_list))]
    pub measures: Option<MeasureList>,
}

/// One of `names`, spelt as in a config file (`um`) and read as a config
/// file is read, for an option (whose help lists `names`).
#[cfg(feature = "cli")]
pub fn named<T>(names: &'static [&'static str]) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: serde::de::DeserializeOwned + Clone + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser;
    use serde::de::value::{Error, StrDeserializer};
    clap::builder::PossibleValuesParser::new(names).try_map(|s: String| {
        T::deserialize(StrDeserializer::<Error>::new(&s)).map_err(|e| e.to_string())
    })
}

/// A comma-separated list of numbers, one setting (an alias, so that an
/// argument parser takes it as one value and not as a repeated option).
pub type Numbers = Vec<Real>;

/// A comma-separated list of measures, one setting (an alias, as [`Numbers`]).
pub type MeasureList = Vec<Measure>;

impl Overrides {
    /// True when nothing is overridden.
    pub fn is_empty(&self) -> bool {
        self.edits().is_empty()
    }

    /// The edits, each with the name of its setting, in the order they apply.
    pub fn edits(&self) -> Vec<(&'static str, Edit)> {
        let mut e = Vec::new();
        let mut push = |name, edit: Option<Edit>| {
            if let Some(edit) = edit {
                e.push((name, edit));
            }
        };
        push("dim", self.dim.map(Edit::Dim));
        push("seed", self.seed.map(Edit::Seed));
        push("mode", self.mode.map(Edit::Mode));
        push("radii", self.radii.clone().map(Edit::Radii));
        push("ratio", self.ratio.clone().map(Edit::Ratio));
        push("beads", self.beads.map(Edit::Beads));
        push("box", self.container.clone().map(Edit::Box));
        push("periodic", self.periodic.then_some(Edit::Periodic(true)));
        push("count", self.count.map(Edit::Count));
        push("large", self.large.map(Edit::LargeRadius));
        push("measures", self.measures.clone().map(Edit::Measures));
        e
    }

    /// Applies every override to `config`; an error is the setting's
    /// ([`Error::Setting`]), so that each caller names it its own way (the
    /// command `--radii`, Python `radii`).
    pub fn apply(&self, config: &mut Config) -> Result<()> {
        for (name, edit) in self.edits() {
            config.apply(&edit).map_err(|e| match e {
                Error::Config(message) => Error::setting(name, message),
                other => other,
            })?;
        }
        Ok(())
    }

    /// The config file at `path` (the default bed without one) with these
    /// overrides applied; not validated.
    pub fn applied_to_file(&self, path: Option<&Path>) -> Result<Config> {
        let mut config = match path {
            Some(path) => Config::from_file(path)?,
            None => Config::default(),
        };
        self.apply(&mut config)?;
        Ok(config)
    }

    /// Where the settings came from (the file at `path`, these overrides),
    /// to say where to look when they are wrong.
    pub fn source(&self, path: Option<&Path>) -> String {
        let file = path.map(|p| p.display().to_string());
        match (file, self.is_empty()) {
            (Some(f), true) => f,
            (Some(f), false) => format!("{f} with command-line options"),
            (None, false) => "command-line options".into(),
            (None, true) => "default config".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_source_names_the_file_and_the_overrides() {
        let none = Overrides::default();
        let seed = Overrides {
            seed: Some(3),
            ..Overrides::default()
        };
        let file = Path::new("bed.toml");
        assert_eq!(none.source(Some(file)), "bed.toml");
        assert_eq!(
            seed.source(Some(file)),
            "bed.toml with command-line options"
        );
        assert_eq!(seed.source(None), "command-line options");
        assert_eq!(none.source(None), "default config");
        assert_eq!(seed.applied_to_file(None).unwrap().seed, 3);
    }

    fn edited(edits: &[Edit]) -> Result<Config> {
        let mut c = Config::default();
        for e in edits {
            c.apply(e)?;
        }
        Ok(c)
    }

    #[test]
    fn radii_and_ratio() {
        let c = edited(&[
            Edit::Radii(vec![5.0, 7.0, 9.0]),
            Edit::Ratio(vec![1.0, 2.0, 3.0]),
        ])
        .unwrap();
        let r: Vec<_> = c.species.iter().map(|s| (s.radius, s.ratio)).collect();
        assert_eq!(r, [(Some(5.0), 1.0), (Some(7.0), 2.0), (Some(9.0), 3.0)]);
        c.plan::<3>().unwrap();
    }

    #[test]
    fn a_ratio_list_of_the_wrong_length_is_refused_and_changes_nothing() {
        let mut c = Config::default();
        let e = c.apply(&Edit::Ratio(vec![1.0, 2.0, 3.0])).unwrap_err();
        assert!(
            e.to_string().contains("3 values but there are 2 species"),
            "{e}"
        );
        assert_eq!(c.species[0].ratio, 1.0);
    }

    #[test]
    fn radii_of_a_chain_config_stay_chains_from_options_and_sweeps_alike() {
        let mut base = Config::default();
        base.apply(&Edit::Beads(3)).unwrap();
        let by_option = {
            let mut c = base.clone();
            Overrides {
                radii: Some(vec![10.0, 20.0, 30.0]),
                ..Default::default()
            }
            .apply(&mut c)
            .unwrap();
            c
        };
        let by_sweep = {
            let mut c = base.clone();
            let value = SweepValue::List(vec![10.0, 20.0, 30.0]);
            c.apply(&Edit::from_sweep("radii", &value).unwrap())
                .unwrap();
            c
        };
        for c in [&by_option, &by_sweep] {
            assert_eq!(c.species.len(), 3);
            assert!(c
                .species
                .iter()
                .all(|s| s.shape == "chain" && s.beads == Some(3)));
        }
        assert_eq!(
            toml::to_string(&by_option).unwrap(),
            toml::to_string(&by_sweep).unwrap()
        );
    }

    #[test]
    fn boxes() {
        let c = edited(&[
            Edit::Box("100,200,300".parse().unwrap()),
            Edit::Periodic(true),
        ])
        .unwrap();
        let b = &c.container;
        assert_eq!(
            (b.width, b.depth, b.height),
            (Some(100.0), Some(200.0), Some(300.0))
        );
        assert!(b.periodic);
        // A new box keeps the periodic setting.
        let mut c = c;
        c.apply(&Edit::Box("diameters=10".parse().unwrap()))
            .unwrap();
        assert_eq!(
            (c.container.diameters, c.container.periodic),
            (Some(10.0), true)
        );
        assert_eq!(c.container.width, None);
        let e = edited(&[Edit::Dim(2), Edit::Box(BoxSpec::Size(vec![1.0, 2.0, 3.0]))]).unwrap_err();
        assert!(e.to_string().contains("dim 3"), "{e}");
        assert!("big".parse::<BoxSpec>().unwrap_err().contains("`big`"));
        assert!("1,2,3,4"
            .parse::<BoxSpec>()
            .unwrap_err()
            .contains("4 numbers"));
    }

    #[test]
    fn count_replaces_roof() {
        let mut c = Config::default();
        c.fill.until = Some("roof".into());
        c.apply(&Edit::Count(50)).unwrap();
        assert_eq!((c.fill.until, c.fill.count), (None, Some(50)));
    }

    #[test]
    fn override_errors_name_the_setting_not_an_option() {
        let mut c = Config::default();
        let e = Overrides {
            ratio: Some(vec![1.0]),
            ..Default::default()
        }
        .apply(&mut c)
        .unwrap_err()
        .message();
        assert!(e.starts_with("ratio: "), "{e}");
        assert!(!e.contains("--"), "{e}");
    }

    #[test]
    fn sweep_parameters_map_to_edits() {
        let n = SweepValue::Number(4.0);
        assert_eq!(Edit::from_sweep("fill.count", &n), Ok(Edit::Count(4)));
        assert_eq!(
            Edit::from_sweep("species[1].radius", &n),
            Ok(Edit::SpeciesRadius(1, 4.0))
        );
        assert!(Edit::from_sweep("fill.count", &SweepValue::Number(2.5)).is_err());
        assert!(Edit::from_sweep("species[0].shape", &n).is_err());
        let mut c = Config::default();
        let e = c.apply(&Edit::SpeciesRatio(5, 1.0)).unwrap_err();
        assert!(e.to_string().contains("only 2 species"), "{e}");
    }

    #[test]
    fn filtration_and_feed_sweeps_edit_their_keys() {
        let n = SweepValue::Number(2e5);
        assert_eq!(
            Edit::from_sweep("filtration.pressure", &n),
            Ok(Edit::Filtration(FiltrationEdit::Pressure(2e5)))
        );
        assert_eq!(
            Edit::from_sweep("feeds[1].count", &SweepValue::Number(60.0)),
            Ok(Edit::FeedCount(1, 60))
        );
        assert!(Edit::from_sweep("feeds[0].count", &SweepValue::Number(1.5)).is_err());
        for p in [
            "filtration.pressure",
            "filtration.flow_rate",
            "feeds[K].count",
        ] {
            assert!(SWEEP_PARAMETERS.iter().any(|(q, _)| *q == p), "{p}");
        }
        let mut c = Config::default();
        let e = c
            .apply(&Edit::Filtration(FiltrationEdit::Pressure(1e5)))
            .unwrap_err();
        assert!(e.to_string().contains("no [filtration] table"), "{e}");
        c.filtration = Some(crate::config::FiltrationConfig {
            pressure: None,
            flow_rate: Some(1e-4),
            viscosity: 1e-3,
            concentration: 100.0,
            checkpoints: 20,
            stop: None,
        });
        // A pressure replaces a flow rate, and the other way round.
        c.apply(&Edit::Filtration(FiltrationEdit::Pressure(3e5)))
            .unwrap();
        let f = c.filtration.as_ref().unwrap();
        assert_eq!((f.pressure, f.flow_rate), (Some(3e5), None));
        c.apply(&Edit::Filtration(FiltrationEdit::FlowRate(2e-4)))
            .unwrap();
        let f = c.filtration.as_ref().unwrap();
        assert_eq!((f.pressure, f.flow_rate), (None, Some(2e-4)));
        let e = c.apply(&Edit::FeedCount(0, 10)).unwrap_err();
        assert!(e.to_string().contains("no feeds[0]"), "{e}");
        // A mass replaces a count, and the other way round.
        assert_eq!(
            Edit::from_sweep("feeds[1].mass_per_area", &SweepValue::Number(0.5)),
            Ok(Edit::FeedMass(1, 0.5))
        );
        c.feeds = vec![crate::config::FeedStageConfig {
            count: 10,
            ..Default::default()
        }];
        c.apply(&Edit::FeedMass(0, 0.5)).unwrap();
        assert_eq!((c.feeds[0].count, c.feeds[0].mass_per_area), (0, Some(0.5)));
        c.apply(&Edit::FeedCount(0, 7)).unwrap();
        assert_eq!((c.feeds[0].count, c.feeds[0].mass_per_area), (7, None));
    }
    #[test]
    fn drying_and_drainage_parameters_map_to_edits() {
        let n = SweepValue::Number(5.0);
        let cases = [
            (
                "analysis.drying.concentration",
                Edit::Drying(DryingEdit::Concentration(5.0)),
            ),
            (
                "analysis.drying.solubility",
                Edit::Drying(DryingEdit::Solubility(5.0)),
            ),
            (
                "analysis.drying.min_neck",
                Edit::Drying(DryingEdit::MinNeck(5.0)),
            ),
            (
                "analysis.drying.tensile_strength",
                Edit::Drying(DryingEdit::TensileStrength(5.0)),
            ),
            (
                "analysis.drying.agitation.stress",
                Edit::Drying(DryingEdit::AgitationStress(5.0)),
            ),
            ("analysis.drainage.pressure", Edit::DrainagePressure(5.0)),
            (
                "analysis.drainage.reduced_pressure",
                Edit::DrainageReducedPressure(5.0),
            ),
            (
                "settling.sticking",
                Edit::Settling(SettlingEdit::Sticking(5.0)),
            ),
            (
                "settling.friction_angle",
                Edit::Settling(SettlingEdit::FrictionAngle(5.0)),
            ),
            (
                "settling.cohesion_diameter",
                Edit::Settling(SettlingEdit::CohesionDiameter(5.0)),
            ),
            (
                "settling.cohesion_exponent",
                Edit::Settling(SettlingEdit::CohesionExponent(5.0)),
            ),
            (
                "settling.restitution",
                Edit::Settling(SettlingEdit::Restitution(5.0)),
            ),
            (
                "settling.drop_height",
                Edit::Settling(SettlingEdit::DropHeight(5.0)),
            ),
            (
                "settling.sliding_friction",
                Edit::Settling(SettlingEdit::SlidingFriction(5.0)),
            ),
            (
                "compaction.steps",
                Edit::Compaction(CompactionEdit::Steps(5)),
            ),
            (
                "compaction.step",
                Edit::Compaction(CompactionEdit::Step(5.0)),
            ),
            (
                "compaction.until",
                Edit::Compaction(CompactionEdit::Until(5.0)),
            ),
        ];
        for (p, edit) in cases {
            assert!(SWEEP_PARAMETERS.iter().any(|(q, _)| *q == p), "{p}");
            assert_eq!(Edit::from_sweep(p, &n).as_ref(), Ok(&edit), "{p}");
            let e = Edit::from_sweep(p, &SweepValue::List(vec![1.0, 2.0])).unwrap_err();
            assert!(e.contains("one number"), "{p}: {e}");
        }
        assert_eq!(
            Edit::from_sweep("settling.contacts", &SweepValue::Number(2.0)),
            Ok(Edit::Settling(SettlingEdit::Contacts(2)))
        );
        let e = Edit::from_sweep("settling.contacts", &SweepValue::Number(4.0)).unwrap_err();
        assert!(e.contains("1, 2 or 3"), "{e}");
        // A pressure replaces a reduced pressure and the other way round:
        // the drainage takes one of them.
        let mut c = Config::default();
        c.apply(&Edit::DrainageReducedPressure(20.0)).unwrap();
        c.apply(&Edit::DrainagePressure(3e5)).unwrap();
        let d = &c.analysis.drainage;
        assert_eq!((d.pressure, d.reduced_pressure), (Some(3e5), None));
        c.apply(&Edit::DrainageReducedPressure(40.0)).unwrap();
        let d = &c.analysis.drainage;
        assert_eq!((d.pressure, d.reduced_pressure), (None, Some(40.0)));
        c.apply(&Edit::Drying(DryingEdit::Concentration(0.5)))
            .unwrap();
        c.apply(&Edit::Drying(DryingEdit::Solubility(50.0)))
            .unwrap();
        c.apply(&Edit::Drying(DryingEdit::MinNeck(0.1))).unwrap();
        c.apply(&Edit::Drying(DryingEdit::TensileStrength(1e6)))
            .unwrap();
        assert_eq!(c.analysis.drying.agitation, None);
        c.apply(&Edit::Drying(DryingEdit::AgitationStress(3e4)))
            .unwrap();
        assert_eq!(
            c.analysis.drying.agitation.as_ref().map(|a| a.stress),
            Some(3e4)
        );
        let d = &c.analysis.drying;
        assert_eq!(
            (
                d.concentration,
                d.solubility,
                d.min_neck,
                d.tensile_strength
            ),
            (0.5, Some(50.0), 0.1, 1e6)
        );
    }
}
