//! The loads on a bed (`docs/reference/fragmentation.md`, "Loads"): the top and bottom
//! bodies, where their shares act, and how a group's total is shared again
//! when one of its bodies loses its last bond.

use super::network::{Bodies, BondGeometry};
use super::spring::{self, body_dofs};
use super::Load;
use crate::bed::Bed;
use crate::container::Wall;
use crate::error::{Error, Result};
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
    /// Which bodies it loads, to say which are missing when it has none.
    role: Role,
    members: Vec<AppliedLoad<D>>,
    /// Share of each member (equal, or by solid volume under gravity).
    weights: Vec<Real>,
    total: Vector<D>,
}

/// The bodies a group loads.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    Top,
    Bottom,
    Every,
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
    /// The loads of `load` on the intact bed; an error saying which bodies
    /// are missing and why when a group the load needs has none (a bed whose
    /// highest bodies all have a partner above them has no top body).
    pub fn new(
        load: Load,
        bed: &Bed<D>,
        bodies: &Bodies<D>,
        bonds: &[BondGeometry<D>],
    ) -> Result<Self> {
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
                vec![
                    Group::equal(Role::Top, tops(), x),
                    Group::equal(Role::Bottom, bottoms, -x),
                ]
            }
            Load::Compression => vec![Group::equal(Role::Top, tops(), down)],
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
                    role: Role::Every,
                    members,
                    weights,
                    total: down,
                }]
            }
        };
        if let Some(g) = groups.iter().find(|g| g.members.is_empty()) {
            return Err(Error::Impossible(match g.role {
                Role::Top => no_top_body(load, bed, bodies),
                Role::Bottom => format!(
                    "no body qualifies as bottom: bottom bodies are those touching the floor, \
                     and none does here, so the {} load on the top bodies has nothing to \
                     balance it; a bed resting on its floor would have them, and the \
                     `compression` or `gravity` load needs none",
                    load.name()
                ),
                Role::Every => "the bed has no body to load".into(),
            }));
        }
        Ok(Loads { groups })
    }

    /// Why [`current`](Self::current) found no load: the group whose bodies
    /// all have lost (or never had) a bond.
    pub fn unbonded(&self, bonded: &[bool]) -> Error {
        let g = self
            .groups
            .iter()
            .find(|g| !g.members.iter().any(|m| bonded[m.body as usize]));
        let (n, which) = match g {
            Some(g) => (
                g.members.len(),
                match g.role {
                    Role::Top => "top",
                    Role::Bottom => "bottom",
                    Role::Every => "loaded",
                },
            ),
            None => (0, "loaded"),
        };
        Error::Impossible(format!(
            "the {n} {which} bodies have no bonds (they touch no other body and no wall), \
             so their load has nowhere to go"
        ))
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
}

/// Why a bed has no top body, by the rule of [`top_bodies`], and what would
/// give it one.
fn no_top_body<const D: usize>(load: Load, bed: &Bed<D>, bodies: &Bodies<D>) -> String {
    let high = highest_points(bed, bodies);
    let top = high.iter().fold(Real::NEG_INFINITY, |a, (_, h)| a.max(*h));
    let reach = 2.0 * bed.r_max();
    let near = high.iter().filter(|(_, h)| *h >= top - reach).count();
    // Four decimals: enough to recognise the heights in the bed file.
    let round = |x: Real| (x * 1e4).round() / 1e4;
    format!(
        "no body qualifies as top, so the {} load has nowhere to act: a top body has no \
         bonded partner whose reference point (centre of its beads) is higher than its own, and \
         reaches within 2 r_max = {} of the bed's highest point ({}); here every body \
         reaching that high ({near} of them) has a partner above its reference point (a tall or tilted \
         body with a lower one resting against it, say). A bed whose highest bodies have \
         nothing resting on them would have top bodies; the `gravity` load needs none",
        load.name(),
        round(reach),
        round(top),
    )
}

impl<const D: usize> Group<D> {
    fn equal(role: Role, members: Vec<AppliedLoad<D>>, total: Vector<D>) -> Self {
        Group {
            role,
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
