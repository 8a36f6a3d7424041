//! The loads on a bed (`spec/fragmentation.md`, "Loads"): the top and bottom
//! bodies, where their shares act, and how a group's total is shared again
//! when one of its bodies loses its last bond.

use super::network::{Bodies, BondGeometry};
use super::spring::{self, body_dofs};
use super::Load;
use crate::bed::Bed;
use crate::container::Wall;
use crate::math::{Real, Vector};

/// The total force of every load (the source study's F = 1).
pub const TOTAL: Real = 1.0;

/// A force on one body at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppliedLoad<const D: usize> {
    /// Body index.
    pub body: u32,
    /// Where it acts (in the box).
    pub point: Vector<D>,
    /// The point relative to the body's reference point.
    pub arm: Vector<D>,
    /// The force.
    pub force: Vector<D>,
}

/// Bodies sharing one total force: the top bodies, the bottom bodies, or
/// (gravity) every body, each with its weight.
#[derive(Clone, Debug)]
struct Group<const D: usize> {
    members: Vec<AppliedLoad<D>>,
    /// Share of each member (equal, or by solid volume under gravity).
    weights: Vec<Real>,
    total: Vector<D>,
}

/// The loaded groups of a bed.
#[derive(Clone, Debug)]
pub struct Loads<const D: usize> {
    groups: Vec<Group<D>>,
}

/// Top bodies of `bed`: no contact partner's reference point above its own,
/// and a highest point within `2 r_max` of the bed's highest point.
pub fn top_bodies<const D: usize>(
    bed: &Bed<D>,
    bodies: &Bodies<D>,
    bonds: &[BondGeometry<D>],
) -> Vec<u32> {
    let up = D - 1;
    let mut covered = vec![false; bodies.len()];
    for g in bonds {
        if let Some(j) = g.j {
            let (i, j) = (g.i as usize, j as usize);
            let (zi, zj) = (bodies.reference[i][up], bodies.reference[j][up]);
            if zj > zi {
                covered[i] = true;
            }
            if zi > zj {
                covered[j] = true;
            }
        }
    }
    let high = highest_points(bed, bodies);
    let top = high.iter().fold(Real::NEG_INFINITY, |a, (_, h)| a.max(*h));
    let reach = 2.0 * bed.r_max();
    (0..bodies.len() as u32)
        .filter(|&b| !covered[b as usize] && high[b as usize].1 >= top - reach)
        .collect()
}

/// Each body's highest bead (the first of equals) and its highest point's height.
fn highest_points<const D: usize>(bed: &Bed<D>, bodies: &Bodies<D>) -> Vec<(u32, Real)> {
    let mut high = vec![(u32::MAX, Real::NEG_INFINITY); bodies.len()];
    for k in 0..bed.len() {
        let b = bodies.of_particle[k] as usize;
        let h = bed.centres[k][D - 1] + bed.radii[k];
        if h > high[b].1 {
            high[b] = (k as u32, h);
        }
    }
    high
}

/// Each body's lowest bead (the first of equals).
fn lowest_beads<const D: usize>(bed: &Bed<D>, bodies: &Bodies<D>) -> Vec<u32> {
    let mut low = vec![(u32::MAX, Real::INFINITY); bodies.len()];
    for k in 0..bed.len() {
        let b = bodies.of_particle[k] as usize;
        let h = bed.centres[k][D - 1] - bed.radii[k];
        if h < low[b].1 {
            low[b] = (k as u32, h);
        }
    }
    low.into_iter().map(|(k, _)| k).collect()
}

/// The load at bead `k`'s surface point `r · dir` from its centre.
fn at_bead<const D: usize>(
    bed: &Bed<D>,
    bodies: &Bodies<D>,
    k: u32,
    dir: Real,
    force: Vector<D>,
) -> AppliedLoad<D> {
    let k = k as usize;
    let to_point = Vector::<D>::up() * (dir * bed.radii[k]);
    AppliedLoad {
        body: bodies.of_particle[k],
        point: bed.centres[k] + to_point,
        arm: bodies.lever[k] + to_point,
        force,
    }
}

impl<const D: usize> Loads<D> {
    /// The loads of `load` on the intact bed.
    pub fn new(load: Load, bed: &Bed<D>, bodies: &Bodies<D>, bonds: &[BondGeometry<D>]) -> Self {
        let x = Vector::<D>::axis(0) * TOTAL;
        let down = Vector::<D>::up() * -TOTAL;
        let tops = || {
            let high = highest_points(bed, bodies);
            top_bodies(bed, bodies, bonds)
                .into_iter()
                .map(|b| at_bead(bed, bodies, high[b as usize].0, 1.0, Vector::zero()))
                .collect::<Vec<_>>()
        };
        let groups = match load {
            Load::Shear => {
                let mut on_floor = vec![false; bodies.len()];
                for g in bonds.iter().filter(|g| g.wall == Some(Wall::Floor)) {
                    on_floor[g.i as usize] = true;
                }
                let low = lowest_beads(bed, bodies);
                let bottoms = (0..bodies.len())
                    .filter(|&b| on_floor[b])
                    .map(|b| at_bead(bed, bodies, low[b], -1.0, Vector::zero()))
                    .collect();
                vec![Group::equal(tops(), x), Group::equal(bottoms, -x)]
            }
            Load::Compression => vec![Group::equal(tops(), down)],
            Load::Gravity => {
                let volumes = crate::analysis::packing::particle_volumes(bed);
                let mut weights = vec![0.0; bodies.len()];
                for (k, v) in volumes.iter().enumerate() {
                    weights[bodies.of_particle[k] as usize] += v;
                }
                let members = (0..bodies.len() as u32)
                    .map(|b| AppliedLoad {
                        body: b,
                        point: bodies.reference[b as usize],
                        arm: Vector::zero(),
                        force: Vector::zero(),
                    })
                    .collect();
                vec![Group {
                    members,
                    weights,
                    total: down,
                }]
            }
        };
        Loads { groups }
    }

    /// The loads on bodies that still have a bond (`bonded[b]`): each group's
    /// total shared by its bonded members by their weights. `None` when a
    /// group has no bonded member left: the load has nowhere to go.
    pub fn current(&self, bonded: &[bool]) -> Option<Vec<AppliedLoad<D>>> {
        let mut out = Vec::new();
        for g in &self.groups {
            let weight: Real = g
                .members
                .iter()
                .zip(&g.weights)
                .filter(|(m, _)| bonded[m.body as usize])
                .map(|(_, w)| w)
                .sum();
            if weight.is_nan() || weight <= 0.0 {
                return None;
            }
            for (m, w) in g.members.iter().zip(&g.weights) {
                if bonded[m.body as usize] {
                    out.push(AppliedLoad {
                        force: g.total * (w / weight),
                        ..*m
                    });
                }
            }
        }
        Some(out)
    }

    /// True when no group has a member (a bed without top bodies, say).
    pub fn is_empty(&self) -> bool {
        self.groups.iter().all(|g| g.members.is_empty())
    }
}

impl<const D: usize> Group<D> {
    fn equal(members: Vec<AppliedLoad<D>>, total: Vector<D>) -> Self {
        Group {
            weights: vec![1.0; members.len()],
            members,
            total,
        }
    }
}

/// The generalized load vector of `loads` over `bodies` bodies.
pub fn load_vector<const D: usize>(loads: &[AppliedLoad<D>], bodies: usize) -> Vec<Real> {
    let m = body_dofs(D);
    let mut b = vec![0.0; bodies * m];
    for l in loads {
        let g = spring::generalized::<D>(&l.arm, &l.force);
        let at = l.body as usize * m;
        for c in 0..m {
            b[at + c] += g[c];
        }
    }
    b
}
