//! Measures of a bed's structure. Every measure takes a [`Bed`] (built by packbed
//! or read from a file) and never reaches back into the deposition engine.

pub mod cake;
pub mod capture;
mod cells;
pub mod contacts;
pub mod dimensions;
mod disjoint_paths;
pub mod filtration;
pub mod heap;
pub mod histogram;
mod maxflow;
pub mod orientation;
pub mod packing;
pub mod pair_correlation;
pub mod percolation;
pub mod pores;
pub mod profile;
pub mod psd;
pub mod regions;
pub mod segregation;
pub mod stats;
pub mod validate;
pub mod voids;

use crate::bed::Bed;
pub use crate::config::{Measure, Measures};
use crate::math::Real;
use serde::Serialize;

pub use cake::{CakeOptions, CakeSummary};
pub use contacts::{coordination, find_contacts, overlaps, Contact, Contacts, Overlaps};
pub use histogram::count_histogram;
pub use orientation::Orientation;
pub use packing::bulk_region;
#[cfg(test)]
use packing::Region;
pub use percolation::{LargeRule, Percolation, PercolationOptions};
pub use profile::Profile;
pub use regions::RegionalPacking;
pub use segregation::Segregation;
pub use voids::VoidSummary;

/// Every measure of a bed, laid out as in `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Summary {
    /// Filter cake properties: porosity, `d32`, specific surface, Kozeny–Carman
    /// permeability (with the packing measure).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cake: Option<CakeSummary>,
    /// Measures the caller left out (`[analysis] measures`); absent when none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub measures_left_out: Vec<&'static str>,
    /// Packing fractions (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packing: Option<PackingSummary>,
    /// Coordination numbers (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coordination: Option<CoordinationSummary>,
    /// Percolation chains of large particles (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub percolation: Option<Percolation>,
    /// Voids of the contact network (2D beds only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub voids: Option<VoidSummary>,
    /// Orientation of bodies of several beads (beds with chains only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientation: Option<Orientation>,
    /// Size segregation (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub segregation: Option<Segregation>,
    /// Pores and constrictions of the bulk slab (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pores: Option<pores::PoresSummary>,
    /// Permeability of the pore network (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub permeability: Option<pores::PermeabilitySummary>,
    /// Why `pores` or `permeability` is absent although asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pores_note: Option<String>,
    /// The formation factor and tortuosities (with the permeability).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transport: Option<pores::transport::TransportSummary>,
    /// Primary drainage of the pore network (absent when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drainage: Option<pores::drainage::DrainageSummary>,
    /// Why `drainage` is absent although asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drainage_note: Option<String>,
    /// The solid bridges and agglomerates the dried cake holds (absent
    /// when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agglomeration: Option<pores::drying::AgglomerationSummary>,
    /// Why `agglomeration` is absent although asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agglomeration_note: Option<String>,
    /// The solid bridges and agglomerates for the files (not in
    /// `summary.json`).
    #[serde(skip)]
    pub dried: Option<std::sync::Arc<pores::drying::Drying>>,
    /// The drainage's curve, pores and bridges for the files (not in
    /// `summary.json`).
    #[serde(skip)]
    pub liquid: Option<std::sync::Arc<pores::drainage::Drainage>>,
    /// The pore network's tables for the files (not in `summary.json`).
    #[serde(skip)]
    pub pore_tables: Option<std::sync::Arc<pores::PoreTables>>,
    /// What the measures warn of (a slab too small for its permeability):
    /// reported under the summary's `warnings` and on stderr.
    #[serde(skip)]
    pub warnings: Vec<String>,
    /// Wall time of the triangulation (reported under `timing`).
    #[serde(skip)]
    pub triangulation_seconds: Option<f64>,
    /// Wall time of the pore network built on it (reported under `timing`).
    #[serde(skip)]
    pub network_seconds: Option<f64>,
}

/// `packing.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct PackingSummary {
    /// Solid volume ÷ box volume (box up to the roof).
    pub global: Real,
    /// Solid fraction of the bulk region ([`packing::bulk_region`]); `None`
    /// (null) when the bed has no bulk region or it holds fewer bodies than the
    /// minimum (`bulk_note` says which).
    pub bulk: Option<Real>,
    /// True when the bed has no bulk region.
    pub bulk_region_empty: bool,
    /// Bodies with at least one particle centre in the bulk region.
    pub bulk_bodies: u64,
    /// Why the bulk measures are null, when they are.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bulk_note: Option<String>,
    /// When they are: the side, in largest diameters, of the smallest cube
    /// whose bulk would hold the minimum of bodies
    /// ([`packing::cube_for_bulk`]); for the screen, not `summary.json`.
    #[serde(skip)]
    pub bulk_cube_diameters: Option<u64>,
    /// Floor, roof, wall and centre regions.
    pub regions: RegionalPacking,
    /// Solid fraction in slabs of `d_max / 4`, bottom to top.
    pub profile: Profile,
    /// g(r) of the bulk's centres (null without a bulk region).
    pub pair_correlation: Option<pair_correlation::PairCorrelation>,
    /// The slope of a heap poured from a point (null for a surface with
    /// less relief than three largest diameters).
    pub heap: Option<heap::Heap>,
}

/// `coordination.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CoordinationSummary {
    /// Mean number of touching bodies per body, over the whole bed.
    pub mean: Real,
    /// The same over particles whose centre lies in the bulk region (each with its
    /// body's number, so a chain counts once per bead inside); null as
    /// `packing.bulk` is.
    pub mean_bulk: Option<Real>,
    /// Number of particles whose centre lies in the bulk region.
    pub bulk_particles: u64,
    /// Number of bodies with 0, 1, 2, … touching bodies.
    pub histogram: Vec<u64>,
    /// The same in the bulk region (one entry per particle, as `mean_bulk`).
    pub histogram_bulk: Vec<u64>,
    /// Per species (size class), in species order.
    pub by_species: Vec<SpeciesCoordination>,
    /// Particles touching the floor.
    pub floor_contacts: u64,
    /// Particles touching a side wall (a particle in a corner counts per wall).
    pub wall_contacts: u64,
}

/// Coordination numbers of one species.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct SpeciesCoordination {
    /// Species index (the `species` column of `particles.csv`).
    pub species: u32,
    /// Species name, when the bed knows it.
    pub name: String,
    /// Bodies of this species.
    pub bodies: u64,
    /// Mean number of touching bodies.
    pub mean: Real,
    /// Mean over its particles in the bulk region (null when the bulk measures
    /// are, or none of its particles is in the bulk).
    pub mean_bulk: Option<Real>,
    /// Its particles in the bulk region.
    pub bulk_particles: u64,
    /// Number of its bodies with 0, 1, 2, … touching bodies.
    pub histogram: Vec<u64>,
}

/// Settings of the analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnalysisOptions {
    /// Contact tolerance relative to the smaller radius of each pair.
    pub contact_tol: Real,
    /// Percolation settings (which particles are large, enumeration caps).
    pub percolation: PercolationOptions,
    /// Bulk measures are null below this many bodies in the bulk region.
    pub bulk_min_bodies: u64,
    /// The direction chain angles are measured from.
    pub angle_from: orientation::AngleFrom,
    /// The measures to compute.
    pub measures: Measures,
    /// Solid density and length unit of the cake properties.
    pub cake: CakeOptions,
    /// The flow through the pore network.
    pub flow: pores::FlowOptions,
    /// Gas displacing the liquid from the pore network.
    pub drainage: pores::drainage::DrainageOptions,
    /// The drying of the drained cake.
    pub drying: pores::drying::DryingOptions,
}

pub use crate::config::BULK_MIN_BODIES;

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            contact_tol: crate::config::DEFAULT_CONTACT_TOL,
            percolation: PercolationOptions::default(),
            bulk_min_bodies: BULK_MIN_BODIES,
            angle_from: orientation::AngleFrom::Vertical,
            measures: Measures::default_set(),
            cake: CakeOptions::default(),
            flow: pores::FlowOptions::default(),
            drainage: pores::drainage::DrainageOptions::default(),
            drying: pores::drying::DryingOptions::default(),
        }
    }
}

impl AnalysisOptions {
    /// The options with this contact tolerance and, if given, percolation
    /// threshold radius (else the default: the largest of the species'
    /// volume-median radii).
    pub(crate) fn new(contact_tol: Real, large_radius: Option<Real>) -> Self {
        let mut o = AnalysisOptions {
            contact_tol,
            ..Default::default()
        };
        if let Some(r) = large_radius {
            o.percolation.large = LargeRule::Radius(r);
        }
        o
    }
}

/// Runs the default measures (all but the pore space) on a bed with default
/// settings and this contact tolerance (relative to the smaller radius of
/// each pair).
pub fn analyze<const D: usize>(bed: &Bed<D>, contact_tol: Real) -> (Contacts, Summary) {
    analyze_with(bed, &AnalysisOptions::new(contact_tol, None))
}

/// Finds the contacts and runs the measures `opts` asks for on a bed.
pub fn analyze_with<const D: usize>(bed: &Bed<D>, opts: &AnalysisOptions) -> (Contacts, Summary) {
    analyze_timed(bed, opts, &mut StageTimes::default())
}

/// Wall time of each analysis stage, in the order they ran: `packbed bench
/// --analysis` prints them, so that a slow measure on a large bed shows itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageTimes(pub Vec<(&'static str, f64)>);

impl StageTimes {
    /// Runs `f`, recording its wall time under `name`.
    pub(crate) fn time<T>(&mut self, name: &'static str, f: impl FnOnce() -> T) -> T {
        let t = std::time::Instant::now();
        let out = f();
        self.0.push((name, t.elapsed().as_secs_f64()));
        out
    }

    /// Total of the stages whose name starts with `prefix` (all for `""`).
    pub(crate) fn total(&self, prefix: &str) -> f64 {
        self.0
            .iter()
            .filter(|(n, _)| n.starts_with(prefix))
            .map(|e| e.1)
            .sum()
    }
}

/// Runs every measure on a bed, timing each stage into `times`.
pub fn analyze_timed<const D: usize>(
    bed: &Bed<D>,
    opts: &AnalysisOptions,
    times: &mut StageTimes,
) -> (Contacts, Summary) {
    let contacts = times.time("contacts", || {
        contacts::find_contacts(bed, opts.contact_tol)
    });
    let z = times.time("coordination", || contacts::coordination(bed, &contacts));
    let (volumes, surfaces) = times.time("packing/volumes", || {
        packing::particle_volumes_and_surfaces(bed)
    });
    let region = packing::bulk_region(bed);
    let in_bulk: Vec<bool> = times.time("coordination/bulk", || match &region {
        Some(reg) => bed.centres.iter().map(|c| reg.contains(c)).collect(),
        None => vec![false; bed.len()],
    });
    let bulk_bodies = count_bodies(bed, &in_bulk);
    let bulk_note = if region.is_none() {
        Some("the bed is too small to have a bulk region".to_string())
    } else if bulk_bodies < opts.bulk_min_bodies {
        Some(format!(
            "the bulk region holds {bulk_bodies} bodies, fewer than the minimum of {}",
            opts.bulk_min_bodies
        ))
    } else {
        None
    };
    let bulk_ok = bulk_note.is_none();
    let want = |m| opts.measures.has(m);
    let coordination = want(Measure::Coordination).then(|| {
        times.time("coordination/summary", || {
            coordination_summary(bed, &contacts, &z, &in_bulk, bulk_ok)
        })
    });
    let d_max = 2.0 * bed.r_max();
    let packing = want(Measure::Packing).then(|| PackingSummary {
        global: times.time("packing/global", || {
            packing::global_fraction_of(bed, &volumes)
        }),
        bulk: times.time("packing/bulk", || {
            region
                .as_ref()
                .filter(|_| bulk_ok)
                .map(|reg| reg.fraction_of(bed, &volumes))
        }),
        bulk_region_empty: region.is_none(),
        bulk_bodies,
        bulk_cube_diameters: bulk_note
            .is_some()
            .then(|| packing::cube_for_bulk(bed, opts.bulk_min_bodies))
            .flatten(),
        bulk_note,
        regions: times.time("packing/regions", || {
            regions::regional_packing_of(bed, &volumes)
        }),
        profile: times.time("packing/profile", || {
            profile::profile_of(bed, 0.25 * d_max, &volumes)
        }),
        pair_correlation: times.time("packing/pair_correlation", || {
            region
                .as_ref()
                .filter(|_| bulk_ok)
                .and_then(|reg| pair_correlation::pair_correlation(bed, reg))
        }),
        heap: times.time("packing/heap", || heap::heap(bed)),
    });
    let pores_wanted = want(Measure::Pores)
        || want(Measure::Permeability)
        || want(Measure::Drainage)
        || want(Measure::Agglomeration);
    // The permeability's ratios (`k / d32²`, `k / k_KC`) read the cake's d32
    // and Kozeny–Carman k: computed for them even when the packing measure
    // (which reports the cake) is not asked for.
    let bulk_fraction = match &packing {
        Some(p) => p.bulk,
        None if pores_wanted => region
            .as_ref()
            .filter(|_| bulk_ok)
            .map(|reg| reg.fraction_of(bed, &volumes)),
        None => None,
    };
    let mut cake = (packing.is_some() || pores_wanted).then(|| {
        times.time("cake", || {
            let bulk = region.as_ref().zip(bulk_fraction);
            let height = packing::surface_height(bed);
            cake::cake(bed, &volumes, &surfaces, bulk, height, &opts.cake)
        })
    });
    let pore_space = pores_wanted.then(|| {
        pore_measures(
            bed,
            opts,
            region.as_ref().filter(|_| bulk_ok),
            cake.as_mut(),
            times,
        )
    });
    let percolation = want(Measure::Percolation)
        .then(|| percolation::percolation_timed(bed, &contacts, &opts.percolation, times));
    let voids = want(Measure::Voids).then(|| {
        times.time("voids", || {
            bed.as_2d()
                .map(|b2| voids::void_summary(b2, &voids::voids(b2, &contacts)))
        })
    });
    let orientation = want(Measure::Orientation).then(|| {
        times.time("orientation", || {
            orientation::orientation(bed, opts.angle_from)
        })
    });
    let summary = Summary {
        measures_left_out: opts.measures.left_out(),
        cake: cake.filter(|_| want(Measure::Packing)),
        packing,
        coordination,
        percolation,
        voids: voids.flatten(),
        orientation: orientation.flatten(),
        segregation: want(Measure::Segregation).then(|| {
            times.time("segregation", || {
                segregation::segregation(bed, d_max, &volumes)
            })
        }),
        ..Summary::default()
    };
    let mut summary = summary;
    match pore_space {
        Some(Ok(space)) => {
            summary.triangulation_seconds = Some(space.triangulation_seconds);
            summary.network_seconds = Some(space.network_seconds);
            summary.pores = want(Measure::Pores).then_some(space.pores);
            summary.permeability = space.permeability;
            summary.transport = space.transport;
            summary.pores_note = space.note;
            summary.pore_tables = Some(std::sync::Arc::new(space.tables));
            summary.warnings.extend(space.warning);
            match space.drainage {
                Some(Ok(d)) => {
                    summary.warnings.extend(d.warning.clone());
                    summary.drainage = Some(d.summary.clone());
                    summary.liquid = Some(std::sync::Arc::new(d));
                }
                Some(Err(why)) => {
                    if want(Measure::Agglomeration) {
                        summary.agglomeration_note = Some(format!("no drainage to dry: {why}"));
                    }
                    summary.drainage_note = Some(why);
                }
                None => {}
            }
            match space.drying {
                Some(Ok(d)) => {
                    summary.agglomeration = Some(d.summary.clone());
                    summary.dried = Some(std::sync::Arc::new(d));
                }
                Some(Err(why)) => summary.agglomeration_note = Some(why),
                None => {}
            }
        }
        Some(Err(why)) => summary.pores_note = Some(why),
        None => {}
    }
    (contacts, summary)
}

impl crate::config::AnalysisConfig {
    /// The options the analysis runs with for this `[analysis]` table.
    pub(crate) fn options(&self) -> AnalysisOptions {
        AnalysisOptions {
            bulk_min_bodies: self.bulk_min_bodies,
            angle_from: self.chain_angle_from,
            measures: self
                .measures
                .as_deref()
                .map_or_else(Measures::default_set, Measures::of),
            cake: CakeOptions {
                solid_density: self.solid_density,
                metres_per_unit: self.length_unit.map(|u| u.metres()),
            },
            flow: self.flow.options(),
            drainage: self.drainage.options(),
            drying: self.drying.options(),
            ..AnalysisOptions::new(self.contact_tol, self.large_radius)
        }
    }
}

impl crate::bed::AnyBed {
    /// The contacts between particles and with the walls, at this tolerance
    /// relative to the smaller radius of each pair.
    pub fn contacts(&self, contact_tol: Real) -> Contacts {
        crate::bed::each_dim!(self, b => find_contacts(b, contact_tol))
    }

    /// Every measure of the bed, with its contacts.
    pub fn analyze(&self, options: &AnalysisOptions) -> (Contacts, Summary) {
        crate::bed::each_dim!(self, b => analyze_with(b, options))
    }
}

/// The pore space and, when asked, the permeability; the cake's specific
/// resistance then comes from the network's `k_z`. `Err` says why there is none.
fn pore_measures<const D: usize>(
    bed: &Bed<D>,
    opts: &AnalysisOptions,
    bulk: Option<&packing::Region<D>>,
    cake: Option<&mut CakeSummary>,
    times: &mut StageTimes,
) -> Result<pores::PoreSpace, String> {
    // Overlapping spheres (DEM pours, scans) need no refusal: the network's
    // geometry takes their lenses out exactly (`pores::geometry`), and a
    // sphere inside another has no cell (`pores.hidden_particles`).
    let z = D - 1;
    let slab = match (opts.flow.slab, bulk) {
        (Some(s), _) => s,
        (None, Some(region)) => (region.lo[z], region.hi[z]),
        (None, None) => {
            let d = 2.0 * bed.r_max();
            return Err(format!(
                "the bed has no bulk slab for the pores and the permeability (it needs at least \
                 {} bodies at least {} from the floor and the sides and {} below the surface): \
                 a taller or wider box would do, or [analysis.flow] slab",
                opts.bulk_min_bodies,
                crate::math::display_length(2.0 * d),
                crate::math::display_length(3.0 * d)
            ));
        }
    };
    let d32 = cake.as_ref().and_then(|c| c.d32);
    let k_kc = cake.as_ref().and_then(|c| c.k_kozeny_carman);
    let flow = opts
        .measures
        .has(Measure::Permeability)
        .then_some(&opts.flow);
    // The slab's size in d32: the cake's, else the whole bed's.
    let d32_or_bed = d32.unwrap_or_else(|| {
        let (r3, r2) = bed
            .radii
            .iter()
            .fold((0.0, 0.0), |(a, b), r| (a + r * r * r, b + r * r));
        2.0 * r3 / r2
    });
    let agglomeration = opts.measures.has(Measure::Agglomeration);
    let drain =
        (opts.measures.has(Measure::Drainage) || agglomeration).then_some(pores::DrainageRequest {
            options: opts.drainage,
            metres_per_unit: opts.cake.metres_per_unit,
            d32: d32_or_bed,
            drying: agglomeration.then_some(opts.drying),
        });
    let mut space = pores::pore_space_timed(bed, slab, flow, drain.as_ref(), d32, k_kc, times)
        .map_err(|e| e.to_string())?;
    let d32 = d32_or_bed;
    let d_max = 2.0 * bed.r_max();
    space.warning = pores::check_slab(&mut space, &bed.container.size, slab, d32, d_max);
    if let (Some(c), Some(k)) = (cake, space.permeability.as_ref().and_then(|p| p.k_z)) {
        c.use_network_k(k);
    }
    Ok(space)
}

/// Coordination numbers: overall, in the bulk and per species.
fn coordination_summary<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    z: &[u32],
    in_bulk: &[bool],
    bulk_ok: bool,
) -> CoordinationSummary {
    // One entry per body, whatever its number of beads: (body, z, species).
    let mut per_body: Vec<(u32, u32, u32)> = (0..bed.len())
        .map(|i| (bed.bodies[i], z[i], bed.species[i]))
        .collect();
    per_body.sort_unstable_by_key(|e| e.0);
    per_body.dedup_by_key(|e| e.0);
    let bulk = |s: Option<u32>| {
        (0..bed.len())
            .filter(move |&i| in_bulk[i] && s.is_none_or(|s| bed.species[i] == s))
            .map(|i| z[i])
    };
    // Null, not 0, when the bulk is too small or holds none of these particles.
    let bulk_mean =
        |s: Option<u32>| (bulk_ok && bulk(s).next().is_some()).then(|| mean_of(bulk(s)));
    let by_species = (0..profile::species_count(bed) as u32)
        .map(|s| {
            let mine = || per_body.iter().filter(move |e| e.2 == s).map(|e| e.1);
            SpeciesCoordination {
                species: s,
                name: bed
                    .species_info
                    .get(s as usize)
                    .map_or_else(String::new, |i| i.name.clone()),
                bodies: mine().count() as u64,
                mean: mean_of(mine()),
                mean_bulk: bulk_mean(Some(s)),
                bulk_particles: bulk(Some(s)).count() as u64,
                histogram: count_histogram(mine()),
            }
        })
        .collect();
    let floor = contacts
        .walls
        .iter()
        .filter(|w| w.wall == crate::container::Wall::Floor)
        .count() as u64;
    CoordinationSummary {
        mean: mean_of(per_body.iter().map(|e| e.1)),
        mean_bulk: bulk_mean(None),
        bulk_particles: bulk(None).count() as u64,
        histogram: count_histogram(per_body.iter().map(|e| e.1)),
        histogram_bulk: count_histogram(bulk(None)),
        by_species,
        floor_contacts: floor,
        wall_contacts: contacts.walls.len() as u64 - floor,
    }
}

/// Number of distinct bodies with at least one particle flagged.
fn count_bodies<const D: usize>(bed: &Bed<D>, flagged: &[bool]) -> u64 {
    let mut bodies: Vec<u32> = (0..bed.len())
        .filter(|&i| flagged[i])
        .map(|i| bed.bodies[i])
        .collect();
    bodies.sort_unstable();
    bodies.dedup();
    bodies.len() as u64
}

/// Mean of counts, 0 for none (never NaN).
fn mean_of(values: impl Iterator<Item = u32>) -> Real {
    let (mut sum, mut n) = (0.0, 0usize);
    for v in values {
        sum += Real::from(v);
        n += 1;
    }
    if n == 0 {
        0.0
    } else {
        sum / n as Real
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use crate::math::Vector;
    use std::f64::consts::PI;

    /// Discs of diameter 1 on the unit square lattice filling a 10 × 10 box.
    fn square_lattice(periodic: bool) -> Bed<2> {
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 10.0]),
                periodic,
            },
            Vec::new(),
        );
        for j in 0..10 {
            for i in 0..10 {
                bed.push(Vector([i as Real + 0.5, j as Real + 0.5]), 0.5, 0);
            }
        }
        bed
    }

    #[test]
    fn square_lattice_summary() {
        let all = AnalysisOptions {
            bulk_min_bodies: 0,
            ..AnalysisOptions::new(1e-6, None)
        };
        let (contacts, s) = analyze_with(&square_lattice(false), &all);
        assert_eq!(contacts.pairs.len(), 2 * 10 * 9);
        assert!((s.packing.as_ref().unwrap().global - PI / 4.0).abs() < 1e-14);
        // Bulk: [2, 8] × [2, 7]: centres 2.5..7.5 by 2.5..6.5, all with 4 neighbours.
        assert!((s.packing.as_ref().unwrap().bulk.unwrap() - PI / 4.0).abs() < 1e-14);
        assert!(!s.packing.as_ref().unwrap().bulk_region_empty);
        assert_eq!(s.coordination.as_ref().unwrap().bulk_particles, 30);
        assert_eq!(s.packing.as_ref().unwrap().bulk_bodies, 30);
        assert_eq!(s.coordination.as_ref().unwrap().mean_bulk, Some(4.0));
        // Corners 2, edges 3, inside 4: 2 × 180 contacts / 100 discs.
        assert!((s.coordination.as_ref().unwrap().mean - 3.6).abs() < 1e-14);
        // Periodic: every disc has four neighbours.
        let (contacts, s) = analyze_with(&square_lattice(true), &all);
        assert_eq!(contacts.pairs.len(), 2 * 10 * 9 + 10);
        assert_eq!(s.coordination.as_ref().unwrap().bulk_particles, 50);
        assert_eq!(s.coordination.as_ref().unwrap().mean_bulk, Some(4.0));
        // 30 bodies is below the default minimum of 50: null, with the reason.
        let (_, s) = analyze(&square_lattice(false), 1e-6);
        assert_eq!(s.packing.as_ref().unwrap().bulk, None);
        assert_eq!(s.coordination.as_ref().unwrap().mean_bulk, None);
        assert_eq!(s.packing.as_ref().unwrap().bulk_bodies, 30);
        let why = s.packing.as_ref().unwrap().bulk_note.clone().unwrap();
        assert!(why.contains("30 bodies") && why.contains("50"), "{why}");
        let (_, s) = analyze(&square_lattice(true), 1e-6);
        assert_eq!(s.packing.as_ref().unwrap().bulk_bodies, 50);
        assert_eq!(s.coordination.as_ref().unwrap().mean_bulk, Some(4.0));
        assert_eq!(s.packing.as_ref().unwrap().bulk_note, None);
    }

    #[test]
    fn chains_count_once_per_body() {
        let mut bed = Bed::new(
            Container {
                size: Vector([20.0, 20.0]),
                periodic: false,
            },
            Vec::new(),
        );
        // A three-bead chain on the floor and two discs on it, one over each joint.
        for k in 0..3 {
            bed.push_bead(Vector([3.0 + 2.0 * k as Real, 1.0]), 1.0, 0, 0);
        }
        let h = 1.0 + 3f64.sqrt();
        bed.push(Vector([4.0, h]), 1.0, 0);
        bed.push(Vector([6.0, h]), 1.0, 0);
        let (contacts, s) = analyze(&bed, 1e-9);
        // Bead pairs: 2 per disc; the discs also touch each other.
        assert_eq!(contacts.pairs.len(), 5);
        // Bodies: the chain touches 2 bodies, each disc touches the chain and the
        // other disc.
        assert!((s.coordination.as_ref().unwrap().mean - 2.0).abs() < 1e-15);
        assert!(s.packing.as_ref().unwrap().bulk_region_empty);
        assert_eq!(s.packing.as_ref().unwrap().bulk, None);
        assert!(s.packing.as_ref().unwrap().bulk_note.is_some());
    }

    #[test]
    fn empty_bed_gives_zeros_not_nan() {
        let bed: Bed<3> = Bed::new(
            Container {
                size: Vector([10.0, 10.0, 10.0]),
                periodic: true,
            },
            Vec::new(),
        );
        let (contacts, s) = analyze(&bed, 1e-6);
        assert_eq!(contacts, Contacts::default());
        assert_eq!(s.packing.as_ref().unwrap().global, 0.0);
        assert_eq!(s.packing.as_ref().unwrap().bulk, None);
        assert!(s.packing.as_ref().unwrap().bulk_region_empty);
        assert_eq!(s.coordination.as_ref().unwrap().mean, 0.0);
        assert_eq!(s.coordination.as_ref().unwrap().mean_bulk, None);
        assert_eq!(s.coordination.as_ref().unwrap().bulk_particles, 0);
    }

    #[test]
    fn measures_left_out_are_absent_and_named() {
        let bed = square_lattice(false);
        let all = AnalysisOptions::default();
        let some = AnalysisOptions {
            measures: Measures::of(&[Measure::Coordination, Measure::Segregation]),
            ..AnalysisOptions::default()
        };
        let (c_all, s_all) = analyze_with(&bed, &all);
        let (c_some, s_some) = analyze_with(&bed, &some);
        assert_eq!(c_all, c_some);
        assert!(s_all.measures_left_out.is_empty());
        assert_eq!(
            s_some.measures_left_out,
            ["packing", "percolation", "voids", "orientation"]
        );
        assert_eq!(s_some.coordination, s_all.coordination);
        assert_eq!(s_some.segregation, s_all.segregation);
        assert!(s_some.packing.is_none() && s_some.percolation.is_none());
        assert!(s_some.voids.is_none() && s_all.voids.is_some());
        let json = serde_json::to_value(&s_some).unwrap();
        assert!(json.get("packing").is_none() && json.get("coordination").is_some());
        // Nothing chosen: the contacts only.
        let none = AnalysisOptions {
            measures: Measures::of(&[]),
            ..AnalysisOptions::default()
        };
        let (c_none, s_none) = analyze_with(&bed, &none);
        assert_eq!(c_none, c_all);
        assert_eq!(s_none.measures_left_out.len(), Measure::DEFAULT.len());
    }
}
