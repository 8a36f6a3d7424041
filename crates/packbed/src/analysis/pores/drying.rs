//! Drying of the deliquored cake: where its dissolved solid is left, the
//! solid bridges that solid makes at the particle contacts, and the
//! agglomerates the bridges join.
//!
//! # The model
//!
//! The cake starts as the drainage leaves it at the reported pressure
//! ([`super::drainage`]): liquid clusters filling pores (joined to the
//! filter medium or trapped) and pendular bridges at the contacts of the
//! drained pores. The liquid carries a dissolved solid at a concentration
//! `c` (kg/m³ of liquid) with a solubility `c_s`; its crystals have a
//! density `ρ_c`. Drying is slow and isothermal, in the capillary regime
//! (Prat 1993, Int. J. Multiphase Flow 19:691; Metzger, Irawan & Tsotsas
//! 2007, AIChE J. 53:3029): evaporation from the gas side lowers each
//! cluster's liquid pressure until one meniscus passes the cluster's
//! throat of lowest entry pressure, and the pore behind it empties, the
//! liquid being pumped to the cluster's other menisci (invasion
//! percolation; the entry pressures are the drainage's, [`super::drainage::entry`]).
//! A cluster that loses a pore may split; its parts then dry on their own.
//!
//! - **Order.** Within a cluster the order in which its pores empty is
//!   capillary only; clusters do not exchange liquid (no film flow between
//!   them), so how their drying interleaves in time (set by the vapour
//!   diffusion the model does not solve) changes nothing this module
//!   reports. The pores empty in the order of an invasion percolation from
//!   every gas pore at once, which is each cluster's own order. Below the
//!   slab the filter medium is closed: no liquid leaves through it.
//! - **Solute.** Diffusion keeps a cluster's concentration uniform (Péclet
//!   number ≪ 1 at the pore scale of a slow drying): the solid a cluster
//!   holds goes with its liquid when it splits, in proportion to the
//!   parts' volumes. While the liquid is below the solubility its solid
//!   stays dissolved and concentrates; at the solubility, each pore that
//!   empties leaves the solid its liquid can no longer hold, `c_s × v`
//!   (the excess over the solubility when the pore brings the cluster to
//!   it). The last pore of a cluster leaves all the solid the cluster
//!   still holds. A saturated mother liquor (`c = c_s`, the default)
//!   deposits in every pore as it empties; a washed cake (`c < c_s`)
//!   deposits late, in the last pores of its clusters.
//! - **Where.** A pore's deposit crystallises in the liquid rings its
//!   receding liquid leaves at its contacts (in a drying NaCl-wetted
//!   packing the solute crystallises "at the contact points between
//!   grains", Delenne, Soulié et al. 2011): it is shared among
//!   the pore's particle pairs in proportion to their pendular bridges at
//!   the reported pressure, each weighted by the pore's share of the bridge
//!   ([`super::drainage::pendular`]). A pore with no pair close enough for a
//!   bridge leaves its deposit on the particles' surfaces, binding nothing.
//!   The pendular bridges of the drained pores dry in place: their solid
//!   stays at their pair.
//! - **Solid bridges.** The solid at a pair takes the shape of a pendular
//!   bridge of its volume; its neck radius `a` follows from that bridge's
//!   toroidal geometry. A pair whose solid is too little to span the gap
//!   (less than the gap's smallest bridge) holds none. A bridge whose neck
//!   is at least `min_neck` times the pair's harmonic mean radius is a
//!   bond, of tensile strength `σ_t π a²` (3D; `σ_t 2a` per unit depth in
//!   2D). For touching spheres the small-bridge limit gives `π a² ∝
//!   (V R)^{1/2}`: the square-root law Endo, Kousaka & Onitsuka (1995,
//!   KONA 13) measured on salt bridges between glass spheres.
//! - **Agglomerates** are the connected components of the bond graph, of
//!   two particles or more.
//!
//! Mass balance: the solid deposited (at pairs and on surfaces) equals the
//! solid dissolved in the liquid the drainage left, exactly up to rounding
//! (tests).
// NaN-rejecting guards read `!(x > 0.0)`: true for NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::drainage::invasion::{invade_on, Adjacency, InvasionGraph, Sets};
use super::drainage::{entry, Drainage, DrainageOptions, PoreState, Wet};
use super::network::Network;
use crate::bed::Bed;
use crate::math::Real;
use rayon::prelude::*;
use serde::Serialize;

/// Why the drying could not run.
pub type Refusal = String;

/// Settings of the drying (`[analysis.drying]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DryingOptions {
    /// Dissolved solid per volume of liquid, kg/m³.
    pub concentration: Real,
    /// Its solubility, kg/m³ (`+∞`: nothing crystallises before a
    /// cluster's last pore).
    pub solubility: Real,
    /// Density of the crystals, kg/m³.
    pub crystal_density: Real,
    /// The smallest neck radius of a bond, in the pair's harmonic mean
    /// radius.
    pub min_neck: Real,
    /// Tensile strength of the bridges' solid, Pa.
    pub tensile_strength: Real,
}

pub use crate::config::{
    DEFAULT_CONCENTRATION, DEFAULT_CRYSTAL_DENSITY, DEFAULT_MIN_NECK, DEFAULT_TENSILE_STRENGTH,
};

impl Default for DryingOptions {
    fn default() -> Self {
        DryingOptions {
            concentration: DEFAULT_CONCENTRATION,
            solubility: DEFAULT_CONCENTRATION,
            crystal_density: DEFAULT_CRYSTAL_DENSITY,
            min_neck: DEFAULT_MIN_NECK,
            tensile_strength: DEFAULT_TENSILE_STRENGTH,
        }
    }
}

/// A pair of particles holding solid after drying (`bridges.csv`).
#[derive(Clone, Debug, PartialEq)]
pub struct SolidBridge {
    /// The two particles.
    pub particles: [u32; 2],
    /// Periods the second lies from the first (periodic beds).
    pub shift: [i8; 2],
    /// Surface gap.
    pub gap: Real,
    /// Liquid of its pendular bridge after the drainage (0: the pair was
    /// inside a liquid cluster).
    pub liquid: Real,
    /// Volume of solid deposited at the pair (area in 2D).
    pub solid: Real,
    /// Neck radius of the solid bridge; `None` when the solid does not
    /// span the gap.
    pub neck_radius: Option<Real>,
    /// A bond: the neck at least `min_neck` of the harmonic mean radius.
    pub bond: bool,
    /// Tensile strength, N (N/m in 2D), with a length unit.
    pub strength: Option<Real>,
    /// The agglomerate it binds (0: none).
    pub agglomerate: u32,
    /// The agitation's stress (Pa, load over the bed's cross-section) when
    /// it broke; `None`: intact, or no agitation.
    pub broken_at: Option<Real>,
    /// The agglomerate it binds after the agitation (0: none); without an
    /// agitation, `agglomerate`.
    pub agglomerate_after: u32,
}

/// An agglomerate (`agglomerates.csv`): particles joined by bonds.
#[derive(Clone, Debug, PartialEq)]
pub struct Agglomerate {
    /// Its number, 1 for the largest by volume.
    pub id: u32,
    /// Particles in it.
    pub particles: u64,
    /// Their volume (area in 2D).
    pub volume: Real,
    /// Diameter of the sphere (disc) of that volume.
    pub equivalent_diameter: Real,
    /// Bonds inside it.
    pub bonds: u64,
    /// Its weakest bond's strength, N (N/m in 2D), with a length unit.
    pub weakest_bond: Option<Real>,
}

/// `agglomeration.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct AgglomerationSummary {
    /// Dissolved solid, kg/m³ of liquid.
    pub concentration: Real,
    /// Its solubility, kg/m³ (`null`: never reached before the last pore).
    pub solubility: Option<Real>,
    /// Crystal density, kg/m³.
    pub crystal_density: Real,
    /// A bond's smallest neck, in the pair's harmonic mean radius.
    pub min_neck: Real,
    /// The solid's tensile strength, Pa.
    pub tensile_strength: Real,
    /// Liquid left by the drainage in the slab (clusters and bridges).
    pub liquid_volume: Real,
    /// Volume of solid it holds dissolved (`liquid × c / ρ_c`).
    pub solid_volume: Real,
    /// The part of it left at particle pairs (the rest coats surfaces).
    pub solid_at_pairs: Real,
    /// The part of it on the particles' surfaces (pores with no pair
    /// close enough for a bridge).
    pub solid_on_surfaces: Real,
    /// The part of it in bonds.
    pub solid_in_bonds: Real,
    /// Liquid clusters when drying starts.
    pub clusters: u64,
    /// Pores the drying empties.
    pub pores_dried: u64,
    /// Pairs holding a solid bridge that spans their gap.
    pub solid_bridges: u64,
    /// Those that are bonds.
    pub bonds: u64,
    /// Mean bonds per particle of the slab.
    pub bonds_per_particle: Real,
    /// Agglomerates (two particles or more).
    pub agglomerates: u64,
    /// Volume fraction of the slab's particles inside agglomerates.
    pub fraction_in_agglomerates: Real,
    /// Mean particles per agglomerate.
    pub mean_particles: Real,
    /// Particles in the largest.
    pub largest_particles: u64,
    /// The product's volume-median size: the equivalent diameter of the
    /// agglomerates and single particles of the slab, by volume.
    pub d50_product: Real,
    /// The particles' own volume-median diameter, for comparison.
    pub d50_particles: Real,
    /// Volume fraction of the product in units of 1, 2, 3–4, 5–8, …
    /// particles (powers of two).
    pub volume_by_particles: Vec<Real>,
    /// Mean bond strength, N (N/m in 2D), with a length unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean_bond_strength: Option<Real>,
    /// The agitated product, when `[analysis.drying.agitation]` asks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agitation: Option<AgitationSummary>,
    /// Why a figure is missing, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// What the drying leaves.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drying {
    /// `agglomeration.*`.
    pub summary: AgglomerationSummary,
    /// Pairs holding solid.
    pub bridges: Vec<SolidBridge>,
    /// Agglomerates, largest first.
    pub agglomerates: Vec<Agglomerate>,
    /// Per particle: its agglomerate (0: none).
    pub agglomerate_of: Vec<u32>,
    /// The slab `[z_lo, z_hi]` whose particles make the product.
    pub slab: (Real, Real),
}

/// `agglomeration.agitation.*` of `summary.json`: the dried cake loaded as
/// `packbed fragment` loads a bed, its solid bridges broken weakest for
/// their load first up to the agitation's stress (`crate::mechanics::agitation`).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct AgitationSummary {
    /// The load: shear, compression or gravity.
    pub load: String,
    /// The agitation's stress, Pa: the load's total over the bed's
    /// cross-section.
    pub stress: Real,
    /// Bonds the load reaches (solid bridges between different bodies).
    pub bonds: u64,
    /// Of them, broken.
    pub broken: u64,
    /// The stress at which the intact cake's first bond breaks, Pa, whether
    /// or not the agitation reaches it (`null`: the load reaches no bond).
    pub first_break_stress: Option<Real>,
    /// The stress at which the cake failed (a loaded piece lost its last
    /// path to the floor or walls), Pa; `null`: it bore the agitation.
    pub failure_stress: Option<Real>,
    /// False when `max_breaks` stopped the breakage before the stress was
    /// borne.
    pub complete: bool,
    /// Agglomerates after it.
    pub agglomerates: u64,
    /// Volume fraction of the slab's particles in agglomerates after it.
    pub fraction_in_agglomerates: Real,
    /// Mean particles per agglomerate after it.
    pub mean_particles: Real,
    /// Particles in the largest after it.
    pub largest_particles: u64,
    /// The product's volume-median size after it.
    pub d50_product: Real,
    /// Volume fraction of the product in units of 1, 2, 3–4, … particles
    /// after it.
    pub volume_by_particles: Vec<Real>,
}

impl Drying {
    /// The columns of `bridges.csv` (a missing neck or strength is NaN, the
    /// form pandas gives an empty cell).
    pub fn bridge_columns(&self) -> Vec<(String, super::Column)> {
        use super::Column::{Float, Int};
        let b = &self.bridges;
        let int = |f: &dyn Fn(&SolidBridge) -> i64| Int(b.iter().map(f).collect());
        let float = |f: &dyn Fn(&SolidBridge) -> Real| Float(b.iter().map(f).collect());
        vec![
            ("particle_a".into(), int(&|r| i64::from(r.particles[0]))),
            ("particle_b".into(), int(&|r| i64::from(r.particles[1]))),
            ("sx".into(), int(&|r| i64::from(r.shift[0]))),
            ("sy".into(), int(&|r| i64::from(r.shift[1]))),
            ("gap".into(), float(&|r| r.gap)),
            ("liquid".into(), float(&|r| r.liquid)),
            ("solid".into(), float(&|r| r.solid)),
            (
                "neck_radius".into(),
                float(&|r| r.neck_radius.unwrap_or(Real::NAN)),
            ),
            ("bond".into(), int(&|r| i64::from(r.bond))),
            (
                "strength_n".into(),
                float(&|r| r.strength.unwrap_or(Real::NAN)),
            ),
            ("agglomerate".into(), int(&|r| i64::from(r.agglomerate))),
            (
                "broken_at_pa".into(),
                float(&|r| r.broken_at.unwrap_or(Real::NAN)),
            ),
            (
                "agglomerate_after".into(),
                int(&|r| i64::from(r.agglomerate_after)),
            ),
        ]
    }

    /// The columns of `agglomerates.csv` (a missing strength is NaN).
    pub fn agglomerate_columns(&self) -> Vec<(String, super::Column)> {
        use super::Column::{Float, Int};
        let a = &self.agglomerates;
        let int = |f: &dyn Fn(&Agglomerate) -> i64| Int(a.iter().map(f).collect());
        let float = |f: &dyn Fn(&Agglomerate) -> Real| Float(a.iter().map(f).collect());
        vec![
            ("agglomerate".into(), int(&|r| i64::from(r.id))),
            ("particles".into(), int(&|r| r.particles as i64)),
            ("volume".into(), float(&|r| r.volume)),
            (
                "equivalent_diameter".into(),
                float(&|r| r.equivalent_diameter),
            ),
            ("bonds".into(), int(&|r| r.bonds as i64)),
            (
                "weakest_bond_n".into(),
                float(&|r| r.weakest_bond.unwrap_or(Real::NAN)),
            ),
        ]
    }
}

/// Refuses settings no drying has.
pub fn check_options(o: &DryingOptions) -> Result<(), Refusal> {
    match crate::config::drying_problem(
        o.concentration,
        o.solubility,
        o.crystal_density,
        o.min_neck,
        o.tensile_strength,
    ) {
        Some(why) => Err(why),
        None => Ok(()),
    }
}

impl crate::config::DryingConfig {
    /// The drying's settings.
    pub fn options(&self) -> DryingOptions {
        DryingOptions {
            concentration: self.concentration,
            solubility: self.solubility_or_default(),
            crystal_density: self.crystal_density,
            min_neck: self.min_neck,
            tensile_strength: self.tensile_strength,
        }
    }
}

/// The solid each pore leaves as it empties (crystal volume), for pores
/// emptying in `order` (every pore once), joined as `adj` says, holding
/// `voids` of liquid with dissolved solid `c` and solubility `s` (crystal
/// volume per liquid volume; `s = +∞`: nothing crystallises before a
/// cluster's last pore).
///
/// The clusters' splits are found backwards in time: adding the pores back
/// in reverse order to a union–find, each pore's arrival joins the parts
/// its emptying will split the cluster into (its children); forwards, a
/// pore's cluster holds its own volume and its children's, and its solid
/// goes to them in proportion to their volumes once the pore's deposit is
/// taken.
pub fn deposits(adj: &Adjacency, order: &[u32], voids: &[Real], c: Real, s: Real) -> Vec<Real> {
    let pores = voids.len();
    const NONE: u32 = u32::MAX;
    let mut sets = Sets::new(pores);
    // The pore whose arrival made each set's current cluster.
    let mut top = vec![NONE; pores];
    let mut parent = vec![NONE; pores];
    let mut volume = vec![0.0; pores];
    let mut added = vec![false; pores];
    for &p in order.iter().rev() {
        let p = p as usize;
        added[p] = true;
        volume[p] = voids[p];
        for &(q, _) in adj.of(p) {
            let q = q as usize;
            if !added[q] {
                continue;
            }
            let r = sets.find(q);
            if sets.find(p) == r {
                continue; // a part already joined through another throat
            }
            let child = top[r] as usize;
            parent[child] = p as u32;
            volume[p] += volume[child];
            sets.union(p, r);
        }
        let r = sets.find(p);
        top[r] = p as u32;
    }
    let mut mass = vec![0.0; pores];
    let mut rest = vec![0.0; pores];
    let mut deposit = vec![0.0; pores];
    for &p in order {
        let p = p as usize;
        let m = match parent[p] {
            NONE => c * volume[p],
            up => {
                let up = up as usize;
                let left = volume[up] - voids[up];
                if left > 0.0 {
                    rest[up] * volume[p] / left
                } else {
                    0.0
                }
            }
        };
        mass[p] = m;
        let after = volume[p] - voids[p];
        let d = if !(after > 0.0) {
            m
        } else if s.is_finite() {
            (m - s * after).max(0.0)
        } else {
            0.0
        };
        deposit[p] = d;
        rest[p] = m - d;
    }
    deposit
}

/// Agglomerates of `n` particles joined by `bonds`: each particle's
/// connected component, named by the smallest particle index in it.
pub fn components(n: usize, bonds: &[(u32, u32)]) -> Vec<u32> {
    let mut sets = Sets::new(n);
    for &(a, b) in bonds {
        sets.union(a as usize, b as usize);
    }
    let mut least = vec![u32::MAX; n];
    for p in 0..n {
        let r = sets.find(p);
        least[r] = least[r].min(p as u32);
    }
    (0..n).map(|p| least[sets.find(p)]).collect()
}

/// Dries the slab `[z_lo, z_hi]` of `net`, the network of `bed`, from the
/// state `drainage` reports (`wet` its pairs and curvature).
#[allow(clippy::too_many_arguments)]
pub fn dry<const D: usize>(
    bed: &Bed<D>,
    net: &Network<D>,
    slab: (Real, Real),
    drainage: &Drainage,
    wet: &Wet,
    drainage_options: &DrainageOptions,
    options: &DryingOptions,
    metres_per_unit: Option<Real>,
) -> Result<Drying, Refusal> {
    check_options(options)?;
    let Some(kappa) = wet.kappa else {
        return Err(
            "drying: the drainage reports no state to dry from (no breakthrough and no \
             [analysis.drainage] pressure)"
                .into(),
        );
    };
    let c = options.concentration / options.crystal_density;
    let s = options.solubility / options.crystal_density;
    let liquid_pore =
        |p: usize| matches!(drainage.pores[p].0, PoreState::Filled | PoreState::Trapped);
    // Gas: the drained pores and everything above the slab (drained from
    // the start); below it the closed filter medium.
    let gas = |p: usize| match drainage.pores[p].0 {
        PoreState::Drained => true,
        PoreState::Outside => drainage.drains_at[p] <= kappa,
        _ => false,
    };
    let mut index = vec![u32::MAX; net.pores.len()];
    let mut members: Vec<u32> = Vec::new();
    for p in 0..net.pores.len() {
        if liquid_pore(p) {
            index[p] = members.len() as u32;
            members.push(p as u32);
        }
    }
    let n = members.len();
    let voids: Vec<Real> = members
        .iter()
        .map(|&p| drainage.pores[p as usize].2)
        .collect();
    let cos = drainage_options.contact_angle.cos();
    // The throats the drying reads: within the liquid, and from gas into it.
    let kinds: Vec<(u32, u32, Real, bool)> = (0..net.throats.len())
        .into_par_iter()
        .filter_map(|t| {
            let [a, b] = net.throats[t].pores.map(|p| p as usize);
            let (la, lb) = (index[a], index[b]);
            let inner = la != u32::MAX && lb != u32::MAX;
            let into = if la != u32::MAX && gas(b) {
                Some(la)
            } else if lb != u32::MAX && gas(a) {
                Some(lb)
            } else {
                None
            };
            if !inner && into.is_none() {
                return None;
            }
            // The drainage's entry, unless it left the throat out (a
            // throat gas never crosses in the drainage, one below the slab).
            let e = match wet.entry.get(t) {
                Some(&e) if e.is_finite() => e,
                _ => entry::entry_curvature(bed, net, t, drainage_options.entry, cos),
            };
            Some(if inner {
                (la, lb, e, true)
            } else {
                (into.unwrap_or(0), u32::MAX, e, false)
            })
        })
        .collect();
    let mut graph = InvasionGraph {
        pores: n,
        outlet: vec![false; n],
        ..InvasionGraph::default()
    };
    for &(a, b, e, inner) in &kinds {
        if inner {
            graph.throats.push((a, b, e));
        } else {
            graph.inlets.push((a, e));
        }
    }
    let adj = Adjacency::new(&graph);
    let invasion = invade_on(&graph, &adj, false);
    let mut order = invasion.order.clone();
    // Liquid the gas cannot reach through any throat (closed throats only)
    // empties last, in index order.
    let mut reached = vec![false; n];
    for &p in &order {
        reached[p as usize] = true;
    }
    order.extend((0..n as u32).filter(|&p| !reached[p as usize]));
    let deposit = deposits(&adj, &order, &voids, c, s);
    let clusters = {
        let pairs: Vec<(u32, u32)> = graph.throats.iter().map(|t| (t.0, t.1)).collect();
        let roots = components(n, &pairs);
        (0..n).filter(|&p| roots[p] == p as u32).count() as u64
    };

    // Each liquid pore's deposit, shared among its pairs by their bridges.
    let pend = &wet.pendular;
    let (start, links) = pend.pores_pairs(net.pores.len());
    let shares: Vec<(Vec<(u32, Real)>, Real)> = members
        .par_iter()
        .zip(&deposit)
        .map(|(&p, &d)| {
            if !(d > 0.0) {
                return (Vec::new(), d);
            }
            let p = p as usize;
            let w: Vec<(u32, Real)> = links[start[p] as usize..start[p + 1] as usize]
                .iter()
                .filter_map(|&(e, share)| {
                    let v = pend.bridge_volume(e as usize, kappa)?;
                    (share * v > 0.0).then_some((e, share * v))
                })
                .collect();
            (w, d)
        })
        .collect();
    let pairs_n = pend.edge_count();
    let liquid_at: Vec<Real> = (0..pairs_n)
        .into_par_iter()
        .map(|e| pend.slab_bridge(e, &drainage.drains_at, kappa))
        .collect();
    let mut solid: Vec<Real> = liquid_at.iter().map(|&l| c * l).collect();
    let mut on_surfaces = 0.0;
    for (w, d) in &shares {
        let total: Real = w.iter().map(|x| x.1).sum();
        if total > 0.0 {
            for &(e, x) in w {
                solid[e as usize] += d * x / total;
            }
        } else {
            on_surfaces += d;
        }
    }
    let liquid_volume: Real = voids.iter().sum::<Real>() + liquid_at.iter().sum::<Real>();

    // Solid bridges and bonds.
    let necks: Vec<Option<Real>> = (0..pairs_n)
        .into_par_iter()
        .map(|e| {
            if solid[e] > 0.0 {
                pend.neck_for_volume(e, solid[e])
            } else {
                None
            }
        })
        .collect();
    let strength_of = |a: Real| {
        metres_per_unit.map(|m| {
            if D == 3 {
                options.tensile_strength * std::f64::consts::PI * (a * m).powi(2)
            } else {
                options.tensile_strength * 2.0 * a * m
            }
        })
    };
    let mut bridges: Vec<SolidBridge> = Vec::new();
    let mut bonds: Vec<(u32, u32)> = Vec::new();
    let mut solid_in_bonds = 0.0;
    let mut solid_at_pairs = 0.0;
    for e in 0..pairs_n {
        if !(solid[e] > 0.0) {
            continue;
        }
        solid_at_pairs += solid[e];
        let (particles, shift, radii, gap) = pend.pair(e);
        let harmonic = 2.0 * radii[0] * radii[1] / (radii[0] + radii[1]);
        let neck = necks[e];
        let bond = neck.is_some_and(|a| a >= options.min_neck * harmonic);
        if bond {
            bonds.push((particles[0], particles[1]));
            solid_in_bonds += solid[e];
        }
        bridges.push(SolidBridge {
            particles,
            shift,
            gap,
            liquid: liquid_at[e],
            solid: solid[e],
            neck_radius: neck,
            bond,
            strength: neck.filter(|_| bond).and_then(strength_of),
            agglomerate: 0,
            broken_at: None,
            agglomerate_after: 0,
        });
    }

    // Agglomerates: components of two particles or more, largest first.
    let product = product(bed, slab, &bonds);
    let mut agglomerates = product.agglomerates;
    for b in &mut bridges {
        if b.bond {
            let id = product.agglomerate_of[b.particles[0] as usize];
            b.agglomerate = id;
            b.agglomerate_after = id;
            let a = &mut agglomerates[id as usize - 1];
            a.bonds += 1;
            if let Some(f) = b.strength {
                a.weakest_bond = Some(a.weakest_bond.map_or(f, |w: Real| w.min(f)));
            }
        }
    }
    let strengths: Vec<Real> = bridges.iter().filter_map(|b| b.strength).collect();
    let summary = AgglomerationSummary {
        concentration: options.concentration,
        solubility: options.solubility.is_finite().then_some(options.solubility),
        crystal_density: options.crystal_density,
        min_neck: options.min_neck,
        tensile_strength: options.tensile_strength,
        liquid_volume,
        solid_volume: c * liquid_volume,
        solid_at_pairs,
        solid_on_surfaces: on_surfaces,
        solid_in_bonds,
        clusters,
        pores_dried: n as u64,
        solid_bridges: necks.iter().filter(|x| x.is_some()).count() as u64,
        bonds: bonds.len() as u64,
        bonds_per_particle: product.bonds_per_particle,
        agglomerates: agglomerates.len() as u64,
        fraction_in_agglomerates: product.fraction_in_agglomerates,
        mean_particles: product.mean_particles,
        largest_particles: product.largest_particles,
        d50_product: product.d50_product,
        d50_particles: product.d50_particles,
        volume_by_particles: product.volume_by_particles,
        mean_bond_strength: (!strengths.is_empty())
            .then(|| strengths.iter().sum::<Real>() / strengths.len() as Real),
        agitation: None,
        note: None,
    };
    Ok(Drying {
        summary,
        bridges,
        agglomerates,
        agglomerate_of: product.agglomerate_of,
        slab,
    })
}

/// What a bond graph makes of the bed's particles: its agglomerates and the
/// size distribution of the product, the slab's particles grouped by
/// agglomerate.
#[derive(Clone, Debug, PartialEq)]
pub struct Product {
    /// Agglomerates (two particles or more), largest by volume first, their
    /// `bonds` and `weakest_bond` not counted.
    pub agglomerates: Vec<Agglomerate>,
    /// Per particle: its agglomerate (0: none).
    pub agglomerate_of: Vec<u32>,
    /// Mean bonds per particle of the slab.
    pub bonds_per_particle: Real,
    /// Volume fraction of the slab's particles inside agglomerates.
    pub fraction_in_agglomerates: Real,
    /// Mean particles per agglomerate.
    pub mean_particles: Real,
    /// Particles in the largest agglomerate.
    pub largest_particles: u64,
    /// Volume-median equivalent diameter of the product's units.
    pub d50_product: Real,
    /// Volume-median diameter of the slab's particles.
    pub d50_particles: Real,
    /// Volume fraction of the product in units of 1, 2, 3–4, 5–8, …
    /// particles.
    pub volume_by_particles: Vec<Real>,
}

/// The agglomerates `bonds` join among `bed`'s particles, and the product
/// the slab `[z_lo, z_hi]` makes of them. A particle is a body: the beads of
/// a rigid chain are one, joined without a bond and counted once (its
/// volume, the slab's membership and `bonds_per_particle`,
/// `d50_particles` stay per bead).
pub fn product<const D: usize>(bed: &Bed<D>, slab: (Real, Real), bonds: &[(u32, u32)]) -> Product {
    let z = D - 1;
    let in_slab: Vec<bool> = bed
        .centres
        .iter()
        .map(|c| c.0[z] >= slab.0 && c.0[z] <= slab.1)
        .collect();
    // A chain's beads are one rigid body: joined as a bond joins particles,
    // and counted once among an agglomerate's particles (its first bead
    // counts it).
    let mut links: Vec<(u32, u32)> = bonds.to_vec();
    let mut counts_its_body = vec![true; bed.len()];
    if bed.bodies.len() == bed.len() {
        let mut first_of: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
        for (p, &b) in bed.bodies.iter().enumerate() {
            match first_of.entry(b) {
                std::collections::hash_map::Entry::Occupied(e) => {
                    links.push((*e.get(), p as u32));
                    counts_its_body[p] = false;
                }
                std::collections::hash_map::Entry::Vacant(e) => {
                    e.insert(p as u32);
                }
            }
        }
    }
    let root = components(bed.len(), &links);
    let body = |p: usize| crate::math::ball_volume::<D>(bed.radii[p]);
    let mut count = vec![0u64; bed.len()];
    let mut volume = vec![0.0; bed.len()];
    for p in 0..bed.len() {
        count[root[p] as usize] += u64::from(counts_its_body[p]);
        volume[root[p] as usize] += body(p);
    }
    let mut big: Vec<u32> = (0..bed.len() as u32)
        .filter(|&p| root[p as usize] == p && count[p as usize] >= 2)
        .collect();
    big.sort_by(|&a, &b| {
        volume[b as usize]
            .total_cmp(&volume[a as usize])
            .then(a.cmp(&b))
    });
    let mut id_of_root = vec![0u32; bed.len()];
    for (k, &r) in big.iter().enumerate() {
        id_of_root[r as usize] = k as u32 + 1;
    }
    let agglomerate_of: Vec<u32> = (0..bed.len())
        .map(|p| id_of_root[root[p] as usize])
        .collect();
    let diameter = |v: Real| {
        if D == 3 {
            (6.0 * v / std::f64::consts::PI).cbrt()
        } else {
            (4.0 * v / std::f64::consts::PI).sqrt()
        }
    };
    let agglomerates: Vec<Agglomerate> = big
        .iter()
        .enumerate()
        .map(|(k, &r)| Agglomerate {
            id: k as u32 + 1,
            particles: count[r as usize],
            volume: volume[r as usize],
            equivalent_diameter: diameter(volume[r as usize]),
            bonds: 0,
            weakest_bond: None,
        })
        .collect();
    // The product: the slab's particles, grouped by agglomerate.
    let mut units: Vec<(u64, Real)> = Vec::new(); // (particles, volume in the slab)
    let mut unit_of_root = vec![u32::MAX; bed.len()];
    let mut particle_sizes: Vec<(Real, Real)> = Vec::new();
    for p in 0..bed.len() {
        if !in_slab[p] {
            continue;
        }
        particle_sizes.push((2.0 * bed.radii[p], body(p)));
        let r = root[p] as usize;
        if unit_of_root[r] == u32::MAX {
            unit_of_root[r] = units.len() as u32;
            units.push((count[r], volume[r]));
        }
    }
    let product: Real = particle_sizes.iter().map(|x| x.1).sum();
    let in_agglomerates: Real = (0..bed.len())
        .filter(|&p| in_slab[p] && agglomerate_of[p] > 0)
        .map(body)
        .sum();
    let mut bins = vec![0.0; 1];
    for &(k, v) in &units {
        let bin = (64 - (k.max(1) - 1).leading_zeros()) as usize; // 1 → 0, 2 → 1, 3–4 → 2, …
        if bins.len() <= bin {
            bins.resize(bin + 1, 0.0);
        }
        bins[bin] += v;
    }
    let total_units: Real = units.iter().map(|u| u.1).sum();
    let volume_by_particles: Vec<Real> = if total_units > 0.0 {
        bins.iter().map(|v| v / total_units).collect()
    } else {
        Vec::new()
    };
    let unit_sizes: Vec<(Real, Real)> = units.iter().map(|&(_, v)| (diameter(v), v)).collect();
    let slab_particles = in_slab.iter().filter(|&&x| x).count();
    Product {
        agglomerate_of,
        bonds_per_particle: if slab_particles > 0 {
            2.0 * bonds.len() as Real / slab_particles as Real
        } else {
            0.0
        },
        fraction_in_agglomerates: if product > 0.0 {
            in_agglomerates / product
        } else {
            0.0
        },
        mean_particles: if agglomerates.is_empty() {
            0.0
        } else {
            agglomerates.iter().map(|a| a.particles).sum::<u64>() as Real
                / agglomerates.len() as Real
        },
        largest_particles: agglomerates.first().map_or(0, |a| a.particles),
        d50_product: volume_median(&unit_sizes),
        d50_particles: volume_median(&particle_sizes),
        volume_by_particles,
        agglomerates,
    }
}

/// The volume-weighted median of `(size, volume)` items (0 when empty).
fn volume_median(items: &[(Real, Real)]) -> Real {
    let mut v: Vec<(Real, Real)> = items.to_vec();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: Real = v.iter().map(|x| x.1).sum();
    let mut run = 0.0;
    for &(size, w) in &v {
        run += w;
        if run >= 0.5 * total {
            return size;
        }
    }
    0.0
}

#[cfg(test)]
mod tests;
