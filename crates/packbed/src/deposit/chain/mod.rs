//! Settling of a rigid chain of beads (a straight row of equal spheres) onto the
//! fixed bed: quasi-static steepest descent of its centre of mass in
//! configuration space (translation and rotation together), frictionless, with
//! no penetration, until gravity is balanced by compressive contact forces.
//!
//! The configuration is the centre of mass `c` and the unit axis `a`; bead `k`
//! sits at `c + s_k a`. Generalised velocities are `(v, ω ρ)` with `ρ` the radius
//! of gyration, so that the Euclidean metric on them is the kinetic-energy metric
//! (the descent is the one a heavily damped body would follow). A contact of bead
//! `k` with an obstacle (inflated sphere or plane, normal `n`) has the gap rate
//! `J · (v, ωρ)` with `J = (n, (l × n)/ρ)`, `l = s_k a` (a scalar torque in 2D).
//! Gravity is the generalised force `(−e_z, 0)`.
//!
//! Each iteration:
//! 1. Candidate contacts within the step's reach are gathered from the grid.
//!    With none touching, the body falls straight down to the exact first hit.
//! 2. Non-negative least squares `(e_z, 0) ≈ Σ λ_i J_i` over the touching ones.
//!    A zero residual is a balance; it is a rest unless a tangent direction of
//!    the supports lowers the centre of mass at second order (on top of a
//!    sphere, an upright chain on the floor): each direction of the supports'
//!    null space is tried (first a random one, drawn from the run's generator)
//!    and the body is tipped along the first that goes down.
//! 3. Otherwise the residual's negative is the projected steepest descent
//!    direction `u` (Moreau: it lies in the cone of admissible motions and
//!    keeps every supporting contact). The step is bounded by conservative
//!    advancement against every non-touching candidate (a lower bound on each
//!    gap along the step, using the convexity of the distance to a point and a
//!    bound on the curvature of the rotation), and by an Armijo line search on
//!    the height; after the linear step the supporting contacts (and any
//!    touched ones that would penetrate) are restored exactly by a Gauss–Newton
//!    projection, so errors do not accumulate.
//!
//! When this fast path (normal-equation NNLS, energy line search) can neither
//! step nor certify a rest, which happens with nearly parallel supports (a rod
//! along a rod), a rare path decides: the balance measured as the independent
//! rest test measures it (QR, every shut contact), polished if needed
//! (`Settler::rare_rest`).
//!
//! A body that does not come to rest within `settle::MAX_ITERATIONS` is reported as
//! stuck (the engine re-drops it and counts it).

mod contacts;
mod momentum;
mod project;
mod rest;
mod settle;

use super::obstacle::Obstacle;
use super::roll::Terrain;
use crate::geometry::Surface;
use crate::math::{moment, rotate, Gen, Real, Vector, MAX_GEN_COLUMNS};

pub(crate) use settle::settle_chain;

/// Largest gap of a support at rest (times the bead radius): well inside the
/// model's contact tolerance of 1e-9 r.
const REST_GAP: Real = 1e-10;
/// Largest displacement of any bead point in one step (times the bead radius):
/// keeps the linearisation honest and bounds the neighbourhood to gather.
const MAX_STEP: Real = 0.25;
/// Contact forces below this fraction of the total are no forces.
const FORCE_TOL: Real = 1e-12;
/// Most touching contacts used at once (a rod of 17 beads lying along another
/// has more than 16).
const MAX_TOUCHING: usize = MAX_GEN_COLUMNS;

/// The shape of a chain: `beads` spheres of radius `r`, centres `spacing · r`
/// apart on a straight line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainShape {
    /// Number of beads (at least 1).
    pub beads: u32,
    /// Centre distance in bead radii.
    pub spacing: Real,
    /// Bead radius.
    pub r: Real,
}

impl ChainShape {
    /// Signed distance of bead `k`'s centre from the centre of mass along the axis.
    #[inline]
    pub(crate) fn offset(&self, k: u32) -> Real {
        (k as Real - 0.5 * (self.beads - 1) as Real) * self.spacing * self.r
    }

    /// Distance from the centre of mass to the end beads' centres.
    #[inline]
    pub(crate) fn half_length(&self) -> Real {
        0.5 * (self.beads - 1) as Real * self.spacing * self.r
    }

    /// Radius of gyration about an axis through the centre of mass normal to the
    /// chain (beads as point masses plus their own inertia; overlaps ignored, it
    /// only sets the metric of the descent).
    fn gyration<const D: usize>(&self) -> Real {
        let n = self.beads as Real;
        let mean_s2 = (0..self.beads)
            .map(|k| self.offset(k).powi(2))
            .sum::<Real>()
            / n;
        let own = if D == 2 { 0.5 } else { 0.4 };
        (mean_s2 + own * self.r * self.r).sqrt()
    }

    /// The bead centres of a chain with centre of mass `com` and unit axis `axis`.
    pub fn beads<const D: usize>(&self, com: Vector<D>, axis: Vector<D>) -> Vec<Vector<D>> {
        (0..self.beads)
            .map(|k| com + axis * self.offset(k))
            .collect()
    }
}

/// Position of a chain: centre of mass and unit axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<const D: usize> {
    /// Centre of mass (the middle of the axis).
    pub com: Vector<D>,
    /// Unit vector along the axis.
    pub axis: Vector<D>,
}

/// A possible contact of one bead with one obstacle, evaluated at a pose.
#[derive(Clone, Copy, Debug)]
struct Candidate<const D: usize> {
    bead: u32,
    obstacle: Obstacle<D>,
    gap: Real,
    row: Gen,
}

/// The settling machinery for one chain shape on one terrain.
struct Settler<'t, 'a, const D: usize> {
    terrain: &'t Terrain<'a, D>,
    shape: ChainShape,
    rho: Real,
    /// Beads per neighbour query (a chunk spans at most a few radii).
    chunk: u32,
}

impl<const D: usize> Settler<'_, '_, D> {
    #[inline]
    fn bead(&self, pose: &Pose<D>, k: u32) -> Vector<D> {
        pose.com + pose.axis * self.shape.offset(k)
    }

    /// Gap and generalised normal of bead `k` against `obstacle`.
    #[inline]
    fn evaluate(&self, pose: &Pose<D>, bead: u32, obstacle: Obstacle<D>) -> Candidate<D> {
        let b = self.bead(pose, bead);
        let (n, gap) = match obstacle.surface {
            Surface::Ball { centre, radius } => {
                let d = b - centre;
                let dist = d.norm();
                (d / dist, dist - radius)
            }
            Surface::Plane { normal, offset } => (normal, normal.dot(&b) - offset),
        };
        let l = pose.axis * self.shape.offset(bead);
        let mut row = Gen::zero();
        row.0[..D].copy_from_slice(&n.0);
        let torque = moment(&l, &n);
        let slots = if D == 2 { 2..3 } else { 3..6 };
        for (t, slot) in slots.enumerate() {
            row[slot] = torque[t] / self.rho;
        }
        Candidate {
            bead,
            obstacle,
            gap,
            row,
        }
    }

    /// Moves the pose by the generalised displacement `u · h`; returns the change
    /// of the centre of mass's height (exact, free of the cancellation that
    /// subtracting two large heights would suffer).
    fn advance(&self, pose: &mut Pose<D>, u: &Gen, h: Real) -> Real {
        for k in 0..D {
            pose.com[k] += u[k] * h;
        }
        let s = h / self.rho;
        let w = if D == 2 {
            [u[2] * s, 0.0, 0.0]
        } else {
            [u[3] * s, u[4] * s, u[5] * s]
        };
        pose.axis = rotate(pose.axis, w);
        if let Some(n) = pose.axis.normalized() {
            pose.axis = n;
        }
        u[D - 1] * h
    }

    /// How fast the chain's fastest point moves along the generalised direction
    /// `u`, and how fast the chain turns (the step bounds of the descent).
    fn speed(&self, u: &Gen) -> (Real, Real) {
        let mut uv: Real = 0.0;
        let mut uw: Real = 0.0;
        for i in 0..6 {
            if i < D {
                uv += u[i] * u[i];
            } else {
                uw += u[i] * u[i];
            }
        }
        let turn = uw.sqrt() / self.rho;
        (
            uv.sqrt() + turn * (self.shape.half_length() + self.shape.r),
            turn,
        )
    }

    /// Conservative advancement: the longest step along `u` (turning at the
    /// rate `turn`) before candidate `c`'s gap could close, a lower bound on
    /// the gap along the step from the convexity of the distance to a point
    /// and a bound on the curvature of the rotation (infinite if it opens).
    fn advancement(&self, c: &Candidate<D>, u: &Gen, turn: Real) -> Real {
        let rate = c.row.dot(u);
        let gap = c.gap.max(0.0);
        let kappa = turn * turn * self.shape.offset(c.bead).abs();
        let disc = (rate * rate + 4.0 * kappa * gap).sqrt() - rate;
        if disc > 0.0 {
            2.0 * gap / disc
        } else {
            Real::INFINITY
        }
    }

    /// A bound on how far any point of the chain moved from `a` to `b`.
    #[inline]
    fn reach(&self, a: &Pose<D>, b: &Pose<D>) -> Real {
        (b.com - a.com).norm()
            + (b.axis - a.axis).norm() * (self.shape.half_length() + self.shape.r)
    }
}

/// True when `PACKBED_CHAIN_DEBUG` asks for diagnostics of stuck chains on
/// stderr.
fn debug_on() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("PACKBED_CHAIN_DEBUG").is_some())
}
