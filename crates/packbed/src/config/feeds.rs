//! `[[feeds]]`: one bed built from several feeds, one after another, as a
//! filter is fed a precoat and then the slurry, or alternating slurries.
//! Each feed draws from its own species (by their ratios), places its own
//! number of bodies and settles them by its own rule:
//!
//! ```toml
//! [[feeds]]
//! species = ["sand"]        # names of [[species]] entries
//! count = 2000
//! settling = { restitution = 0.5 }   # default: the config's [settling]
//!
//! [[feeds]]
//! species = ["flour"]
//! count = 20000
//! ```
//!
//! The first feeds may be a filter medium (`medium = true`: a precoat, a
//! granular medium, a fibre layer of horizontal chains): they settle on the
//! solid floor, then the medium is lifted by [`Plan::medium_gap`] and the
//! floor opens. A later body that reaches the floor has passed the medium:
//! it leaves the bed as filtrate, counted with where it left
//! ([`crate::analysis::capture`]).
//!
//! [`Plan::medium_gap`]: super::Plan::medium_gap
//!
//! A species belongs to one feed, so a particle's feed is its species'
//! (`particles.csv` gains a `feed` column); to feed one slurry twice, give
//! it two species entries. Without `[[feeds]]` a bed is one feed of every
//! species, filled as `[fill]` says, bit for bit as before.

use super::medium_file::MediumFile;
use super::mesh::{Mesh, MeshConfig};
use super::settling::{Settling, SettlingConfig};
use crate::error::{Error, Result};
use crate::math::Real;
use crate::species::{Shape, Species};
use serde::{Deserialize, Serialize};

/// One `[[feeds]]` entry as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeedStageConfig {
    /// The names of the species this feed draws from (none for a mesh).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub species: Vec<String>,
    /// How many particles (beads) it places (none for a mesh: its wires
    /// fill the box).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub count: u64,
    /// Or how much it feeds as a mass of solids per filter area, kg/m²
    /// (3D; needs `analysis.length_unit` and `solid_density`): the feed ends
    /// with the body that brings the mass it fed, placed or passed, each
    /// bead counted whole, to at least this.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_per_area: Option<Real>,
    /// Its settling rule (default: the config's `[settling]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settling: Option<SettlingConfig>,
    /// True for a filter medium: it settles on the solid floor, then stands
    /// fixed above an open floor through which the later feeds can pass.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub medium: bool,
    /// A woven square mesh of wires as the medium, placed rather than fed
    /// (`mesh = { wire_diameter = 2, aperture = 3 }`; see [`MeshConfig`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshConfig>,
    /// A medium read from a bed file (`file = "medium.csv"`, relative to the
    /// config file; see `config::medium_file`): placed as read, not fed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<std::path::PathBuf>,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl FeedStageConfig {
    /// True for a filter medium: marked `medium = true`, a mesh, or read
    /// from a file.
    pub fn is_medium(&self) -> bool {
        self.medium || self.mesh.is_some() || self.file.is_some()
    }
}

/// One feed of a bed, checked: what it draws, how many, how they settle.
#[derive(Clone, Debug, PartialEq)]
pub struct FeedStage {
    /// Indices of its species (into the plan's species), in config order.
    pub species: Vec<u32>,
    /// Beads it places; for a feed by mass, the expected number (the
    /// memory estimate and the species' shares of the bed).
    pub count: u64,
    /// A feed by mass: kg of solids per m² of filter, as written.
    pub mass_per_area: Option<Real>,
    /// A feed by mass: the solid volume it feeds, in the bed's length unit
    /// cubed (set with the box, [`amounts`]); `None` for a feed by count.
    pub volume: Option<Real>,
    /// How its particles come to rest.
    pub settling: Settling,
    /// True for a filter medium (the feeds before the first slurry).
    pub medium: bool,
    /// A woven mesh placed as the medium (its species are made for it).
    pub mesh: Option<Mesh>,
    /// A medium read from a bed file, placed as read (its species are made
    /// for it when the file is read).
    pub file: Option<MediumFile>,
}

impl<const D: usize> super::Plan<D> {
    /// How far a filter medium stands above the open floor: the longest
    /// body of the feeds after it (a sphere's diameter, a chain's length end
    /// to end). A body resting on the floor then reaches no higher than the
    /// medium's bottom, so it touches none of it: it has passed; a body the
    /// medium holds rests on a contact above its bottom, so its lowest point
    /// stands above half the gap. 0 without a medium.
    pub fn medium_gap(&self) -> Real {
        if !self.feeds.iter().any(|f| f.medium) {
            return 0.0;
        }
        self.feeds
            .iter()
            .filter(|f| !f.medium)
            .flat_map(|f| &f.species)
            .map(|&s| {
                let s = &self.species[s as usize];
                let r = s.size.bounds().1;
                match s.shape {
                    Shape::Sphere => 2.0 * r,
                    Shape::Chain { beads, spacing, .. } => {
                        2.0 * r + Real::from(beads.saturating_sub(1)) * spacing * r
                    }
                }
            })
            .fold(0.0, Real::max)
    }
}

/// The feeds of `stages`, checked against the named `species` (each of which
/// the caller marks with its feed); `settling` is the config's rule.
pub(crate) fn resolve_feeds(
    stages: &[FeedStageConfig],
    species: &mut [Species],
    settling: &SettlingConfig,
) -> Result<Vec<FeedStage>> {
    let mut out = Vec::with_capacity(stages.len());
    for (k, stage) in stages.iter().enumerate() {
        let what = format!("feeds[{k}]");
        if stage.is_medium() && k > 0 && !stages[k - 1].is_medium() {
            return Err(Error::config(format!(
                "{what}.medium: the medium's feeds come first, before every feed that is not a medium (move this entry up)"
            )));
        }
        if let Some(path) = &stage.file {
            out.push(file_stage(k, stage, path, settling)?);
            continue;
        }
        if let Some(mesh) = &stage.mesh {
            out.push(mesh_stage(k, stage, mesh, settling)?);
            continue;
        }
        match (stage.count, stage.mass_per_area) {
            (0, None) => {
                return Err(Error::config(format!(
                    "{what}.count must be at least 1 (or give the feed's `mass_per_area`, kg/m²)"
                )))
            }
            (_, Some(m)) if !(m.is_finite() && m > 0.0) => {
                return Err(Error::config(format!(
                    "{what}.mass_per_area must be a positive number of kg per m² of filter (got {m})"
                )))
            }
            (n, Some(_)) if n > 0 => {
                return Err(Error::config(format!(
                    "{what}: give its amount once: `count` (beads) or `mass_per_area` (kg/m²), not both"
                )))
            }
            _ => {}
        }
        if stage.species.is_empty() {
            return Err(Error::config(format!(
                "{what}.species is empty: name the [[species]] this feed draws from"
            )));
        }
        let mut picked = Vec::with_capacity(stage.species.len());
        for name in &stage.species {
            let Some(i) = species.iter().position(|s| &s.name == name) else {
                let known: Vec<&str> = species.iter().map(|s| s.name.as_str()).collect();
                return Err(Error::config(format!(
                    "{what}.species: no species is named `{name}` (the species are {})",
                    known.join(", ")
                )));
            };
            if let Some(other) = species[i].feed {
                return Err(Error::config(format!(
                    "{what}.species: `{name}` is fed by feeds[{other}] already; a species belongs to one feed (give the second feed its own [[species]] entry)"
                )));
            }
            species[i].feed = Some(k as u32);
            picked.push(i as u32);
        }
        let sum: Real = picked.iter().map(|&i| species[i as usize].ratio).sum();
        if sum <= 0.0 {
            return Err(Error::config(format!(
                "{what}: the ratios of its species sum to zero"
            )));
        }
        // A feed draws by its own species' ratios; the bed holds each species
        // in the share its feed's count gives it, which the ratios then say
        // (the requested size distribution, the summary's species): its
        // expected bodies, the count (in beads) over the feed's mean beads
        // per body, since the ratios (and the size distribution's number
        // shares) count bodies. A feed by mass scales its shares once its
        // count is known ([`amounts`]).
        if stage.mass_per_area.is_none() {
            let beads: Real = picked
                .iter()
                .map(|&i| {
                    let s = &species[i as usize];
                    s.ratio / sum * Real::from(s.shape.beads())
                })
                .sum();
            let bodies = stage.count as Real / beads;
            for &i in &picked {
                species[i as usize].ratio *= bodies / sum;
            }
        }
        let rule = stage.settling.as_ref().unwrap_or(settling).resolve()?;
        out.push(FeedStage {
            species: picked,
            count: stage.count,
            mass_per_area: stage.mass_per_area,
            volume: None,
            settling: rule,
            medium: stage.medium,
            mesh: None,
            file: None,
        });
    }
    if out.last().is_some_and(|f| f.medium) {
        return Err(Error::config(
            "[[feeds]]: every feed is a medium; add the slurry's feed after it (a medium is what a later feed is filtered through)",
        ));
    }
    if let Some(s) = species.iter().find(|s| s.feed.is_none()) {
        return Err(Error::config(format!(
            "species `{}` is in no [[feeds]] entry: name it in one feed's `species`, or remove it",
            s.name
        )));
    }
    Ok(out)
}

/// Checks feed `k`, a medium placed rather than fed (its `key`, `mesh` or
/// `file`): the first feed, since it lies on the floor (`lies`, e.g. "a
/// mesh is laid"), and given no key of a fed feed (`placed` says why).
/// Returns the feed's name for messages.
fn placed_first(
    k: usize,
    stage: &FeedStageConfig,
    key: &str,
    lies: &str,
    placed: &str,
) -> Result<String> {
    let what = format!("feeds[{k}]");
    if k > 0 {
        return Err(Error::config(format!(
            "{what}.{key}: {lies} on the floor, so it is the first feed (a precoat may follow it)"
        )));
    }
    for (given, other) in [
        (!stage.species.is_empty(), "species"),
        (stage.count != 0, "count"),
        (stage.mass_per_area.is_some(), "mass_per_area"),
        (stage.settling.is_some(), "settling"),
        (key != "mesh" && stage.mesh.is_some(), "mesh"),
    ] {
        if given {
            return Err(Error::config(format!(
                "{what}.{other}: {placed} (remove `{other}`)"
            )));
        }
    }
    Ok(what)
}

/// Feed `k`, a medium read from `path`: placed, so it names no species,
/// count, mass or rule; only the first feed, since it lies on the floor.
fn file_stage(
    k: usize,
    stage: &FeedStageConfig,
    path: &std::path::Path,
    settling: &SettlingConfig,
) -> Result<FeedStage> {
    let what = placed_first(
        k,
        stage,
        "file",
        "a medium read from a file lies",
        "a medium read from a file is placed as the file has it, not fed",
    )?;
    if path.as_os_str().is_empty() {
        return Err(Error::config(format!(
            "{what}.file is empty: name the bed file of the medium"
        )));
    }
    Ok(FeedStage {
        species: Vec::new(),
        count: 0,
        mass_per_area: None,
        volume: None,
        settling: settling.resolve()?,
        medium: true,
        mesh: None,
        file: Some(MediumFile {
            path: path.to_path_buf(),
            beads: None,
        }),
    })
}

/// Feed `k`, a woven mesh: placed, so it names no species, count or rule
/// (its species and count come with the box, [`weave`]); only the first
/// feed, since it is laid on the floor.
fn mesh_stage(
    k: usize,
    stage: &FeedStageConfig,
    mesh: &MeshConfig,
    settling: &SettlingConfig,
) -> Result<FeedStage> {
    let what = placed_first(
        k,
        stage,
        "mesh",
        "a mesh is laid",
        "a mesh is placed, not fed: its wires fill the box",
    )?;
    Ok(FeedStage {
        species: Vec::new(),
        count: 0,
        mass_per_area: None,
        volume: None,
        settling: settling.resolve()?,
        medium: true,
        mesh: Some(mesh.resolve(&what)?),
        file: None,
    })
}

/// Adds the species of the feeds' mesh (if any) to `species`, now that the
/// box `c` is known, and sets that feed's species and count (its beads).
pub(crate) fn weave<const D: usize>(
    feeds: &mut [FeedStage],
    species: &mut Vec<Species>,
    c: &crate::container::Container<D>,
) -> Result<()> {
    for (k, feed) in feeds.iter_mut().enumerate() {
        let Some(mesh) = feed.mesh else { continue };
        for family in mesh.wires(c, &format!("feeds[{k}]"))? {
            let s = mesh.species(&family, k as u32);
            if species.iter().any(|t| t.name == s.name) {
                return Err(Error::config(format!(
                    "species `{}`: that name is the mesh's (feeds[{k}]); rename the species",
                    s.name
                )));
            }
            feed.species.push(species.len() as u32);
            feed.count += u64::from(family.wires) * u64::from(family.beads);
            species.push(s);
        }
    }
    Ok(())
}

/// Turns each feed by mass into the solid volume it feeds and its expected
/// count, now that the box `c` is known: `unit` metres per length unit,
/// `rho` the solid density (kg/m³). The expected count is the volume over
/// the mean body volume of the feed's species (by their ratios); it sizes
/// the memory estimate and the species' shares of the requested size
/// distribution, while the engine feeds until the volume is reached.
pub(crate) fn amounts<const D: usize>(
    feeds: &mut [FeedStage],
    species: &mut [Species],
    c: &crate::container::Container<D>,
    unit: Option<Real>,
    rho: Option<Real>,
) -> Result<()> {
    for (k, feed) in feeds.iter_mut().enumerate() {
        let Some(mass) = feed.mass_per_area else {
            continue;
        };
        let what = format!("feeds[{k}].mass_per_area");
        if D != 3 {
            return Err(Error::config(format!(
                "{what}: a mass per filter area needs a 3D bed (dim = 3); give a 2D feed its `count`"
            )));
        }
        let (Some(unit), Some(rho)) = (unit, rho) else {
            return Err(Error::config(format!(
                "{what}: a mass becomes particles through the bed's scale: set analysis.length_unit and analysis.solid_density"
            )));
        };
        let area: Real = (0..D - 1).map(|a| c.size[a]).product();
        let volume = mass * area / (rho * unit);
        let sum: Real = feed
            .species
            .iter()
            .map(|&i| species[i as usize].ratio)
            .sum();
        let mean_body: Real = feed
            .species
            .iter()
            .map(|&i| {
                let s = &species[i as usize];
                s.ratio / sum
                    * Real::from(s.shape.beads())
                    * crate::math::ball_volume::<D>(1.0)
                    * s.size.mean_cube()
            })
            .sum();
        let expected = (volume / mean_body).ceil();
        if !(expected.is_finite() && expected >= 1.0) || expected > 1e12 {
            return Err(Error::config(format!(
                "{what}: {mass} kg/m² over this box is {expected} bodies of the feed's sizes; give a mass of at least one body and at most 10^12"
            )));
        }
        // In beads, as a feed's count is.
        let beads = feed
            .species
            .iter()
            .map(|&i| u64::from(species[i as usize].shape.beads()))
            .max()
            .unwrap_or(1);
        feed.count = expected as u64 * beads;
        // The shares count bodies, as the ratios do.
        for &i in &feed.species {
            species[i as usize].ratio *= expected / sum;
        }
        feed.volume = Some(volume);
    }
    Ok(())
}
