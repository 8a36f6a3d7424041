//! The bond network of a bed: one rigid body per sphere or chain, one bond per
//! contact of the analysis (particle pairs, floor, side walls), with the
//! geometry the spring law needs (`docs/reference/fragmentation.md`, "The network").
//!
//! Every lever arm is built from minimum-image displacements, never from
//! absolute positions, so that a chain or a pair across a periodic side has the
//! same arms as anywhere else.

use crate::analysis::Contacts;
use crate::bed::Bed;
use crate::container::Wall;
use crate::math::{Real, Vector};

/// The walls a bond can join, in the order of their node numbers in the
/// network's connectivity (after the bodies).
pub const WALL_NODES: usize = 5;

/// Node number of `wall` among the wall nodes (floor 0, x0 1, x1 2, y0 3, y1 4).
pub fn wall_node(wall: Wall) -> usize {
    match wall {
        Wall::Floor => 0,
        Wall::Low(k) => 1 + 2 * k,
        Wall::High(k) => 2 + 2 * k,
    }
}

/// The rigid bodies of a bed.
#[derive(Clone, Debug)]
pub struct Bodies<const D: usize> {
    /// The bed's body id of each body, in order of first appearance.
    pub ids: Vec<u32>,
    /// Reference point `x_b`: the centre of a sphere, the mean of a chain's
    /// bead centres (unwrapped across periodic sides).
    pub reference: Vec<Vector<D>>,
    /// `ρ_b`: the largest distance from `x_b` to a bead surface.
    pub reach: Vec<Real>,
    /// Body index of each particle.
    pub of_particle: Vec<u32>,
    /// Each particle's centre relative to its body's reference point.
    pub lever: Vec<Vector<D>>,
}

impl<const D: usize> Bodies<D> {
    /// The bodies of `bed`.
    pub fn of(bed: &Bed<D>) -> Self {
        let n = bed.len();
        // Body ids of imported beds need not be dense or consecutive.
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_by_key(|&k| (bed.bodies[k as usize], k));
        let mut ids = Vec::new();
        let mut of_particle = vec![0u32; n];
        let mut first = Vec::new();
        for &k in &order {
            let id = bed.bodies[k as usize];
            if ids.last() != Some(&id) {
                ids.push(id);
                first.push(k);
            }
            of_particle[k as usize] = (ids.len() - 1) as u32;
        }
        // Number bodies by first appearance in the bed, so that a bed of spheres
        // has body index = particle index.
        let mut by_appearance: Vec<usize> = (0..ids.len()).collect();
        by_appearance.sort_by_key(|&b| first[b]);
        let mut rank = vec![0u32; ids.len()];
        for (r, &b) in by_appearance.iter().enumerate() {
            rank[b] = r as u32;
        }
        let ids: Vec<u32> = by_appearance.iter().map(|&b| ids[b]).collect();
        let first: Vec<u32> = by_appearance.iter().map(|&b| first[b]).collect();
        for b in of_particle.iter_mut() {
            *b = rank[*b as usize];
        }
        let nb = ids.len();
        let mut offset = vec![Vector::<D>::zero(); n];
        let mut mean = vec![Vector::<D>::zero(); nb];
        let mut beads = vec![0usize; nb];
        for k in 0..n {
            let b = of_particle[k] as usize;
            let anchor = &bed.centres[first[b] as usize];
            offset[k] = bed.container.displacement(anchor, &bed.centres[k]);
            mean[b] += offset[k];
            beads[b] += 1;
        }
        for b in 0..nb {
            mean[b] = mean[b] * (1.0 / beads[b] as Real);
        }
        let mut lever = vec![Vector::<D>::zero(); n];
        let mut reach = vec![0.0; nb];
        for k in 0..n {
            let b = of_particle[k] as usize;
            lever[k] = offset[k] - mean[b];
            reach[b] = Real::max(reach[b], lever[k].norm() + bed.radii[k]);
        }
        let reference = (0..nb)
            .map(|b| bed.centres[first[b] as usize] + mean[b])
            .collect();
        Bodies {
            ids,
            reference,
            reach,
            of_particle,
            lever,
        }
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True without bodies.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }
}

/// One bond: a contact between two bodies or a body and a wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BondGeometry<const D: usize> {
    /// Body index of body i.
    pub i: u32,
    /// Body index of body j, or `None` for a wall.
    pub j: Option<u32>,
    /// The wall of a wall bond.
    pub wall: Option<Wall>,
    /// Particle (bead) of body i.
    pub bead_i: u32,
    /// Particle (bead) of body j.
    pub bead_j: Option<u32>,
    /// Contact point, in the box (wrapped across periodic sides).
    pub point: Vector<D>,
    /// Unit normal from bead i's centre towards bead j (or the wall).
    pub normal: Vector<D>,
    /// Contact point relative to body i's reference point.
    pub arm_i: Vector<D>,
    /// Contact point relative to body j's reference point (zero for a wall).
    pub arm_j: Vector<D>,
}

/// The bonds of `bed`: every pair of `contacts` (in its order), then every
/// floor and side-wall contact (in its order). Pairs whose centres coincide
/// have no normal and are skipped (they cannot come from a valid bed).
pub fn bonds<const D: usize>(
    bed: &Bed<D>,
    bodies: &Bodies<D>,
    contacts: &Contacts,
) -> Vec<BondGeometry<D>> {
    let mut out = Vec::with_capacity(contacts.pairs.len() + contacts.walls.len());
    for c in &contacts.pairs {
        let (a, b) = (c.i as usize, c.j as usize);
        let d = bed.container.displacement(&bed.centres[a], &bed.centres[b]);
        let Some(n) = d.normalized() else { continue };
        let to_point = n * bed.radii[a];
        let arm_i = bodies.lever[a] + to_point;
        // The point seen from bead j's image: p − c_j' = r_a n − d.
        let arm_j = bodies.lever[b] + (to_point - d);
        out.push(BondGeometry {
            i: bodies.of_particle[a],
            j: Some(bodies.of_particle[b]),
            wall: None,
            bead_i: a as u32,
            bead_j: Some(b as u32),
            point: bed.container.wrap(bed.centres[a] + to_point),
            normal: n,
            arm_i,
            arm_j,
        });
    }
    for c in &contacts.walls {
        let a = c.i as usize;
        let n = -bed.container.wall_normal(c.wall);
        let to_point = n * bed.radii[a];
        out.push(BondGeometry {
            i: bodies.of_particle[a],
            j: None,
            wall: Some(c.wall),
            bead_i: a as u32,
            bead_j: None,
            point: bed.centres[a] + to_point,
            normal: n,
            arm_i: bodies.lever[a] + to_point,
            arm_j: Vector::zero(),
        });
    }
    out
}
