//! The pore space of a bed (`docs/reference/pores.md`): the regular triangulation of the
//! particle centres weighted by their squared radii, its cells (pores) and
//! facets (throats), their sizes, and the permeability from the Stokes flow
//! through the network.

pub mod drainage;
pub mod drying;
pub mod flow;
pub mod geometry;
pub mod network;
pub mod transport;
pub mod triangulation;

use super::StageTimes;
use crate::bed::Bed;
use crate::math::Real;
use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;

pub use flow::{AxisFlow, Flow};
pub use network::Network;

/// Settings of the pore space and flow (`[analysis.flow]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowOptions {
    /// Fluid viscosity `μ`.
    pub viscosity: Real,
    /// The axes to drive the flow along (x, y, z); `None`: z, and x and y on
    /// periodic beds.
    pub axes: Option<[bool; 3]>,
    /// The flow region `[z_lo, z_hi]`; `None`: the bulk slab.
    pub slab: Option<(Real, Real)>,
    /// Which length sets a throat's conductance.
    pub conductance: crate::config::Conductance,
    /// The constant factor on every throat's conductance.
    pub conductance_factor: Real,
}

impl Default for FlowOptions {
    fn default() -> Self {
        FlowOptions {
            viscosity: 1.0,
            axes: None,
            slab: None,
            conductance: crate::config::Conductance::default(),
            conductance_factor: crate::config::Conductance::default().default_factor(),
        }
    }
}

impl crate::config::FlowConfig {
    /// The options the flow runs with for this `[analysis.flow]` table (here,
    /// not in `config`, so that the config floor imports nothing above it).
    pub(crate) fn options(&self) -> FlowOptions {
        use crate::config::FlowAxis;
        FlowOptions {
            viscosity: self.viscosity,
            axes: self
                .axes
                .as_ref()
                .map(|list| [FlowAxis::X, FlowAxis::Y, FlowAxis::Z].map(|a| list.contains(&a))),
            slab: self.slab.map(|s| (s[0], s[1])),
            conductance: self.conductance,
            conductance_factor: self
                .conductance_factor
                .unwrap_or(self.conductance.default_factor()),
        }
    }
}

/// Percentiles of a size distribution.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct SizeDistribution {
    /// Number of pores or throats.
    pub count: u64,
    /// Mean by number.
    pub mean: Real,
    /// 10th, 35th, 50th and 90th percentiles by number.
    pub p10: Real,
    /// The size 35 % of them are smaller than (by number).
    pub p35: Real,
    /// Median by number.
    pub p50: Real,
    /// 90th percentile by number.
    pub p90: Real,
    /// The same percentiles weighted by void volume.
    pub by_void_volume: Percentiles,
}

/// Volume-weighted percentiles.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Percentiles {
    /// 10th percentile.
    pub p10: Real,
    /// 35th percentile.
    pub p35: Real,
    /// Median.
    pub p50: Real,
    /// 90th percentile.
    pub p90: Real,
}

/// `pores.*` keys of `summary.json`: the pores and throats of the slab.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct PoresSummary {
    /// The slab `[z_lo, z_hi]` the pores are counted in (power centres).
    pub slab: [Real; 2],
    /// Pore body radius (the sphere touching the cell's four spheres from
    /// outside), over the pores that have one.
    pub body_radius: SizeDistribution,
    /// Pores of the slab left out of `body_radius`: no sphere touches their
    /// four spheres from outside (spheres of very different sizes, about 2.3
    /// times or more, where the size changes faster across the cell than a
    /// sphere between them could follow); `body_radius` 0 in `pores.csv`.
    pub body_radius_undefined: u64,
    /// Constriction radius of the throats between two pores of the slab.
    pub constriction_radius: SizeDistribution,
    /// Constriction diameter 35 % of the constrictions are smaller than
    /// (by number): the granular filter design size `d_c35`; `None` (null)
    /// when the slab's cells enclose no volume (`note` says why).
    pub d_c35: Option<Real>,
    /// Void volume of the slab's cells over their volume: the network's
    /// porosity, to hold against `cake.porosity`; `None` (null) as `d_c35`.
    pub network_porosity: Option<Real>,
    /// Pores and throats in the whole network (all heights).
    pub network_pores: u64,
    /// Throats in the whole network.
    pub network_throats: u64,
    /// Particles with no cell (inside others' power cells; overlaps only).
    pub hidden_particles: u64,
    /// Cells whose spheres' sectors exceeded the cell (void clamped at 0).
    pub clamped_cells: u64,
    /// Cells of the slab whose overlapping spheres' void is not exact: three
    /// spheres sharing a point or a lens reaching another face of the cell
    /// (the void is then an upper bound, clamped to the cell), or a centre
    /// inside another sphere (`geometry`'s module docs). 0 on beds that do
    /// not overlap.
    pub overlap_inexact_cells: u64,
    /// Throats between pores of the slab whose fluid area, void or solid
    /// surface is not exact for the same reasons.
    pub overlap_inexact_throats: u64,
    /// Why a figure above is null, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// `permeability.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct PermeabilitySummary {
    /// Along x (periodic beds), length².
    pub k_x: Option<Real>,
    /// Along y (3D periodic beds).
    pub k_y: Option<Real>,
    /// Along z, through the slab.
    pub k_z: Option<Real>,
    /// The mean of the axes computed over `d32²` (`cake.d32`).
    pub k_over_d32_squared: Option<Real>,
    /// The mean of the axes over the Kozeny–Carman `k` of the bulk.
    pub k_over_kozeny_carman: Option<Real>,
    /// `k_z` over the mean of `k_x` and `k_y` (periodic beds); null where
    /// the slab is too thin for the side axes ([`SLAB_MIN_SIDE`]).
    pub anisotropy: Option<Real>,
    /// The anisotropy's standard uncertainty: the spread of `k_x` and `k_y`
    /// as the sampling error of an axis, and the thin slab's bias on the
    /// side axes (see [`check_slab`]).
    pub anisotropy_uncertainty: Option<Real>,
    /// The fluid viscosity used.
    pub viscosity: Real,
    /// Which length set the throats' conductances (`constriction` or
    /// `hydraulic_radius`; `[analysis.flow] conductance`).
    pub conductance: &'static str,
    /// The constant factor on every throat's conductance
    /// (`[analysis.flow] conductance_factor`).
    pub conductance_factor: Real,
    /// Each axis: permeability, flux, balance and pores solved.
    pub axes: Vec<AxisFlow>,
    /// Throats shorter than 1e-3 of their spheres' mean radius: their two
    /// pores share a power centre and were solved as one node.
    pub throats_merged: u64,
    /// The largest flux imbalance of the axes (inflow against outflow).
    pub imbalance: Real,
    /// Why a figure above is null, or not to be trusted, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// A pore as written to `pores.csv` (the same for 2D and 3D). Fixed-size
/// fields, no vectors: a row per pore of a 10^6-sphere bed made 1.9 GB of
/// small vectors.
#[derive(Clone, Debug, PartialEq)]
pub struct PoreRow {
    /// Particle ids of the vertices (the first `dim + 1`).
    pub particles: [u32; 4],
    /// Image shifts of the vertices (periodic beds; mirror codes on walls).
    pub images: [[i8; 2]; 4],
    /// Power centre (the first `dim` entries).
    pub centre: [Real; 3],
    /// Cell volume, void volume, body radius.
    pub volume: Real,
    /// Void volume of the cell.
    pub void_volume: Real,
    /// Pore body radius.
    pub body_radius: Real,
    /// True for the pores of the slab.
    pub in_slab: bool,
    /// Pressure along each solved axis, in the order of
    /// [`PoreTables::axes`] (unit gradient).
    pub pressure: [Real; 3],
}

/// A throat as written to `throats.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct ThroatRow {
    /// The two pores.
    pub pores: [u32; 2],
    /// Period shift of the second pore.
    pub shift: [i8; 2],
    /// Constriction radius.
    pub constriction_radius: Real,
    /// Hydraulic conductance.
    pub conductance: Real,
    /// Flux along each solved axis, first pore to second, in the order of
    /// [`PoreTables::axes`].
    pub flux: [Real; 3],
}

/// The pore network as tables for the files (`pores.csv`, `throats.csv`, the
/// VTK network), free of the dimension.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PoreTables {
    /// 2 or 3.
    pub dim: usize,
    /// Periodic sides (image shifts are periods) or walls (mirror images).
    pub periodic: bool,
    /// The solved axes, in the order of the pressure and flux columns.
    pub axes: Vec<&'static str>,
    /// Every pore.
    pub pores: Vec<PoreRow>,
    /// Every throat.
    pub throats: Vec<ThroatRow>,
    /// Per pore, where the liquid is at the drainage's reported pressure
    /// (state, cluster, liquid volume), when the drainage ran.
    pub liquid: Option<Vec<(drainage::PoreState, i64, Real)>>,
}

/// One column of a pore table.
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    /// Ids, counts, image shifts, flags.
    Int(Vec<i64>),
    /// Coordinates and measures.
    Float(Vec<Real>),
}

impl Column {
    /// Number of rows.
    pub(crate) fn len(&self) -> usize {
        match self {
            Column::Int(v) => v.len(),
            Column::Float(v) => v.len(),
        }
    }

    /// True for no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl PoreTables {
    /// Side axes whose image shifts are reported: x (and y in 3D) on
    /// periodic beds, none with walls.
    fn shift_axes(&self) -> usize {
        if self.periodic {
            self.dim - 1
        } else {
            0
        }
    }

    /// The columns of `pores.csv` (and of Python's `Bed.pores()`), in order.
    pub fn pore_columns(&self) -> Vec<(String, Column)> {
        let p = &self.pores;
        let int = |f: &dyn Fn(&PoreRow) -> i64| Column::Int(p.iter().map(f).collect());
        let float = |f: &dyn Fn(&PoreRow) -> Real| Column::Float(p.iter().map(f).collect());
        let mut out = vec![("id".to_string(), Column::Int((0..p.len() as i64).collect()))];
        for v in 0..=self.dim {
            out.push((format!("v{v}"), int(&|r| i64::from(r.particles[v]))));
        }
        for v in 0..=self.dim {
            for (a, axis) in AXES.iter().enumerate().take(self.shift_axes()) {
                out.push((format!("v{v}_s{axis}"), int(&|r| i64::from(r.images[v][a]))));
            }
        }
        for (a, axis) in AXES.iter().enumerate().take(self.dim) {
            out.push((axis.to_string(), float(&|r| r.centre[a])));
        }
        out.push(("volume".into(), float(&|r| r.volume)));
        out.push(("void_volume".into(), float(&|r| r.void_volume)));
        out.push(("body_radius".into(), float(&|r| r.body_radius)));
        out.push(("in_slab".into(), int(&|r| i64::from(r.in_slab))));
        for (k, axis) in self.axes.iter().enumerate() {
            out.push((format!("pressure_{axis}"), float(&|r| r.pressure[k])));
        }
        if let Some(liquid) = &self.liquid {
            // 0 outside the slab, 1 drained, 2 filled, 3 trapped.
            let code = |s: drainage::PoreState| match s {
                drainage::PoreState::Outside => 0,
                drainage::PoreState::Drained => 1,
                drainage::PoreState::Filled => 2,
                drainage::PoreState::Trapped => 3,
            };
            out.push((
                "filled".into(),
                Column::Int(
                    liquid
                        .iter()
                        .map(|l| {
                            i64::from(
                                l.0 == drainage::PoreState::Filled
                                    || l.0 == drainage::PoreState::Trapped,
                            )
                        })
                        .collect(),
                ),
            ));
            out.push((
                "liquid_state".into(),
                Column::Int(liquid.iter().map(|l| code(l.0)).collect()),
            ));
            out.push((
                "cluster".into(),
                Column::Int(liquid.iter().map(|l| l.1).collect()),
            ));
            out.push((
                "liquid".into(),
                Column::Float(liquid.iter().map(|l| l.2).collect()),
            ));
        }
        out
    }

    /// The columns of `throats.csv` (and of Python's `Bed.pores()`), in order.
    pub fn throat_columns(&self) -> Vec<(String, Column)> {
        let t = &self.throats;
        let int = |f: &dyn Fn(&ThroatRow) -> i64| Column::Int(t.iter().map(f).collect());
        let float = |f: &dyn Fn(&ThroatRow) -> Real| Column::Float(t.iter().map(f).collect());
        let mut out = vec![
            ("id".to_string(), Column::Int((0..t.len() as i64).collect())),
            ("pore_a".into(), int(&|r| i64::from(r.pores[0]))),
            ("pore_b".into(), int(&|r| i64::from(r.pores[1]))),
        ];
        for (a, axis) in AXES.iter().enumerate().take(self.shift_axes()) {
            out.push((format!("s{axis}"), int(&|r| i64::from(r.shift[a]))));
        }
        out.push((
            "constriction_radius".into(),
            float(&|r| r.constriction_radius),
        ));
        out.push(("conductance".into(), float(&|r| r.conductance)));
        for (k, axis) in self.axes.iter().enumerate() {
            out.push((format!("flux_{axis}"), float(&|r| r.flux[k])));
        }
        out
    }
}

/// What the pore measures found: their summaries and the tables for the files.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PoreSpace {
    /// `pores.*`.
    pub pores: PoresSummary,
    /// `permeability.*`, when asked for and solvable.
    pub permeability: Option<PermeabilitySummary>,
    /// Why the permeability is absent, when it is.
    pub note: Option<String>,
    /// The tables.
    pub tables: PoreTables,
    /// Wall time of the triangulation alone, seconds (every attempt, when
    /// the images had to reach further).
    pub triangulation_seconds: f64,
    /// Wall time of the network built on the triangulation, seconds.
    pub network_seconds: f64,
    /// The warning of a slab too small for its permeability ([`check_slab`]).
    pub warning: Option<String>,
    /// The drainage, when asked for; `Err` says why there is none.
    pub drainage: Option<Result<drainage::Drainage, String>>,
    /// The drying after it, when asked for; `Err` says why there is none.
    pub drying: Option<Result<drying::Drying, String>>,
    /// The formation factor and tortuosities, with the permeability.
    pub transport: Option<transport::TransportSummary>,
}

/// What the drainage needs beside the network: its settings, the length
/// unit (pressures in Pa) and the `d32` the pressures are reduced with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrainageRequest {
    /// `[analysis.drainage]`.
    pub options: drainage::DrainageOptions,
    /// Metres per unit of the bed's lengths.
    pub metres_per_unit: Option<Real>,
    /// The Sauter diameter the pressures are reduced with.
    pub d32: Real,
    /// `[analysis.drying]`, when the cake is dried after its drainage.
    pub drying: Option<drying::DryingOptions>,
}

/// Builds the pore network of `bed`, measures its pores and, when `flow` is
/// set, solves the flow. `slab` is the flow region; `d32` and `k_kc` the
/// cake's, for the ratios.
pub fn pore_space<const D: usize>(
    bed: &Bed<D>,
    slab: (Real, Real),
    flow: Option<&FlowOptions>,
    d32: Option<Real>,
    k_kc: Option<Real>,
) -> crate::error::Result<PoreSpace> {
    pore_space_timed(bed, slab, flow, None, d32, k_kc, &mut StageTimes::default())
}

/// [`pore_space`], timing its stages (`pores/triangulation`, `pores/network`,
/// `pores/flow`) into `times`.
pub fn pore_space_timed<const D: usize>(
    bed: &Bed<D>,
    slab: (Real, Real),
    flow: Option<&FlowOptions>,
    drain: Option<&DrainageRequest>,
    d32: Option<Real>,
    k_kc: Option<Real>,
    times: &mut StageTimes,
) -> crate::error::Result<PoreSpace> {
    let stages = |times: &StageTimes| {
        (
            times.total("pores/triangulation"),
            times.total("pores/network"),
        )
    };
    let (t0, n0) = stages(times);
    let mut net = network::network_timed(bed, slab, times)?;
    let (t1, n1) = stages(times);
    let (triangulation_seconds, network_seconds) = (t1 - t0, n1 - n0);
    let in_slab: Vec<bool> = net
        .pores
        .iter()
        .map(|p| p.centre[D - 1] >= slab.0 && p.centre[D - 1] <= slab.1)
        .collect();
    // The distributions' inputs go before the flow: at 10^6 spheres they
    // are 0.24 GB beside its peak.
    let pores = summary(&net, &in_slab, slab);
    let mut dried = None;
    let mut drainage = drain.map(|d| {
        let t = std::time::Instant::now();
        let out = drainage::drain_wet(bed, &net, slab, d.d32, d.metres_per_unit, &d.options);
        // Its stages, or the whole when it was refused.
        match &out {
            Ok((d, _)) => times.0.extend(d.seconds.iter().copied()),
            Err(_) => times.0.push(("pores/drainage", t.elapsed().as_secs_f64())),
        }
        if let (Some(options), Ok((drained, wet))) = (&d.drying, &out) {
            let t = std::time::Instant::now();
            dried = Some(drying::dry(
                bed,
                &net,
                slab,
                drained,
                wet,
                &d.options,
                options,
                d.metres_per_unit,
            ));
            times.0.push(("pores/drying", t.elapsed().as_secs_f64()));
        }
        out.map(|(d, _)| d)
    });
    let shapes = std::mem::take(&mut net.shapes);
    let mut note = None;
    let mut permeability = None;
    let mut solved: Option<Flow> = None;
    let mut transported = None;
    if let Some(options) = flow {
        let axes = flow_axes::<D>(bed.container.periodic, options.axes);
        let merge = flow::merged(&shapes);
        let diffusive = transport::diffusive_conductances(&shapes);
        let t = Instant::now();
        let size = &bed.container.size;
        let solved_flow = flow::solve(&net, shapes, size, slab, options, &axes);
        times.0.push(("pores/flow", t.elapsed().as_secs_f64()));
        match solved_flow {
            Ok(f) => {
                permeability = Some(permeability_summary::<D>(&f, options, d32, k_kc));
                let t = Instant::now();
                let porosity = pores.network_porosity;
                transported = Some(
                    transport::transport(&net, &merge, &diffusive, &f, &axes, size, slab, porosity)
                        .unwrap_or_else(|e| transport::TransportSummary {
                            note: Some(format!("the transport could not be solved ({e:?})")),
                            ..Default::default()
                        }),
                );
                let relative = drain.is_some_and(|d| d.options.relative_permeability);
                if let (Some(Ok(d)), true) = (drainage.as_mut(), relative) {
                    d.relative_permeability(&net, &merge, &f.conductance, &in_slab, size, slab);
                }
                times.0.push(("pores/transport", t.elapsed().as_secs_f64()));
                solved = Some(f);
            }
            Err(flow::FlowError::NoPath(axis)) => {
                note = Some(format!(
                    "no open path through the slab along {axis}: the permeability is 0 or the \
                     slab holds no connected pores"
                ))
            }
            Err(flow::FlowError::Solver(e)) => {
                return Err(crate::error::Error::Impossible(format!(
                    "permeability: the pressure equations could not be solved ({e:?})"
                )))
            }
        }
    } else {
        drop(shapes);
    }
    let mut tables = tables(bed, net, &in_slab, solved);
    if let Some(Ok(d)) = &drainage {
        tables.liquid = Some(d.pores.clone());
    }
    Ok(PoreSpace {
        transport: transported,
        drainage,
        drying: dried,
        pores,
        permeability,
        note,
        tables,
        triangulation_seconds,
        network_seconds,
        warning: None,
    })
}

/// The `pores.*` summary of the network's slab.
fn summary<const D: usize>(net: &Network<D>, in_slab: &[bool], slab: (Real, Real)) -> PoresSummary {
    let body: Vec<(Real, Real)> = net
        .pores
        .iter()
        .zip(in_slab)
        .filter(|e| *e.1)
        .map(|(p, _)| (p.body_radius, p.void_volume))
        .collect();
    let slab_pores = body.len();
    // A pore with no tangent sphere has no body radius (0 stood for it,
    // a step at 0 in `plot_pores`).
    let body: Vec<(Real, Real)> = body.into_iter().filter(|e| e.0 > 0.0).collect();
    let body_radius_undefined = (slab_pores - body.len()) as u64;
    let constriction: Vec<(Real, Real)> = net
        .throats
        .iter()
        .zip(&net.shapes)
        .filter(|(t, _)| in_slab[t.pores[0] as usize] && in_slab[t.pores[1] as usize])
        .map(|(t, s)| (t.constriction_radius, s.void_volume))
        .collect();
    let (void, volume) = net
        .pores
        .iter()
        .zip(in_slab)
        .filter(|e| *e.1)
        .fold((0.0, 0.0), |acc, (p, _)| {
            (acc.0 + p.void_volume, acc.1 + p.volume)
        });
    let constriction_dist = distribution(constriction);
    // The cells of centres on one plane (a single layer on the floor) are
    // flat: they enclose no volume, so neither a porosity nor a constriction
    // of the pore space is measured (0 would read as a closed bed).
    let flat = volume.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    let note = if slab_pores == 0 {
        Some("the slab holds no pore: the network's porosity and d_c35 are not defined".into())
    } else if flat {
        Some(format!(
            "the slab's {} cells enclose no volume (the particle centres lie on one plane): \
             the network's porosity and d_c35 are not defined",
            slab_pores
        ))
    } else if constriction_dist.count == 0 {
        Some("the slab holds no throat between two of its pores: d_c35 is not defined".into())
    } else {
        None
    };
    PoresSummary {
        slab: [slab.0, slab.1],
        body_radius: distribution(body),
        body_radius_undefined,
        d_c35: (!flat && constriction_dist.count > 0).then_some(2.0 * constriction_dist.p35),
        constriction_radius: constriction_dist,
        network_porosity: (!flat).then(|| void / volume),
        network_pores: net.pores.len() as u64,
        network_throats: net.throats.len() as u64,
        hidden_particles: net.hidden.len() as u64,
        clamped_cells: net
            .pores
            .iter()
            .filter(|p| p.void_volume <= 0.0 && p.volume > 0.0)
            .count() as u64,
        overlap_inexact_cells: net
            .overlap_inexact_pores
            .iter()
            .filter(|&&p| in_slab[p as usize])
            .count() as u64,
        overlap_inexact_throats: net
            .overlap_inexact_throats
            .iter()
            .filter(|&&t| {
                let [a, b] = net.throats[t as usize].pores;
                in_slab[a as usize] && in_slab[b as usize]
            })
            .count() as u64,
        note,
    }
}

/// The axes to solve: those asked, else z and the periodic side axes.
fn flow_axes<const D: usize>(periodic: bool, asked: Option<[bool; 3]>) -> Vec<usize> {
    let z = D - 1;
    match asked {
        Some(a) => {
            let mut out: Vec<usize> = (0..D - 1).filter(|&k| a[k]).collect();
            if a[2] {
                out.push(z);
            }
            out
        }
        None if periodic => (0..D).collect(),
        None => vec![z],
    }
}

fn permeability_summary<const D: usize>(
    f: &Flow,
    options: &FlowOptions,
    d32: Option<Real>,
    k_kc: Option<Real>,
) -> PermeabilitySummary {
    let get = |name: &str| f.axes.iter().find(|a| a.axis == name).and_then(|a| a.k);
    let (k_x, k_y, k_z) = (get("x"), get("y"), get("z"));
    // An axis whose balance failed has no `k`: neither has any figure made
    // from it (the mean of the axes, the anisotropy).
    let failed: Vec<&str> = f
        .axes
        .iter()
        .filter(|a| a.k.is_none())
        .map(|a| a.axis)
        .collect();
    let ks: Vec<Real> = f.axes.iter().filter_map(|a| a.k).collect();
    let mean =
        (!ks.is_empty() && failed.is_empty()).then(|| ks.iter().sum::<Real>() / ks.len() as Real);
    let sides: Vec<Real> = [k_x, k_y].into_iter().flatten().collect();
    let anisotropy = k_z
        .filter(|_| !sides.is_empty() && failed.is_empty())
        .and_then(|kz| {
            let side = sides.iter().sum::<Real>() / sides.len() as Real;
            (side > 0.0 && kz > 0.0).then(|| kz / side)
        });
    let note = (!failed.is_empty()).then(|| {
        let worst = f.axes.iter().map(|a| a.imbalance).fold(0.0, Real::max);
        format!(
            "the flux through the slab does not balance along {} (imbalance {worst:.3e}, more \
             than {:e}): no permeability is given along it, nor the figures made from it",
            failed.join(", "),
            flow::BALANCE
        )
    });
    PermeabilitySummary {
        k_x,
        k_y: if D == 3 { k_y } else { None },
        k_z,
        k_over_d32_squared: mean
            .zip(d32)
            .filter(|e| e.1 > 0.0)
            .map(|(k, d)| k / (d * d)),
        k_over_kozeny_carman: mean.zip(k_kc).filter(|e| e.1 > 0.0).map(|(k, kc)| k / kc),
        anisotropy,
        anisotropy_uncertainty: None,
        viscosity: options.viscosity,
        conductance: options.conductance.name(),
        conductance_factor: options.conductance_factor,
        axes: f.axes.clone(),
        throats_merged: f.merged,
        imbalance: f.axes.iter().map(|a| a.imbalance).fold(0.0, Real::max),
        note,
    }
}

/// The thinnest slab whose `k_z` is within a few percent of a thick slab's
/// of the same bed: 3 Sauter diameters `d32` and 2 largest diameters
/// `d_max` (BENCHMARKS.md, "How large a slab": equal spheres 1.3 % at
/// 3 `d32`; lognormal gsd 1.6, `d_max` = 2.4 `d32`, 4 % at 2 `d_max`).
pub const SLAB_MIN_Z: [Real; 2] = [3.0, 2.0];

/// The same for the side axes (x, y): 10 `d32` and 3 `d_max`. Along a
/// side axis the flow runs inside the slab and loses the half pores at its
/// two faces, about `0.5 d32 / thickness` of `k` (equal spheres: 13 % at
/// 4 `d32`, 6 % at 8, 3 % at 12), so the anisotropy is reported from here on.
pub const SLAB_MIN_SIDE: [Real; 2] = [10.0, 3.0];

/// The narrowest box side whose `k` is within the seed-to-seed spread
/// (3 %) of a wide box's: 4 `d32` and 2 `d_max`.
pub const SLAB_MIN_WIDTH: [Real; 2] = [4.0, 2.0];

/// Holds the permeability of `space` against the size of its slab
/// (`slab`, in a box `size`, a bed of Sauter diameter `d32` and largest
/// diameter `d_max`): below [`SLAB_MIN_Z`], [`SLAB_MIN_SIDE`] or
/// [`SLAB_MIN_WIDTH`] its `k` is not within a few percent of the bed's.
/// Returns the warning, and notes it under `permeability.note`; a `k` of 0
/// there (no pore path inside a slab thinner than its pores) and the
/// anisotropy become null, and the anisotropy gets its uncertainty where it
/// is given.
pub fn check_slab<const D: usize>(
    space: &mut PoreSpace,
    size: &crate::math::Vector<D>,
    slab: (Real, Real),
    d32: Real,
    d_max: Real,
) -> Option<String> {
    let k = space.permeability.as_mut()?;
    if !(d32 > 0.0 && d_max > 0.0) {
        return None;
    }
    let least = |rule: [Real; 2]| (rule[0] * d32).max(rule[1] * d_max);
    let thickness = slab.1 - slab.0;
    let width = (0..D - 1).map(|a| size[a]).fold(Real::INFINITY, Real::min);
    let (thick, wide) = (thickness / d32, width / d32);
    let has_side = k.axes.iter().any(|a| a.axis != "z");
    let has_z = k.axes.iter().any(|a| a.axis == "z");
    let narrow = width < least(SLAB_MIN_WIDTH);
    let thin_z = has_z && thickness < least(SLAB_MIN_Z);
    let thin_side = has_side && thickness < least(SLAB_MIN_SIDE);
    let mut notes = Vec::new();
    if thin_side || narrow {
        if let Some(a) = k.anisotropy.take() {
            notes.push(format!(
                "anisotropy {a:.3} not converged: the side axes' k is low by about {:.0} % in a \
                 slab {thick:.2} d32 thick",
                50.0 / thick
            ));
        }
    } else if let (Some(a), Some(x), Some(y)) = (k.anisotropy, k.k_x, k.k_y) {
        // The spread of the two side axes, the sampling error of one axis'
        // k, and the thin slab's bias on the side axes (0.5 d32 / thickness).
        let spread = (x - y).abs() / (x + y);
        let bias = 0.5 / thick;
        k.anisotropy_uncertainty = Some(a * (3.0 * spread * spread + bias * bias).sqrt());
    }
    if thin_z || thin_side || narrow {
        for axis in &mut k.axes {
            let thin = if axis.axis == "z" { thin_z } else { thin_side };
            let short = thin || narrow;
            if short && axis.k == Some(0.0) {
                axis.k = None;
                notes.push(format!(
                    "k_{} null: no pore path crosses a slab this thin along {}, 0 would not be the \
                     bed's",
                    axis.axis, axis.axis
                ));
            }
        }
        let get = |name: &str| k.axes.iter().find(|a| a.axis == name).and_then(|a| a.k);
        let kept = (get("x"), get("y"), get("z"));
        if kept != (k.k_x, k.k_y, k.k_z) {
            // The mean of the axes lost one of them.
            (k.k_x, k.k_y, k.k_z) = kept;
            k.k_over_d32_squared = None;
            k.k_over_kozeny_carman = None;
            k.anisotropy = None;
        }
    }
    let warning = (thin_z || thin_side || narrow).then(|| {
        let need = if has_side {
            least(SLAB_MIN_SIDE)
        } else {
            least(SLAB_MIN_Z)
        };
        let show = crate::math::display_length;
        let mut would_do = Vec::new();
        if thickness < need {
            would_do.push(format!(
                "a slab at least {} thick ({:.1} d32; a box {} taller)",
                show(need),
                need / d32,
                show(need - thickness)
            ));
        }
        if narrow {
            would_do.push(format!(
                "a box at least {} wide",
                show(least(SLAB_MIN_WIDTH))
            ));
        }
        format!(
            "permeability: the flow slab is {thick:.2} d32 thick in a box {wide:.1} d32 wide \
             ({} and {}), too small for k within a few percent of the bed's (BENCHMARKS.md, \
             \"How large a slab\"): {} would do",
            show(thickness),
            show(width),
            would_do.join(" and ")
        )
    });
    if let Some(w) = &warning {
        notes.insert(0, w.trim_start_matches("permeability: ").to_string());
    }
    if !notes.is_empty() {
        let joined = notes.join("; ");
        k.note = Some(match k.note.take() {
            Some(n) => format!("{n}; {joined}"),
            None => joined,
        });
    }
    warning
}

/// Percentiles by number and by weight of `(size, weight)` pairs.
fn distribution(mut v: Vec<(Real, Real)>) -> SizeDistribution {
    if v.is_empty() {
        return SizeDistribution::default();
    }
    // Stable, so the order (and the sums below) is the serial sort's; one
    // thread took about a second for the throats of 10^6 spheres.
    v.par_sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = v.len();
    let by_number = |q: Real| v[(((n - 1) as Real) * q).round() as usize].0;
    let total: Real = v.iter().map(|e| e.1.max(0.0)).sum();
    let by_weight = |q: Real| {
        if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return 0.0;
        }
        let mut acc = 0.0;
        for e in &v {
            acc += e.1.max(0.0);
            if acc >= q * total {
                return e.0;
            }
        }
        v[n - 1].0
    };
    SizeDistribution {
        count: n as u64,
        mean: v.iter().map(|e| e.0).sum::<Real>() / n as Real,
        p10: by_number(0.10),
        p35: by_number(0.35),
        p50: by_number(0.50),
        p90: by_number(0.90),
        by_void_volume: Percentiles {
            p10: by_weight(0.10),
            p35: by_weight(0.35),
            p50: by_weight(0.50),
            p90: by_weight(0.90),
        },
    }
}

/// Entry `i` of each axis' values (at most three axes), zeros after them.
fn per_axis(values: Option<&Vec<Vec<Real>>>, i: usize) -> [Real; 3] {
    std::array::from_fn(|k| values.and_then(|v| v.get(k)).map_or(0.0, |v| v[i]))
}

/// The tables, from the network and the flow they replace: the pores' rows
/// are made before the throats' and each source goes once its rows are
/// made, so the network, the flow and both tables are never in memory at
/// once (at 10^6 spheres that was 2.8 GB, at 10^5 the run's peak).
fn tables<const D: usize>(
    bed: &Bed<D>,
    net: Network<D>,
    in_slab: &[bool],
    flow: Option<Flow>,
) -> PoreTables {
    let Network {
        pores: net_pores,
        throats: net_throats,
        ..
    } = net;
    let (axes, pressure, conductance, throat_flux) = match flow {
        Some(f) => (
            f.axes.iter().map(|a| a.axis).collect(),
            Some(f.pressure),
            Some(f.conductance),
            Some(f.throat_flux),
        ),
        None => (Vec::new(), None, None, None),
    };
    let pores = net_pores
        .iter()
        .enumerate()
        .map(|(i, p)| PoreRow {
            particles: std::array::from_fn(|v| if v <= D { p.sites[v].particle } else { 0 }),
            images: std::array::from_fn(|v| if v <= D { p.sites[v].image } else { [0; 2] }),
            centre: std::array::from_fn(|a| p.centre.get(a).copied().unwrap_or(0.0)),
            volume: p.volume,
            void_volume: p.void_volume,
            body_radius: p.body_radius,
            in_slab: in_slab[i],
            pressure: per_axis(pressure.as_ref(), i),
        })
        .collect();
    drop((net_pores, pressure));
    let throats = net_throats
        .iter()
        .enumerate()
        .map(|(t, th)| ThroatRow {
            pores: th.pores,
            shift: th.shift,
            constriction_radius: th.constriction_radius,
            conductance: conductance.as_ref().map_or(0.0, |c| c[t]),
            flux: per_axis(throat_flux.as_ref(), t),
        })
        .collect();
    PoreTables {
        dim: D,
        periodic: bed.container.periodic,
        axes,
        pores,
        throats,
        liquid: None,
    }
}

#[cfg(test)]
mod tests;
