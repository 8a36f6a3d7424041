//! Contact forces and breakage of a bed under load (`docs/reference/fragmentation.md`):
//! a stage after the analysis that takes a [`Bed`] and its contacts, never the
//! deposition engine.
//!
//! Every body is rigid and every contact a spring; the bed is loaded
//! (`shear`, `compression`, `gravity`), the stiffness system is solved exactly
//! by a sparse Cholesky factorisation ([`solver`]), and bonds are broken one
//! by one, strongest first, until a count or the failure of the bed.

pub mod agitation;
pub mod loads;
pub mod network;
pub mod solver;
pub mod spring;

use crate::analysis::Contacts;
use crate::bed::Bed;
pub use crate::config::fragmentation::{Breaks, FragmentationConfig, Load};
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
pub use loads::{AppliedLoad, TOTAL};
pub use network::{Bodies, BondGeometry};
use serde::Serialize;
use spring::body_dofs;

/// One broken bond.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// 1 for the first break.
    pub step: u64,
    /// Index of the bond in [`Fragmentation::bonds`].
    pub bond: usize,
    /// The bond's force magnitude when it broke.
    pub magnitude: Real,
    /// Connected pieces of the bond network (with at least one body) after it.
    pub fragments: u64,
    /// Bodies in the largest of them.
    pub largest_fragment: u64,
}

/// `fragmentation.*` of `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FragmentationSummary {
    /// The load.
    pub load: Load,
    /// Bonds of the intact bed.
    pub bonds: u64,
    /// Largest bond force magnitude of the intact bed.
    pub max_force: Real,
    /// Mean bond force magnitude of the intact bed.
    pub mean_force: Real,
    /// Standard deviation ÷ mean of the magnitudes (population sd).
    pub force_cv: Real,
    /// Bodies of the intact bed held by their ground springs (mechanisms).
    pub unstable_bodies: u64,
    /// Bonds broken.
    pub breaks: u64,
    /// True when the bed failed.
    pub failed: bool,
    /// Breaks until failure (null when the run stopped before it).
    pub breaks_to_failure: Option<u64>,
    /// Pieces of the bond network at the end.
    pub fragments: u64,
    /// Bodies in the largest piece at the end.
    pub largest_fragment: u64,
}

/// The forces in a bed under load and the order its bonds broke.
#[derive(Clone, Debug)]
pub struct Fragmentation<const D: usize> {
    /// The rigid bodies.
    pub bodies: Bodies<D>,
    /// Every bond of the intact bed.
    pub bonds: Vec<BondGeometry<D>>,
    /// The force each bond exerts on its body i, in the intact bed.
    pub forces: Vec<Vector<D>>,
    /// The loads on the intact bed.
    pub loads: Vec<AppliedLoad<D>>,
    /// Each body's unknowns (translation, rotation) in the intact bed.
    pub displacements: Vec<Real>,
    /// Ground-spring stiffness of each unknown.
    pub ground: Vec<Real>,
    /// The broken bonds, in order.
    pub steps: Vec<Step>,
    /// The summary.
    pub summary: FragmentationSummary,
    /// Numeric factorisations done (the first included).
    pub factorisations: usize,
    /// Wall time of the network, the loads and the first solve.
    pub first_solve_seconds: f64,
    /// Wall time of the breaks.
    pub breakage_seconds: f64,
}

impl<const D: usize> Fragmentation<D> {
    /// `normal` (positive: tension) of bond `k`'s force.
    pub fn normal(&self, k: usize) -> Real {
        self.forces[k].dot(&self.bonds[k].normal)
    }

    /// `tangential` of bond `k`'s force.
    pub fn tangential(&self, k: usize) -> Real {
        let f = self.forces[k];
        (f - self.bonds[k].normal * self.normal(k)).norm()
    }
}

/// Loads `bed` as `options` say, solves for its bond forces and breaks bonds
/// (`contacts`: the analysis' contacts of `bed`).
pub fn fragment<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    options: &FragmentationConfig,
) -> Result<Fragmentation<D>> {
    solve_and_break(bed, contacts, options, true, &mut |_| {})
}

/// [`fragment`], telling `progress` the number of bonds broken after each
/// break (a long breakage re-solves the bed once per break).
pub fn fragment_with<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    options: &FragmentationConfig,
    progress: &mut dyn FnMut(u64),
) -> Result<Fragmentation<D>> {
    solve_and_break(bed, contacts, options, true, progress)
}

/// The bond forces of the intact bed under `options.load`, without breaking
/// any bond (`options.breaks` is not used; `steps` is empty).
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub fn forces<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    options: &FragmentationConfig,
) -> Result<Fragmentation<D>> {
    solve_and_break(bed, contacts, options, false, &mut |_| {})
}

fn solve_and_break<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    options: &FragmentationConfig,
    breaking: bool,
    progress: &mut dyn FnMut(u64),
) -> Result<Fragmentation<D>> {
    options.check()?;
    let start = std::time::Instant::now();
    let bodies = Bodies::of(bed);
    let bonds = network::bonds(bed, &bodies, contacts);
    if bonds.is_empty() {
        return Err(Error::Impossible(
            "the bed has no bonds (no particle touches another or a wall)".into(),
        ));
    }
    let load_groups = loads::Loads::new(options.load, bed, &bodies, &bonds)?;
    let springs = solver::Springs {
        kn: 1.0,
        kt: options.kt_over_kn,
    };
    let nb = bodies.len();
    let mut bond_count = bond_counts(&bonds, nb);
    let loads = load_groups
        .current(&bonded(&bond_count))
        .ok_or_else(|| load_groups.unbonded(&bonded(&bond_count)))?;
    let mut system = solver::Solver::new(&bonds, &bodies.reference, &bodies.reach, springs)?;
    let u = system.solve(&loads::load_vector(&loads, nb))?;
    let forces = bond_forces(&bonds, &vec![true; bonds.len()], &u, springs);
    let magnitudes: Vec<Real> = forces.iter().map(|f| f.norm()).collect();
    let unstable = unstable_bodies::<D>(&u, system.ground(), &bodies.reach);
    let first_solve_seconds = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();

    let mut alive = vec![true; bonds.len()];
    let mut current = magnitudes.clone();
    let mut steps = Vec::new();
    let (mut fragments, mut largest, failed) = network_state(&bonds, &alive, nb, Some(&loads));
    let mut failed_at = failed.then_some(0u64);
    loop {
        if !breaking {
            break;
        }
        let done = steps.len() as u64;
        match options.breaks {
            Breaks::Failure if failed_at.is_some() => break,
            Breaks::Count(n) if done >= n => break,
            _ => {}
        }
        // The strongest bond; the first listed wins a tie.
        let Some(k) = strongest(&current, &alive) else {
            break;
        };
        let magnitude = current[k];
        alive[k] = false;
        unbond(&mut bond_count, &bonds[k]);
        system.remove(k)?;
        let loaded = load_groups.current(&bonded(&bond_count));
        let failed;
        (fragments, largest, failed) = network_state(&bonds, &alive, nb, loaded.as_deref());
        let step = done + 1;
        if failed_at.is_none() && failed {
            failed_at = Some(step);
        }
        steps.push(Step {
            step,
            bond: k,
            magnitude,
            fragments,
            largest_fragment: largest,
        });
        progress(step);
        let more = match options.breaks {
            Breaks::Failure => failed_at.is_none(),
            Breaks::Count(n) => step < n,
        };
        if !more {
            break;
        }
        let Some(now) = &loaded else { break };
        let u = system.solve(&loads::load_vector(now, nb))?;
        let f = bond_forces(&bonds, &alive, &u, springs);
        for (c, f) in current.iter_mut().zip(&f) {
            *c = f.norm();
        }
    }
    let summary = FragmentationSummary {
        load: options.load,
        bonds: bonds.len() as u64,
        max_force: magnitudes.iter().copied().fold(0.0, Real::max),
        mean_force: mean(&magnitudes),
        force_cv: cv(&magnitudes),
        unstable_bodies: unstable,
        breaks: steps.len() as u64,
        failed: failed_at.is_some(),
        breaks_to_failure: failed_at,
        fragments,
        largest_fragment: largest,
    };
    Ok(Fragmentation {
        factorisations: system.factorisations,
        first_solve_seconds,
        breakage_seconds: start.elapsed().as_secs_f64(),
        ground: system.ground().to_vec(),
        bodies,
        bonds,
        forces,
        loads,
        displacements: u,
        steps,
        summary,
    })
}

/// Bonds per body.
fn bond_counts<const D: usize>(bonds: &[BondGeometry<D>], bodies: usize) -> Vec<u32> {
    let mut count = vec![0u32; bodies];
    for g in bonds {
        count[g.i as usize] += 1;
        if let Some(j) = g.j {
            count[j as usize] += 1;
        }
    }
    count
}

/// Takes a broken bond `g` off its bodies' counts.
fn unbond<const D: usize>(count: &mut [u32], g: &BondGeometry<D>) {
    count[g.i as usize] -= 1;
    if let Some(j) = g.j {
        count[j as usize] -= 1;
    }
}

/// Which bodies still have a bond (the loads go to those).
fn bonded(count: &[u32]) -> Vec<bool> {
    count.iter().map(|&c| c > 0).collect()
}

/// Relative difference below which two magnitudes tie: the solve's rounding
/// (and the ground springs' ~1e-9) are below it, so bonds that carry the same
/// force by symmetry tie however the arithmetic rounded them.
pub const TIE: Real = 1e-9;

/// The alive bond with the largest magnitude, the first listed of those
/// within [`TIE`] of it (`None` when no bond is left).
fn strongest(magnitudes: &[Real], alive: &[bool]) -> Option<usize> {
    let top = (0..magnitudes.len())
        .filter(|&k| alive[k])
        .map(|k| magnitudes[k])
        .reduce(Real::max)?;
    (0..magnitudes.len()).find(|&k| alive[k] && magnitudes[k] >= top * (1.0 - TIE))
}

fn mean(v: &[Real]) -> Real {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<Real>() / v.len() as Real
    }
}

fn cv(v: &[Real]) -> Real {
    let mu = mean(v);
    if mu.is_nan() || mu <= 0.0 {
        return 0.0;
    }
    let var = v.iter().map(|x| (x - mu) * (x - mu)).sum::<Real>() / v.len() as Real;
    var.sqrt() / mu
}

/// The force on body i of every bond (zero for a broken one).
fn bond_forces<const D: usize>(
    bonds: &[BondGeometry<D>],
    alive: &[bool],
    u: &[Real],
    springs: solver::Springs,
) -> Vec<Vector<D>> {
    let m = body_dofs(D);
    bonds
        .iter()
        .zip(alive)
        .map(|(g, &on)| {
            if !on {
                return Vector::zero();
            }
            let k = spring::stiffness::<D>(&g.normal, springs.kn, springs.kt);
            let i = g.i as usize * m;
            let uj = g.j.map(|j| &u[j as usize * m..j as usize * m + m]);
            spring::bond_force::<D>(g, &k, &u[i..i + m], uj)
        })
        .collect()
}

/// Bodies whose ground springs carry more than `1e-6` of the total load (a
/// torque counted as the force at the body's reach).
fn unstable_bodies<const D: usize>(u: &[Real], ground: &[Real], reach: &[Real]) -> u64 {
    let m = body_dofs(D);
    let limit = 1e-6 * TOTAL;
    (0..reach.len())
        .filter(|&b| {
            let at = b * m;
            let force: Real = (0..D)
                .map(|c| (ground[at + c] * u[at + c]).powi(2))
                .sum::<Real>()
                .sqrt();
            let torque: Real = (D..m)
                .map(|c| (ground[at + c] * u[at + c]).powi(2))
                .sum::<Real>()
                .sqrt();
            force > limit || (reach[b] > 0.0 && torque / reach[b] > limit)
        })
        .count() as u64
}

/// Union–find over bodies and the five wall nodes.
struct Pieces {
    parent: Vec<u32>,
}

impl Pieces {
    fn of<const D: usize>(bonds: &[BondGeometry<D>], alive: &[bool], bodies: usize) -> Self {
        let mut p = Pieces {
            parent: (0..(bodies + network::WALL_NODES) as u32).collect(),
        };
        for (g, _) in bonds.iter().zip(alive).filter(|(_, a)| **a) {
            let other = match (g.j, g.wall) {
                (Some(j), _) => j as usize,
                (None, Some(w)) => bodies + network::wall_node(w),
                (None, None) => continue,
            };
            p.join(g.i as usize, other);
        }
        p
    }

    fn root(&mut self, mut a: usize) -> usize {
        while self.parent[a] as usize != a {
            let up = self.parent[self.parent[a] as usize];
            self.parent[a] = up;
            a = up as usize;
        }
        a
    }

    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            // The smaller root wins, so the result does not depend on bond order.
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi] = lo as u32;
        }
    }
}

/// The connected pieces with at least one body, the bodies in the largest,
/// and whether the bed has failed: a loaded body sits in a piece with no
/// floor or wall bond, or a group's load has nowhere to go (`loads` is `None`).
fn network_state<const D: usize>(
    bonds: &[BondGeometry<D>],
    alive: &[bool],
    bodies: usize,
    loads: Option<&[AppliedLoad<D>]>,
) -> (u64, u64, bool) {
    let mut p = Pieces::of(bonds, alive, bodies);
    let mut size = vec![0u64; bodies + network::WALL_NODES];
    for b in 0..bodies {
        let r = p.root(b);
        size[r] += 1;
    }
    let count = size.iter().filter(|&&s| s > 0).count() as u64;
    let largest = size.iter().copied().max().unwrap_or(0);
    let failed = match loads {
        None => true,
        Some(loads) => {
            let mut supported = vec![false; bodies + network::WALL_NODES];
            for w in 0..network::WALL_NODES {
                let r = p.root(bodies + w);
                supported[r] = true;
            }
            loads
                .iter()
                .filter(|l| l.force.norm() > 0.0)
                .any(|l| !supported[p.root(l.body as usize)])
        }
    };
    (count, largest, failed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_to_rounding_go_to_the_first_listed() {
        let alive = [true, true, true, false];
        // Bonds 0 and 2 carry the same force by symmetry, rounded apart.
        let m = [0.5, 0.25, 0.5 + 1e-15, 0.9];
        assert_eq!(strongest(&m, &alive), Some(0));
        assert_eq!(strongest(&[0.5, 0.25, 0.5 + 1e-6, 0.9], &alive), Some(2));
        assert_eq!(strongest(&m, &[false; 4]), None);
    }

    #[test]
    fn forces_break_nothing_and_match_the_intact_bed_of_fragment() {
        // Three discs in a row on the floor of a walled box, one on top.
        let bed = Bed::of_discs(
            [6.0, 10.0],
            false,
            &[
                (1.0, 1.0, 1.0),
                (3.0, 1.0, 1.0),
                (5.0, 1.0, 1.0),
                (2.0, 1.0 + 3f64.sqrt(), 1.0),
            ],
        );
        let contacts = crate::analysis::find_contacts(&bed, 1e-6);
        let options = FragmentationConfig::default();
        let intact = forces(&bed, &contacts, &options).unwrap();
        let broken = fragment(&bed, &contacts, &options).unwrap();
        assert!(intact.steps.is_empty() && intact.summary.breaks == 0);
        assert!(!broken.steps.is_empty());
        assert_eq!(intact.forces, broken.forces);
        assert_eq!(intact.summary.max_force, broken.summary.max_force);
    }
}
