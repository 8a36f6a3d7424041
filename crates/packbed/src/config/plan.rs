//! Validation of a config into a [`Plan`] the engine runs: sizes resolved,
//! the box built, every bound checked once (lengths, memory, chains, the pore
//! space), estimates of the bed.

use super::*;
use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use crate::species::{EntryOrientation, Shape, SizeDist, SizeTable, Species, TableOptions, Within};

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
    /// How a dropped particle comes to rest.
    pub settling: Settling,
    /// Where particles enter.
    pub feed: Feed,
    /// The compaction after settling, if any.
    pub compaction: Option<super::Compaction>,
    /// The feeds one after another (`[[feeds]]`); empty: one feed of every
    /// species, filled as `fill` says, settled by `settling`.
    pub feeds: Vec<FeedStage>,
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

/// Longest species name, in bytes: a name labels tables, plots and the
/// screen, and a longer one is a mistake (a file pasted into the config).
pub const MAX_NAME_BYTES: usize = 256;

impl SpeciesConfig {
    fn resolve(&self, index: usize, metres_per_unit: Option<Real>) -> Result<Species> {
        let at = format!("species[{index}]");
        if let Some(name) = self.name.as_deref().filter(|n| n.len() > MAX_NAME_BYTES) {
            return Err(Error::config(format!(
                "{at}.name is {} bytes long, at most {MAX_NAME_BYTES}: `{}`",
                name.len(),
                crate::error::echo(name)
            )));
        }
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
                    None | Some("vertical") => EntryOrientation::Vertical,
                    Some("random") => EntryOrientation::Random,
                    Some("horizontal") => EntryOrientation::Horizontal,
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
            feed: None,
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
            let options = TableOptions {
                within,
                pan_min: self.pan_min,
            };
            return SizeTable::read_with(t, &options, metres_per_unit).map(SizeDist::Table);
        }
        if self.within.is_some() {
            return Err(Error::config(format!(
                "{at}.size.within applies to a `table`'s classes only"
            )));
        }
        if self.pan_min.is_some() {
            return Err(Error::config(format!(
                "{at}.size.pan_min applies to a sieve `table` only"
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

/// Extra peak bytes of the pore space (`pores`, `permeability`) per point
/// triangulated (a particle or an image), 2D and 3D. Measured as the
/// largest `VmPeak` (the address space `ulimit -v` bounds) of `packbed
/// analyze --measures all` on periodic beds of equal particles, less the
/// rest of the estimate: 10^6 spheres 3.27 GB (1.82 KB a point), 10^5
/// spheres 0.54 GB (1.67 KB), 10^6 discs 1.17 GB (0.19 KB), 2026-11-28
/// (BENCHMARKS.md, "The pore space's memory bound"); rounded up by two
/// thirds and more. It was 8 KB a particle in both dimensions, from an early
/// build: a 16 GB laptop was refused 2·10^6 spheres, about 6.5 GB by the
/// 10^6 figure.
const BYTES_PER_POINT_PORES: [u64; 2] = [512, 3072];

/// The margin of images the pore network is first built with, in largest
/// radii (`analysis::pores::network`; it grows only when a pore near a side
/// needs more).
pub const PORE_MARGIN_RADII: Real = 6.0;

/// Points the pore space triangulates per particle of `container`: the
/// particles and, on a periodic bed, their images within the first margin
/// of each side (a bed spread evenly across the floor).
pub fn pore_points_per_particle<const D: usize>(container: &Container<D>, r_max: Real) -> Real {
    if !container.periodic {
        return 1.0;
    }
    let margin = PORE_MARGIN_RADII * r_max;
    let factor = (0..D - 1)
        .map(|k| 1.0 + 2.0 * margin / container.extent(k))
        .product::<Real>();
    if factor.is_finite() {
        factor.max(1.0)
    } else {
        1.0
    }
}

/// Address space a run takes whatever its size (the program, thread stacks,
/// the allocator's arenas): a 10^6-sphere run needs 1.2 GiB under `ulimit -v`
/// against its 0.84 GB resident.
const BYTES_FIXED: u64 = 192 << 20;

/// The peak memory of a run placing `particles` in `dim` dimensions and
/// computing `measures`, in bytes; `points` is the pore space's points per
/// particle ([`pore_points_per_particle`]).
pub(crate) fn run_bytes(dim: u8, particles: Real, measures: &[Measure], points: Real) -> Real {
    let pores = measures
        .iter()
        .any(|m| matches!(m, Measure::Pores | Measure::Permeability));
    let d = usize::from(dim == 3);
    let per = BYTES_PER_PARTICLE[d] as Real
        + if pores {
            BYTES_PER_POINT_PORES[d] as Real * points
        } else {
            0.0
        };
    particles * per + BYTES_FIXED as Real
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
        let mut species = name_species(species);
        rsa_places_single_particles(self.mode, &species)?;
        let settling = self.settling.resolve()?;
        let mut feeds = self.feeds(&mut species)?;
        if self.mode == Mode::Rsa && !settling.is_rolling() {
            return Err(Error::config(
                "[settling] rules how dropped particles come to rest; mode = \"rsa\" drops none (remove [settling], or use mode = \"deposit\")",
            ));
        }
        let compaction = self.compaction(&species, &feeds)?;
        let r_max = Self::r_max(&species);
        let container = self.container.resolve::<D>(&species, r_max)?;
        // A mesh's wires span the box, so its species come with the box.
        let fed_species = species.len();
        super::feeds::weave(&mut feeds, &mut species, &container)?;
        super::feeds::amounts(
            &mut feeds,
            &mut species,
            &container,
            self.analysis.length_unit.map(LengthUnit::metres),
            self.analysis.solid_density,
        )?;
        let feed = self.feed.resolve(&container, r_max)?;
        if self.mode == Mode::Rsa && !self.feed.is_default() {
            return Err(Error::config(
                "[feed] says where dropped particles enter; mode = \"rsa\" drops none (remove [feed], or use mode = \"deposit\")",
            ));
        }
        let fill = match (&self.fill.until, self.fill.count) {
            _ if !feeds.is_empty() => Fill::Count(feeds.iter().map(|f| f.count).sum()),
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
        // A mesh's wires span the box on purpose (closed through its sides).
        chains_fit(&species[..fed_species], &container)?;
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
        let beads = species[..fed_species]
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
        let points = pore_points_per_particle(&container, r_max);
        let needed = run_bytes(self.dim, estimate, measures, points);
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
        if let Some(f) = &self.filtration {
            f.drive()?;
            if D == 2 {
                return Err(Error::config(
                    "[filtration] is solved in 3D beds: a 2D bed's permeability is per unit depth, and its filtration curve is not modelled (set dim = 3)",
                ));
            }
            if !feeds.iter().any(|f| f.medium) {
                return Err(Error::config(
                    "[filtration] filters the slurry through a medium: mark the medium's feeds with `medium = true` in [[feeds]]",
                ));
            }
            if self.analysis.length_unit.is_none() || self.analysis.solid_density.is_none() {
                return Err(Error::config(
                    "[filtration] gives its figures in SI: set analysis.length_unit and analysis.solid_density",
                ));
            }
        }
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
            // A medium laid as it is (a woven mesh, a bed file) lies on the
            // floor: no base layer under it (one under a mesh was 1,000
            // powder particles below the wires, and the capture counted
            // them lodged).
            base_layer: if feeds
                .first()
                .is_some_and(|f| f.file.is_some() || f.mesh.is_some())
            {
                BaseLayerKind::None
            } else {
                self.fill.base_layer
            },
            species,
            contact_tol: tol,
            large_radius,
            settling,
            feed,
            compaction,
            feeds,
        })
    }

    /// `[compaction]`, checked: spheres and discs dropped on a bare floor.
    fn compaction(
        &self,
        species: &[Species],
        feeds: &[FeedStage],
    ) -> Result<Option<super::Compaction>> {
        let Some(c) = &self.compaction else {
            return Ok(None);
        };
        let c = c.resolve()?;
        if self.mode == Mode::Rsa {
            return Err(Error::config(
                "[compaction] compacts a settled bed; mode = \"rsa\" settles none (remove [compaction], or use mode = \"deposit\")",
            ));
        }
        if species
            .iter()
            .any(|s| matches!(s.shape, Shape::Chain { .. }))
        {
            return Err(Error::config(
                "[compaction] moves spheres and discs; a rigid chain's rotations are not modelled (remove the chains' species or [compaction])",
            ));
        }
        if feeds.iter().any(|f| f.file.is_some() || f.mesh.is_some()) {
            return Err(Error::config(
                "[compaction] would move the laid medium (a mesh or a bed file) with the cake; compact a cake on a bare floor",
            ));
        }
        Ok(Some(c))
    }

    /// The `[[feeds]]`, checked, each species marked with its feed; none
    /// without the table.
    fn feeds(&self, species: &mut [Species]) -> Result<Vec<FeedStage>> {
        if self.feeds.is_empty() {
            return Ok(Vec::new());
        }
        if self.mode == Mode::Rsa {
            return Err(Error::config(
                "[[feeds]] settle particles one feed after another; mode = \"rsa\" drops none (remove [[feeds]], or use mode = \"deposit\")",
            ));
        }
        if self.fill.count.is_some() || self.fill.until.is_some() {
            return Err(Error::config(
                "[[feeds]] give each feed its count: remove fill.count and fill.until",
            ));
        }
        super::feeds::resolve_feeds(&self.feeds, species, &self.settling)
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
/// Random sequential addition places spheres and discs only: a chain is
/// refused with the config, before any work (not by the first replicate).
fn rsa_places_single_particles(mode: Mode, species: &[Species]) -> Result<()> {
    if mode != Mode::Rsa {
        return Ok(());
    }
    match species
        .iter()
        .find(|s| matches!(s.shape, Shape::Chain { .. }))
    {
        Some(s) => Err(Error::config(format!(
            "mode = \"rsa\" places spheres and discs only, but species `{}` is a chain \
             (chains need mode = \"deposit\")",
            crate::error::echo(&s.name)
        ))),
        None => Ok(()),
    }
}

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
/// `measures` when that would need more memory than packbed may use (in 3D
/// the pore space costs about three times the rest); `points` as in
/// `run_bytes`.
pub fn check_analysis(
    particles: usize,
    dim: u8,
    measures: &[Measure],
    points: Real,
    what: &str,
) -> Result<()> {
    let memory = crate::input::memory_budget_bytes() as Real;
    let needed = run_bytes(dim, particles as Real, measures, points);
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
            let name = self.preset.as_deref().unwrap_or("thesis");
            let beads = species.iter().map(|s| s.shape.beads()).max().unwrap_or(1);
            size = Container::<D>::preset_size(name, r_max, beads).ok_or_else(|| {
                Error::config(format!(
                    "box.preset: unknown preset `{name}` (expected {})",
                    crate::container::PRESETS
                        .map(|p| format!("\"{p}\""))
                        .join(", ")
                ))
            })?;
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
    fn the_pore_space_counts_the_images_of_a_periodic_bed() {
        use crate::container::Container;
        use crate::math::Vector;
        let periodic = Container {
            size: Vector([600.0, 600.0, 2000.0]),
            periodic: true,
        };
        // A margin of 60 on each side of 600: 1.2 along each side axis.
        let f = pore_points_per_particle(&periodic, 10.0);
        assert!((f - 1.44).abs() < 1e-12, "{f}");
        let discs = Container {
            size: Vector([2000.0, 1000.0]),
            periodic: true,
        };
        assert!((pore_points_per_particle(&discs, 10.0) - 1.06).abs() < 1e-12);
        let walled = Container {
            periodic: false,
            ..periodic
        };
        assert_eq!(pore_points_per_particle(&walled, 10.0), 1.0);
        // The images raise the pore space's share, and only its share.
        let all = [Measure::Pores];
        let with = run_bytes(3, 1e6, &all, 1.44) - run_bytes(3, 1e6, &[], 1.44);
        let without = run_bytes(3, 1e6, &all, 1.0) - run_bytes(3, 1e6, &[], 1.0);
        assert!((with / without - 1.44).abs() < 1e-12);
        assert_eq!(run_bytes(3, 1e6, &[], 1.44), run_bytes(3, 1e6, &[], 1.0));
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
