//! Primary drainage of the pore network: a gas displacing the wetting liquid
//! that fills the cake, as when a filter cake is deliquored by gas pressure
//! or suction (VDI 2762), and where the liquid stays.
//!
//! The sample is the flow's slab (the bulk slab unless `[analysis.flow]
//! slab` says otherwise), as a cake between a gas chamber and a filter
//! medium held wet: every pore above the slab is gas, every pore below is
//! the liquid reservoir the displaced liquid leaves by. The gas drains the
//! slab's pores by invasion percolation ([`invasion`]), each throat passing
//! it at its capillary entry pressure ([`entry`]); the liquid cut off from
//! the outlet is trapped, unless trapping is switched off (the liquid then
//! leaves through the films in the corners, the bound the literature
//! compares with). In the drained pores the liquid stays as pendular bridges
//! at the contacts ([`pendular`]), at the curvature the gas pressure sets.
//!
//! Assumptions, stated where a user reads the figures (docs/guide/drainage-and-drying.md):
//! quasi-static (capillary forces dominate: low capillary number, no
//! viscous pressure drop), a rigid bed, one contact angle, no evaporation,
//! gravity neglected across the slab (Bond number of the pores ≪ 1).
//!
//! Pressures are computed as curvatures `κ = P_c / γ` in the bed's length
//! unit and reported both as `P_c·d32/γ` (dimensionless, always) and in Pa
//! (with `[analysis] length_unit`).
// NaN-rejecting guards read `!(x > 0.0)`: true for NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bridge;
pub mod entry;
pub mod invasion;
pub mod msp;
pub mod pendular;

use super::network::{Network, Site};
use crate::bed::Bed;
use crate::math::Real;
use invasion::{Invasion, InvasionGraph, Sets};
use rayon::prelude::*;
use serde::Serialize;

/// Settings of the drainage (`[analysis.drainage]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrainageOptions {
    /// Surface tension of the liquid, N/m.
    pub surface_tension: Real,
    /// Contact angle of the liquid on the solid, radians, in `[0, π/2)`.
    pub contact_angle: Real,
    /// Liquid cut off from the outlet stays (true) or leaves by films.
    pub trapping: bool,
    /// How a throat's entry pressure follows from its shape.
    pub entry: EntryModel,
    /// Where the liquid is reported; `None`: twice the breakthrough
    /// pressure.
    pub state: Option<StatePressure>,
    /// Rows of the capillary pressure–saturation table.
    pub points: usize,
    /// Relative permeabilities along the curve (with the permeability).
    pub relative_permeability: bool,
}

impl Default for DrainageOptions {
    fn default() -> Self {
        DrainageOptions {
            surface_tension: WATER_SURFACE_TENSION,
            contact_angle: 0.0,
            trapping: true,
            entry: EntryModel::default(),
            state: None,
            points: DEFAULT_POINTS,
            relative_permeability: false,
        }
    }
}

/// The pressure the liquid is reported at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StatePressure {
    /// `P_c·d32/γ`.
    Reduced(Real),
    /// Pa (the bed's length unit known).
    Pascal(Real),
}

impl crate::config::DrainageConfig {
    /// The options the drainage runs with for this `[analysis.drainage]`.
    pub fn options(&self) -> DrainageOptions {
        DrainageOptions {
            surface_tension: self.surface_tension,
            contact_angle: self.contact_angle.to_radians(),
            trapping: self.trapping,
            entry: self.entry,
            state: match (self.pressure, self.reduced_pressure) {
                (Some(p), _) => Some(StatePressure::Pascal(p)),
                (None, Some(r)) => Some(StatePressure::Reduced(r)),
                (None, None) => None,
            },
            points: self.points,
            relative_permeability: self.relative_permeability,
        }
    }
}

/// Water at 20 °C against air, N/m (the default liquid: water on glass,
/// contact angle 0).
pub const WATER_SURFACE_TENSION: Real = 0.0728;

/// Rows of the drainage curve by default.
pub const DEFAULT_POINTS: usize = 60;

pub use crate::config::EntryModel;

/// One row of the capillary pressure–saturation curve (`drainage.csv`).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CurvePoint {
    /// `P_c·d32/γ`.
    pub pc_reduced: Real,
    /// `P_c` in Pa (`None` without a length unit).
    pub pc_pa: Option<Real>,
    /// Wetting saturation: liquid in filled pores, trapped clusters and
    /// pendular bridges over the slab's pore volume.
    pub saturation: Real,
    /// The part in pores still filled and joined to the outlet.
    pub connected: Real,
    /// The part in clusters cut off from the outlet.
    pub trapped: Real,
    /// The part in pendular bridges of drained pores.
    pub pendular: Real,
    /// Relative permeability of the liquid along z (every few rows; empty
    /// on the others, and without the permeability measure).
    pub k_rw: Option<Real>,
    /// Relative permeability of the gas along z.
    pub k_rg: Option<Real>,
}

/// A capillary pressure, two ways.
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq)]
pub struct Pressure {
    /// `P_c·d32/γ`.
    pub reduced: Real,
    /// In Pa (`None` without `[analysis] length_unit`).
    pub pa: Option<Real>,
}

/// Sizes of the liquid clusters cut off from the outlet.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Clusters {
    /// Number of clusters.
    pub count: u64,
    /// Pores in the largest.
    pub largest_pores: u64,
    /// Liquid volume of the largest over the slab's pore volume.
    pub largest_fraction: Real,
    /// Median pores per cluster (by number of clusters).
    pub median_pores: Real,
    /// Clusters of 1, 2, 3–4, 5–8, … pores (powers of two).
    pub pores_histogram: Vec<u64>,
}

/// `drainage.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct DrainageSummary {
    /// Surface tension, N/m.
    pub surface_tension: Real,
    /// Contact angle, degrees.
    pub contact_angle: Real,
    /// Whether liquid cut off from the outlet was kept.
    pub trapping: bool,
    /// The entry-pressure model (`msp` or `inscribed`).
    pub entry: &'static str,
    /// The `d32` the pressures are reduced with.
    pub d32: Real,
    /// Pores of the slab (the sample).
    pub pores: u64,
    /// Their void volume.
    pub pore_volume: Real,
    /// The capillary pressure at which the gas first reaches the outlet
    /// (the threshold pressure); `None` when it never does.
    pub breakthrough: Option<Pressure>,
    /// The wetting saturation just after breakthrough.
    pub saturation_at_breakthrough: Option<Real>,
    /// The lowest entry pressure met at the inlet face: where the gas
    /// first enters the sample.
    pub entry_pressure: Option<Pressure>,
    /// The pressure the liquid is reported at (`state` in `liquid.csv`).
    pub state: Option<Pressure>,
    /// The wetting saturation at `state` (filled, trapped and pendular).
    pub residual_saturation: Option<Real>,
    /// Its parts at `state`.
    pub residual_connected: Option<Real>,
    /// The trapped part at `state`.
    pub residual_trapped: Option<Real>,
    /// The pendular part at `state`.
    pub residual_pendular: Option<Real>,
    /// Liquid clusters cut off from the outlet at `state`.
    pub clusters: Clusters,
    /// Pendular bridges at `state`.
    pub bridges: u64,
    /// Mean bridges per particle of the slab at `state`.
    pub bridges_per_particle: Real,
    /// Drained pores whose bridges would hold more than the pore's void
    /// (the rings have merged: funicular); their liquid is the pore's void.
    pub funicular_pores: u64,
    /// The curve at the reduced pressures of [`table_pressures`], the same
    /// for every bed: ensembles average it point by point (with bands) and
    /// `compare` draws the groups' curves side by side.
    pub curve: FixedCurve,
    /// Why a figure above is null, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The saturation at fixed reduced pressures (`drainage.curve.*`).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct FixedCurve {
    /// `P_c·d32/γ`, [`table_pressures`].
    pub pc_reduced: Vec<Real>,
    /// Wetting saturation at each.
    pub saturation: Vec<Real>,
    /// Its part in pendular bridges.
    pub pendular: Vec<Real>,
}

/// The reduced pressures `P_c·d32/γ` of [`FixedCurve`]: 20 a decade from 1
/// to 100, which spans the drainage of sphere packs from the first entry
/// (about 4 for equal spheres) to past its end (a few times the
/// breakthrough, about 9), and of wider size distributions.
pub fn table_pressures() -> Vec<Real> {
    (0..=40).map(|k| 10f64.powf(k as Real / 20.0)).collect()
}

/// Where a pore's liquid is at the reported pressure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PoreState {
    /// Not a pore of the slab.
    #[default]
    Outside,
    /// Drained by the gas (pendular bridges may remain).
    Drained,
    /// Filled, joined to the outlet.
    Filled,
    /// Filled, cut off from the outlet.
    Trapped,
}

impl PoreState {
    /// The `state` column of `pores.csv`.
    pub fn name(self) -> &'static str {
        match self {
            PoreState::Outside => "",
            PoreState::Drained => "drained",
            PoreState::Filled => "filled",
            PoreState::Trapped => "trapped",
        }
    }
}

/// A pendular bridge, as written to `liquid.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct BridgeRow {
    /// The two particles.
    pub particles: [u32; 2],
    /// Periods the second lies from the first (periodic beds).
    pub shift: [i8; 2],
    /// Surface gap (negative: overlap).
    pub gap: Real,
    /// Liquid volume of the bridge inside the slab's pores (area in 2D).
    pub volume: Real,
    /// Neck radius.
    pub neck_radius: Real,
    /// Half-filling angle on the first and second particle, degrees.
    pub filling_angle: [Real; 2],
}

/// What the drainage found: the summary and the tables for the files.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drainage {
    /// `drainage.*`.
    pub summary: DrainageSummary,
    /// The capillary pressure–saturation curve.
    pub curve: Vec<CurvePoint>,
    /// Per network pore at `state`: its state, cluster id (-1: none; 0 the
    /// liquid joined to the outlet; 1… the trapped clusters, largest first)
    /// and liquid volume.
    pub pores: Vec<(PoreState, i64, Real)>,
    /// The pendular bridges at `state`.
    pub bridges: Vec<BridgeRow>,
    /// Liquid held in bridges per particle at `state` (half of each of its
    /// bridges), and bridge count per particle.
    pub per_particle: Vec<(Real, u32)>,
    /// Warnings (a slab too thin).
    pub warning: Option<String>,
    /// When each network pore drains (0 above the slab, `+∞` below).
    pub drains_at: Vec<Real>,
    /// Wall time of each stage (`pores/drainage/…`), for `packbed bench`.
    pub seconds: Vec<(&'static str, Real)>,
}

impl Drainage {
    /// The columns of `drainage.csv` without the relative permeabilities
    /// (for Python's `Bed.drainage()`; `pc_pa` only with a length unit).
    pub fn curve_columns(&self) -> Vec<(String, super::Column)> {
        use super::Column::Float;
        let c = &self.curve;
        let col = |f: &dyn Fn(&CurvePoint) -> Real| Float(c.iter().map(f).collect());
        let mut out = vec![("pc_reduced".to_string(), col(&|p| p.pc_reduced))];
        if c.iter().all(|p| p.pc_pa.is_some()) && !c.is_empty() {
            out.push(("pc_pa".into(), col(&|p| p.pc_pa.unwrap_or(0.0))));
        }
        out.push(("saturation".into(), col(&|p| p.saturation)));
        out.push(("connected".into(), col(&|p| p.connected)));
        out.push(("trapped".into(), col(&|p| p.trapped)));
        out.push(("pendular".into(), col(&|p| p.pendular)));
        out
    }

    /// The rows of the curve with relative permeabilities: `pc_reduced`,
    /// `saturation`, `k_rw`, `k_rg`.
    pub fn relative_columns(&self) -> Vec<(String, super::Column)> {
        use super::Column::Float;
        let rows: Vec<&CurvePoint> = self
            .curve
            .iter()
            .filter(|p| p.k_rw.is_some() && p.k_rg.is_some())
            .collect();
        let col = |f: &dyn Fn(&CurvePoint) -> Real| Float(rows.iter().map(|p| f(p)).collect());
        vec![
            ("pc_reduced".into(), col(&|p| p.pc_reduced)),
            ("saturation".into(), col(&|p| p.saturation)),
            ("k_rw".into(), col(&|p| p.k_rw.unwrap_or(0.0))),
            ("k_rg".into(), col(&|p| p.k_rg.unwrap_or(0.0))),
        ]
    }

    /// The columns of `liquid.csv` (the state column aside).
    pub fn bridge_columns(&self) -> Vec<(String, super::Column)> {
        use super::Column::{Float, Int};
        let b = &self.bridges;
        let int = |f: &dyn Fn(&BridgeRow) -> i64| Int(b.iter().map(f).collect());
        let float = |f: &dyn Fn(&BridgeRow) -> Real| Float(b.iter().map(f).collect());
        vec![
            ("particle_a".into(), int(&|r| i64::from(r.particles[0]))),
            ("particle_b".into(), int(&|r| i64::from(r.particles[1]))),
            ("sx".into(), int(&|r| i64::from(r.shift[0]))),
            ("sy".into(), int(&|r| i64::from(r.shift[1]))),
            ("gap".into(), float(&|r| r.gap)),
            ("volume".into(), float(&|r| r.volume)),
            ("neck_radius".into(), float(&|r| r.neck_radius)),
            ("filling_angle_a".into(), float(&|r| r.filling_angle[0])),
            ("filling_angle_b".into(), float(&|r| r.filling_angle[1])),
        ]
    }
}

/// Rows of the curve between two relative permeabilities: each costs two
/// solves of the flow.
pub const RELATIVE_EVERY: usize = 6;

impl Drainage {
    /// Fills `k_rw` and `k_rg` of every [`RELATIVE_EVERY`]th row of the
    /// curve (and its last): the flow along z through the throats whose two
    /// pores hold the phase, over the flow through all of them. Pores off
    /// the slab (`in_slab` false) hold both phases: the sample sits between
    /// reservoirs of both, as in a steady-state measurement. Throat
    /// conductances `g`, merged throats `merge`, as the flow's. Film flow of
    /// the liquid in drained pores is left out.
    pub fn relative_permeability<const D: usize>(
        &mut self,
        net: &Network<D>,
        merge: &[bool],
        g: &[Real],
        in_slab: &[bool],
        size: &crate::math::Vector<D>,
        slab: (Real, Real),
    ) {
        let k_of = |open: &dyn Fn(usize) -> bool| -> Option<Real> {
            let c: Vec<Real> = g
                .iter()
                .enumerate()
                .map(|(t, &g)| if open(t) { g } else { 0.0 })
                .collect();
            super::flow::solve_z(net, merge, &c, size, slab)
                .ok()
                .and_then(|(f, _)| f.k)
        };
        let Some(k) = k_of(&|_| true).filter(|&k| k > 0.0) else {
            return;
        };
        let d32 = self.summary.d32;
        let last = self.curve.len().saturating_sub(1);
        for i in (0..self.curve.len()).filter(|&i| i % RELATIVE_EVERY == 0 || i == last) {
            let kappa = self.curve[i].pc_reduced / d32;
            let drains_at = &self.drains_at;
            let wet = |p: u32| !in_slab[p as usize] || !(drains_at[p as usize] <= kappa);
            let dry = |p: u32| !in_slab[p as usize] || drains_at[p as usize] <= kappa;
            let both = |t: usize, f: &dyn Fn(u32) -> bool| {
                let th = &net.throats[t];
                f(th.pores[0]) && f(th.pores[1])
            };
            self.curve[i].k_rw = k_of(&|t| both(t, &wet)).map(|w| w / k);
            self.curve[i].k_rg = k_of(&|t| both(t, &dry)).map(|w| w / k);
        }
    }
}

/// Why drainage cannot run on this bed: a one-line reason.
pub type Refusal = String;

/// Checks the options, naming the keys of `[analysis.drainage]`.
pub fn check_options(o: &DrainageOptions) -> Result<(), Refusal> {
    if !(o.surface_tension.is_finite() && o.surface_tension > 0.0) {
        return Err(format!(
            "analysis.drainage.surface_tension must be a positive number of N/m, got {}",
            o.surface_tension
        ));
    }
    let deg = o.contact_angle.to_degrees();
    if !(o.contact_angle.is_finite() && o.contact_angle >= 0.0) {
        return Err(format!(
            "analysis.drainage.contact_angle must be between 0 and 90 degrees, got {deg}"
        ));
    }
    if o.contact_angle >= std::f64::consts::FRAC_PI_2 {
        return Err(format!(
            "analysis.drainage.contact_angle {deg} degrees: at 90 degrees or more the liquid does \
             not wet the solid and gas displacing it is not a drainage (imbibition of the gas)"
        ));
    }
    Ok(())
}

/// The sites of the facet a throat crosses: those its two pores share (the
/// second pore's shifted by the throat's periods).
pub fn facet_sites<const D: usize>(net: &Network<D>, throat: usize) -> [Site; 3] {
    let th = &net.throats[throat];
    let a = &net.pores[th.pores[0] as usize].sites;
    let b = &net.pores[th.pores[1] as usize].sites;
    let shifted = |s: Site| Site {
        particle: s.particle,
        image: [
            s.image[0].saturating_add(th.shift[0]),
            s.image[1].saturating_add(th.shift[1]),
        ],
    };
    let mut out = [a[0]; 3];
    let mut k = 0;
    for &s in &a[..=D] {
        if k < D && b[..=D].iter().any(|&t| shifted(t) == s) {
            out[k] = s;
            k += 1;
        }
    }
    out
}

/// Where each pore of the network lies against the slab.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Below,
    In,
    Above,
}

/// Drains the slab `[z_lo, z_hi]` of `net`, the network of `bed`, and finds
/// where the liquid stays. `d32` reduces the pressures; `metres_per_unit`
/// gives them in Pa.
#[cfg(test)]
pub fn drain<const D: usize>(
    bed: &Bed<D>,
    net: &Network<D>,
    slab: (Real, Real),
    d32: Real,
    metres_per_unit: Option<Real>,
    options: &DrainageOptions,
) -> Result<Drainage, Refusal> {
    drain_wet(bed, net, slab, d32, metres_per_unit, options).map(|(d, _)| d)
}

/// What the drying of the drained cake starts from beside [`Drainage`]:
/// the pairs that may hold bridges and the curvature the liquid is
/// reported at (`None` when there is none).
pub struct Wet {
    /// The candidate bridges.
    pub pendular: pendular::Pendular,
    /// `P_c / γ` of the reported state.
    pub kappa: Option<Real>,
    /// The entry curvature of every throat the gas may pass into or within
    /// the slab (`+∞` for the others).
    pub entry: Vec<Real>,
}

/// [`drain`], with what the drying needs.
pub fn drain_wet<const D: usize>(
    bed: &Bed<D>,
    net: &Network<D>,
    slab: (Real, Real),
    d32: Real,
    metres_per_unit: Option<Real>,
    options: &DrainageOptions,
) -> Result<(Drainage, Wet), Refusal> {
    check_options(options)?;
    let z = D - 1;
    let side: Vec<Side> = net
        .pores
        .iter()
        .map(|p| {
            if p.centre[z] < slab.0 {
                Side::Below
            } else if p.centre[z] > slab.1 {
                Side::Above
            } else {
                Side::In
            }
        })
        .collect();
    // The sample's pores, numbered in network order.
    let mut index = vec![u32::MAX; net.pores.len()];
    let mut members: Vec<u32> = Vec::new();
    for (p, s) in side.iter().enumerate() {
        if *s == Side::In {
            index[p] = members.len() as u32;
            members.push(p as u32);
        }
    }
    if members.is_empty() {
        return Err(
            "drainage: the slab holds no pore (a taller bed or [analysis.flow] slab)".into(),
        );
    }
    let mut clock = Clock::start();
    let cos = options.contact_angle.cos();
    // Entry curvatures (P_e / γ) of every throat, on every core.
    // Only the throats the gas may pass into or within the slab count.
    let entry: Vec<Real> = (0..net.throats.len())
        .into_par_iter()
        .map(|t| {
            let th = &net.throats[t];
            let (a, b) = (side[th.pores[0] as usize], side[th.pores[1] as usize]);
            let wanted = matches!(
                (a, b),
                (Side::In, Side::In) | (Side::In, Side::Above) | (Side::Above, Side::In)
            );
            if wanted {
                entry::entry_curvature(bed, net, t, options.entry, cos)
            } else {
                Real::INFINITY
            }
        })
        .collect();
    clock.lap("pores/drainage/entries");
    // The lowest entry into the slab: where the curve starts, and the
    // lowest curvature a bridge is asked for at.
    let first_entry = net
        .throats
        .par_iter()
        .zip(&entry)
        .filter(|(th, _)| {
            let (a, b) = (side[th.pores[0] as usize], side[th.pores[1] as usize]);
            matches!((a, b), (Side::In, Side::Above) | (Side::Above, Side::In))
        })
        .map(|(_, &e)| e)
        .min_by(Real::total_cmp)
        .ok_or_else(|| {
            "drainage: no pore of the slab opens to the gas above it (the slab reaches the top \
             of the bed): lower [analysis.flow] slab's top"
                .to_string()
        })?;
    // The invasion is serial (each step depends on the last) and the
    // candidate bridges are not (pair by pair): the bridges are built on
    // the cores the invasion leaves idle. Both are deterministic, so the
    // result does not depend on how the work interleaves.
    let in_slab = side_in(&side);
    let (graphed, pendular) = rayon::join(
        || -> Result<_, Refusal> {
            let graph = invasion_graph(net, &side, &index, &entry, members.len())?;
            let adjacency = invasion::Adjacency::new(&graph);
            let invasion = invasion::invade_on(&graph, &adjacency, options.trapping);
            Ok((graph, adjacency, invasion))
        },
        || pendular::Pendular::new(bed, net, &in_slab, options.contact_angle, 0.8 * first_entry),
    );
    let (graph, adjacency, invasion) = graphed?;
    let voids: Vec<Real> = members
        .iter()
        .map(|&p| net.pores[p as usize].void_volume.max(0.0))
        .collect();
    let pore_volume: Real = voids.iter().sum();
    let scale = Scale {
        d32,
        gamma: options.surface_tension,
        metres_per_unit,
    };

    // When each network pore drains (below: never; above: gas from the start).
    let drains_at: Vec<Real> = side
        .iter()
        .zip(&index)
        .map(|(s, &i)| match s {
            Side::Below => Real::INFINITY,
            Side::Above => 0.0,
            Side::In => invasion.drains_at[i as usize],
        })
        .collect();
    let breakthrough = invasion.breakthrough;
    clock.lap("pores/drainage/invasion+bridges");
    let state_kappa =
        match (options.state, breakthrough) {
            (Some(StatePressure::Reduced(r)), _) => Some(r / d32),
            (Some(StatePressure::Pascal(p)), _) => match metres_per_unit {
                Some(m) => Some(p * m / options.surface_tension),
                None => return Err(
                    "drainage: a pressure in Pa needs [analysis] length_unit, the length of one \
                     unit of the bed"
                        .into(),
                ),
            },
            (None, Some(k)) => Some(2.0 * k),
            (None, None) => None,
        };
    // The curve's pressures: from below the first entry to past the end of
    // drainage, with the breakthrough itself.
    let mut curve_kappas = curve_pressures(&invasion, &voids, first_entry, options.points);
    // The fixed table's pressures join the curve (below its start nothing has
    // drained: the saturation there is 1 without computing).
    let table: Vec<Real> = table_pressures().iter().map(|r| r / d32).collect();
    let start = curve_kappas.first().copied().unwrap_or(Real::INFINITY);
    curve_kappas.extend(table.iter().copied().filter(|&k| k >= start));
    // And the pressure the liquid is reported at: its row is the summary's.
    curve_kappas.extend(state_kappa.filter(|&k| k >= start && k.is_finite()));
    curve_kappas.sort_by(Real::total_cmp);
    curve_kappas.dedup();
    // The whole curve in two sweeps: the liquid's split in one pass back
    // through the pressures, the bridges edge by edge.
    // (The split is a serial union–find; the bridges' totals take the other
    // cores meanwhile.)
    let (split, bridged) = rayon::join(
        || {
            invasion::liquid_split_on(
                &graph,
                &adjacency,
                &invasion.drains_at,
                &voids,
                &curve_kappas,
                options.trapping,
            )
        },
        || pendular.totals(&drains_at, &curve_kappas, &voids),
    );
    let curve: Vec<CurvePoint> = curve_kappas
        .iter()
        .zip(split.iter().zip(&bridged))
        .map(|(&kappa, (&(connected, trapped), &pend))| {
            curve_point(&scale, kappa, [connected, trapped, pend], pore_volume)
        })
        .collect();
    clock.lap("pores/drainage/curve");
    let mut summary = DrainageSummary {
        surface_tension: options.surface_tension,
        contact_angle: options.contact_angle.to_degrees(),
        trapping: options.trapping,
        entry: options.entry.name(),
        d32,
        pores: members.len() as u64,
        pore_volume,
        entry_pressure: first_entry.is_finite().then(|| scale.pressure(first_entry)),
        breakthrough: breakthrough.map(|k| scale.pressure(k)),
        curve: fixed_curve(&curve_kappas, &curve, d32),
        ..DrainageSummary::default()
    };
    // The breakthrough is a row of the curve.
    summary.saturation_at_breakthrough = breakthrough.and_then(|k| {
        let i = curve_kappas.binary_search_by(|x| x.total_cmp(&k)).ok()?;
        Some(curve[i].saturation)
    });
    let mut out = Drainage {
        pores: vec![(PoreState::Outside, -1, 0.0); net.pores.len()],
        per_particle: vec![(0.0, 0); bed.len()],
        ..Drainage::default()
    };
    if breakthrough.is_none() {
        summary.note = Some(
            "the gas never reaches the bottom of the slab (no open path of throats through it): \
             no breakthrough; the liquid is reported at the pressure asked for, if any"
                .into(),
        );
    }
    if let Some(kappa) = state_kappa {
        // The clusters' union–find is serial; the bridges take the other cores.
        let (at, (pend, bridges)) = rayon::join(
            || state_at(&graph, &invasion, &voids, kappa, options.trapping),
            || {
                (
                    pendular.volumes(&drains_at, kappa, &members, &voids),
                    pendular.bridges(&drains_at, kappa),
                )
            },
        );
        let p = point(&scale, kappa, &at, &voids, pend.total, pore_volume);
        summary.state = Some(scale.pressure(kappa));
        summary.residual_saturation = Some(p.saturation);
        summary.residual_connected = Some(p.connected);
        summary.residual_trapped = Some(p.trapped);
        summary.residual_pendular = Some(p.pendular);
        summary.clusters = clusters(&at, &voids, pore_volume);
        summary.funicular_pores = pend.funicular;
        for (i, &p) in members.iter().enumerate() {
            let liquid = if at.liquid[i] {
                voids[i]
            } else {
                pend.per_pore[i]
            };
            let state = if !at.liquid[i] {
                PoreState::Drained
            } else if at.cluster[i] == 0 {
                PoreState::Filled
            } else {
                PoreState::Trapped
            };
            out.pores[p as usize] = (state, at.cluster[i], liquid);
        }
        for b in &bridges {
            for &particle in &b.particles {
                let e = &mut out.per_particle[particle as usize];
                e.0 += 0.5 * b.volume;
                e.1 += 1;
            }
        }
        summary.bridges = bridges.len() as u64;
        let in_slab = (0..bed.len())
            .filter(|&i| {
                let h = bed.centres[i].0[z];
                h >= slab.0 && h <= slab.1
            })
            .count();
        summary.bridges_per_particle = if in_slab > 0 {
            2.0 * bridges.len() as Real / in_slab as Real
        } else {
            0.0
        };
        out.bridges = bridges;
    }
    let thickness = (slab.1 - slab.0) / d32;
    if thickness < MIN_THICKNESS {
        out.warning = Some(format!(
            "drainage: the slab is {thickness:.1} d32 thick, under {MIN_THICKNESS} d32: the \
             breakthrough pressure of so thin a sample is lower than a cake's (the gas finds a \
             path through few pores), give a taller bed or [analysis.flow] slab"
        ));
    }
    clock.lap("pores/drainage/state");
    out.summary = summary;
    out.curve = curve;
    out.drains_at = drains_at;
    out.seconds = clock.laps;
    Ok((
        out,
        Wet {
            pendular,
            kappa: state_kappa,
            entry,
        },
    ))
}

/// The slab's pores and throats as the gas sees them: `index` numbers the
/// slab's pores (`members` of them), `entry` is every throat's entry
/// curvature. A throat into the slab from above is an inlet; a pore with a
/// throat to the pores below is at the outlet.
fn invasion_graph<const D: usize>(
    net: &Network<D>,
    side: &[Side],
    index: &[u32],
    entry: &[Real],
    members: usize,
) -> Result<InvasionGraph, Refusal> {
    let mut graph = InvasionGraph {
        pores: members,
        outlet: vec![false; members],
        ..InvasionGraph::default()
    };
    for (t, th) in net.throats.iter().enumerate() {
        let (a, b) = (th.pores[0] as usize, th.pores[1] as usize);
        match (side[a], side[b]) {
            (Side::In, Side::In) => graph.throats.push((index[a], index[b], entry[t])),
            (Side::In, Side::Above) => graph.inlets.push((index[a], entry[t])),
            (Side::Above, Side::In) => graph.inlets.push((index[b], entry[t])),
            (Side::In, Side::Below) => graph.outlet[index[a] as usize] = true,
            (Side::Below, Side::In) => graph.outlet[index[b] as usize] = true,
            _ => {}
        }
    }
    if !graph.outlet.iter().any(|&o| o) {
        return Err(
            "drainage: no pore of the slab opens to the liquid below it, the bed has no outlet \
             (the slab reaches the floor): raise [analysis.flow] slab's bottom"
                .into(),
        );
    }
    Ok(graph)
}

/// Wall times of the stages, one lap each.
struct Clock {
    last: std::time::Instant,
    laps: Vec<(&'static str, Real)>,
}

impl Clock {
    fn start() -> Clock {
        Clock {
            last: std::time::Instant::now(),
            laps: Vec::new(),
        }
    }

    fn lap(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        self.laps.push((name, (now - self.last).as_secs_f64()));
        self.last = now;
    }
}

/// The thinnest slab, in `d32`, whose breakthrough is read as the cake's.
pub const MIN_THICKNESS: Real = 5.0;

fn side_in(side: &[Side]) -> Vec<bool> {
    side.iter().map(|&s| s == Side::In).collect()
}

/// Converts curvatures to the reported pressures.
struct Scale {
    d32: Real,
    gamma: Real,
    metres_per_unit: Option<Real>,
}

impl Scale {
    fn pressure(&self, kappa: Real) -> Pressure {
        Pressure {
            reduced: kappa * self.d32,
            pa: self.metres_per_unit.map(|m| kappa * self.gamma / m),
        }
    }
}

/// The liquid of the sample at one pressure: which pores hold it, and their
/// clusters (0: joined to the outlet; 1…: cut off, largest first).
struct State {
    liquid: Vec<bool>,
    cluster: Vec<i64>,
}

/// The sample at curvature `kappa`: a pore is liquid when it has not drained
/// by then; the liquid pores are grouped by the throats between them.
///
/// Without trapping the liquid cut off through the pores is joined to the
/// outlet by the films in the corners (the model's meaning of no trapping):
/// it is all cluster 0.
fn state_at(
    g: &InvasionGraph,
    inv: &Invasion,
    voids: &[Real],
    kappa: Real,
    trapping: bool,
) -> State {
    let n = g.pores;
    let liquid: Vec<bool> = (0..n).map(|p| !(inv.drains_at[p] <= kappa)).collect();
    let mut sets = Sets::new(n + 1);
    if !trapping {
        for p in 0..n {
            if liquid[p] {
                sets.union(p, n);
            }
        }
    }
    for &(a, b, _) in &g.throats {
        if liquid[a as usize] && liquid[b as usize] {
            sets.union(a as usize, b as usize);
        }
    }
    for p in 0..n {
        if liquid[p] && g.outlet[p] {
            sets.union(p, n);
        }
    }
    let outlet = sets.find(n);
    // Cut-off clusters by volume, largest first (ties by first pore).
    let mut volume: Vec<(Real, usize)> = Vec::new();
    let mut slot = vec![usize::MAX; n + 1];
    for p in 0..n {
        if !liquid[p] {
            continue;
        }
        let r = sets.find(p);
        if r == outlet {
            continue;
        }
        if slot[r] == usize::MAX {
            slot[r] = volume.len();
            volume.push((0.0, p));
        }
        volume[slot[r]].0 += voids[p];
    }
    let mut rank: Vec<usize> = (0..volume.len()).collect();
    rank.sort_by(|&a, &b| {
        volume[b]
            .0
            .total_cmp(&volume[a].0)
            .then(volume[a].1.cmp(&volume[b].1))
    });
    let mut id_of = vec![0i64; volume.len()];
    for (k, &c) in rank.iter().enumerate() {
        id_of[c] = k as i64 + 1;
    }
    let cluster = (0..n)
        .map(|p| {
            if !liquid[p] {
                -1
            } else {
                let r = sets.find(p);
                if r == outlet {
                    0
                } else {
                    id_of[slot[r]]
                }
            }
        })
        .collect();
    State { liquid, cluster }
}

/// The row of the curve at `kappa` from the sample's liquid at `at`.
fn point(
    scale: &Scale,
    kappa: Real,
    at: &State,
    voids: &[Real],
    pendular: Real,
    pore_volume: Real,
) -> CurvePoint {
    let (mut connected, mut trapped) = (0.0, 0.0);
    for (&c, &v) in at.cluster.iter().zip(voids) {
        match c {
            0 => connected += v,
            c if c > 0 => trapped += v,
            _ => {}
        }
    }
    curve_point(scale, kappa, [connected, trapped, pendular], pore_volume)
}

/// The row of the curve at `kappa` from the liquid's volumes `[joined to
/// the outlet, cut off, in bridges]`.
fn curve_point(scale: &Scale, kappa: Real, liquid: [Real; 3], pore_volume: Real) -> CurvePoint {
    let [connected, trapped, pendular] = liquid;
    let frac = |v: Real| {
        if pore_volume > 0.0 {
            v / pore_volume
        } else {
            0.0
        }
    };
    let p = scale.pressure(kappa);
    CurvePoint {
        pc_reduced: p.reduced,
        pc_pa: p.pa,
        saturation: frac(connected + trapped + pendular),
        connected: frac(connected),
        trapped: frac(trapped),
        pendular: frac(pendular),
        k_rw: None,
        k_rg: None,
    }
}

fn clusters(at: &State, voids: &[Real], pore_volume: Real) -> Clusters {
    let count = at.cluster.iter().copied().max().unwrap_or(0).max(0) as usize;
    let mut pores = vec![0u64; count + 1];
    let mut volume = vec![0.0; count + 1];
    for (p, &c) in at.cluster.iter().enumerate() {
        if c > 0 {
            pores[c as usize] += 1;
            volume[c as usize] += voids[p];
        }
    }
    let mut sizes: Vec<u64> = pores[1..].to_vec();
    sizes.sort_unstable();
    let median = if sizes.is_empty() {
        0.0
    } else if sizes.len() % 2 == 1 {
        sizes[sizes.len() / 2] as Real
    } else {
        0.5 * (sizes[sizes.len() / 2 - 1] + sizes[sizes.len() / 2]) as Real
    };
    let mut histogram: Vec<u64> = Vec::new();
    for &s in &sizes {
        let bin = (u64::BITS - s.leading_zeros() - 1) as usize;
        if histogram.len() <= bin {
            histogram.resize(bin + 1, 0);
        }
        histogram[bin] += 1;
    }
    Clusters {
        count: count as u64,
        largest_pores: if count > 0 { pores[1] } else { 0 },
        largest_fraction: if count > 0 && pore_volume > 0.0 {
            volume[1] / pore_volume
        } else {
            0.0
        },
        median_pores: median,
        pores_histogram: histogram,
    }
}

/// The curve at the table's reduced pressures: each is a row of `curve`
/// (at curvatures `kappas`), or lies below its start, where the sample is
/// full.
fn fixed_curve(kappas: &[Real], curve: &[CurvePoint], d32: Real) -> FixedCurve {
    let mut out = FixedCurve::default();
    for r in table_pressures() {
        let k = r / d32;
        let (s, p) = match kappas.binary_search_by(|x| x.total_cmp(&k)) {
            Ok(i) => (curve[i].saturation, curve[i].pendular),
            Err(_) => (1.0, 0.0),
        };
        out.pc_reduced.push(r);
        out.saturation.push(s);
        out.pendular.push(p);
    }
    out
}

/// The curvatures the curve is written at: `points` evenly spaced from
/// 0.8 of the lowest inlet entry to past the end of drainage (the curvature
/// by which 99.5 % of the volume that ever drains has drained, and at
/// least twice the breakthrough), with the breakthrough itself.
fn curve_pressures(inv: &Invasion, voids: &[Real], first_entry: Real, points: usize) -> Vec<Real> {
    let mut drained: Vec<(Real, Real)> = inv
        .drains_at
        .iter()
        .zip(voids)
        .filter(|e| e.0.is_finite())
        .map(|(&k, &v)| (k, v))
        .collect();
    // Stable: equal curvatures keep pore order, so the running sum below
    // adds in the same order on any thread count.
    drained.par_sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: Real = drained.iter().map(|e| e.1).sum();
    let mut acc = 0.0;
    let mut end = first_entry;
    for &(k, v) in &drained {
        acc += v;
        end = k;
        if acc >= 0.995 * total {
            break;
        }
    }
    if let Some(b) = inv.breakthrough {
        end = end.max(2.0 * b);
    }
    if !first_entry.is_finite() {
        return Vec::new();
    }
    let lo = 0.8 * first_entry;
    let hi = (1.1 * end).max(lo * 1.5);
    let points = points.max(2);
    let mut out: Vec<Real> = (0..points)
        .map(|i| lo + (hi - lo) * i as Real / (points - 1) as Real)
        .collect();
    if let Some(b) = inv.breakthrough {
        out.push(b);
    }
    out.sort_by(Real::total_cmp);
    out.dedup();
    out
}

#[cfg(test)]
mod tests;
