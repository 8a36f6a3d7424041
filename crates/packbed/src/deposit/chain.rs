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
//! A body that does not come to rest within [`MAX_ITERATIONS`] is reported as
//! stuck (the engine re-drops it and counts it).

use super::obstacle::{particle_key, wall_obstacle, Obstacle};
use super::roll::Terrain;
use crate::geometry::Surface;
use crate::math::{Real, Vector};
use rand::RngExt;

/// A generalised vector: translation in slots `0..D`, rotation (times the radius
/// of gyration) in slot 2 (2D) or slots 3–5 (3D).
type Gen = Vector<6>;

/// Iterations after which a chain counts as stuck.
pub(crate) const MAX_ITERATIONS: usize = 20_000;
/// Gap below which an obstacle touches the chain (times the bead radius).
const CONTACT_TOL: Real = 1e-7;
/// Largest gap of a support at rest (times the bead radius): well inside the
/// model's contact tolerance of 1e-9 r.
const REST_GAP: Real = 1e-10;
/// Penetration that the projection must remove (times the bead radius).
const PENETRATION_TOL: Real = 1e-12;
/// Largest displacement of any bead point in one step (times the bead radius):
/// keeps the linearisation honest and bounds the neighbourhood to gather.
const MAX_STEP: Real = 0.25;
/// NNLS residual below which the forces balance, relative to the sum of the
/// contact forces (in units of the weight), as for spheres.
const REST_TOL: Real = 1e-10;
/// Largest residual of a balance after its supports are shut (forces solved
/// again), in units of the weight: a hundredth of the independent checker's
/// bound (`1e-7`; the engine's metric gives the larger residual).
const POST_REST_TOL: Real = 1e-9;
/// Contact forces below this fraction of the total are no forces.
const FORCE_TOL: Real = 1e-12;
/// Size of the tipping trial move at a balance (times the bead radius).
const TIP_STEP: Real = 1e-3;
/// Height drop of a tipping trial that counts as going down (times the bead
/// radius): far above rounding, far below the drop of a real unstable balance
/// (about `TIP_STEP² r / (2 (1 + R/r))`).
const TIP_DROP: Real = 1e-10;
/// Most tipping moves after failed line searches, per chain.
const MAX_NUDGES: usize = 8;
/// Largest rest residual accepted by the QR balance of the rare path (see
/// [`Settler::balance_qr`]), in units of the weight and in the independent
/// checker's metric: a tenth of the checker's bound (`1e-7`).
const QR_REST_TOL: Real = 1e-8;
/// Largest gap of a contact counted by the QR balance of the rare path (times
/// the bead radius): half the model's contact tolerance (`1e-9 r`), within
/// which the independent checker counts a contact.
const QR_SHUT: Real = 5e-10;
/// Largest overlap accepted at a rest found by the rare path (times the bead
/// radius): a tenth of the model's bound (`1e-9 r`).
const QR_OVERLAP: Real = 1e-10;
/// Most touching contacts used at once (a rod of 17 beads lying along another
/// has more than 16).
const MAX_TOUCHING: usize = 48;

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
    pub fn offset(&self, k: u32) -> Real {
        (k as Real - 0.5 * (self.beads - 1) as Real) * self.spacing * self.r
    }

    /// Distance from the centre of mass to the end beads' centres.
    #[inline]
    pub fn half_length(&self) -> Real {
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
        if D == 2 {
            row[2] = (l[0] * n[1] - l[1] * n[0]) / self.rho;
        } else {
            row[3] = (l[1] * n[2] - l[2] * n[1]) / self.rho;
            row[4] = (l[2] * n[0] - l[0] * n[2]) / self.rho;
            row[5] = (l[0] * n[1] - l[1] * n[0]) / self.rho;
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
        let a = pose.axis;
        if D == 2 {
            let t = u[2] * s;
            let (sn, cs) = t.sin_cos();
            pose.axis[0] = a[0] * cs - a[1] * sn;
            pose.axis[1] = a[0] * sn + a[1] * cs;
        } else {
            let w = [u[3] * s, u[4] * s, u[5] * s];
            let t = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            if t > 0.0 {
                let k = [w[0] / t, w[1] / t, w[2] / t];
                let (sn, cs) = t.sin_cos();
                let kxa = [
                    k[1] * a[2] - k[2] * a[1],
                    k[2] * a[0] - k[0] * a[2],
                    k[0] * a[1] - k[1] * a[0],
                ];
                let kda = k[0] * a[0] + k[1] * a[1] + k[2] * a[2];
                for i in 0..3 {
                    pose.axis[i] = a[i] * cs + kxa[i] * sn + k[i] * kda * (1.0 - cs);
                }
            }
        }
        if let Some(n) = pose.axis.normalized() {
            pose.axis = n;
        }
        u[D - 1] * h
    }

    /// A bound on how far any point of the chain moved from `a` to `b`.
    #[inline]
    fn reach(&self, a: &Pose<D>, b: &Pose<D>) -> Real {
        (b.com - a.com).norm()
            + (b.axis - a.axis).norm() * (self.shape.half_length() + self.shape.r)
    }

    /// Every bead–obstacle pair whose gap is below `margin` (fixed particles
    /// through their periodic images, walls and floor).
    fn gather(&self, pose: &Pose<D>, margin: Real, out: &mut Vec<Candidate<D>>) {
        out.clear();
        let t = self.terrain;
        let r = self.shape.r;
        let reach = r + t.r_fixed_max + margin;
        let mut first = 0;
        while first < self.shape.beads {
            let last = (first + self.chunk).min(self.shape.beads);
            let (mut lo, mut hi) = (self.bead(pose, first), self.bead(pose, first));
            for k in first + 1..last {
                let b = self.bead(pose, k);
                for i in 0..D {
                    lo[i] = lo[i].min(b[i]);
                    hi[i] = hi[i].max(b[i]);
                }
            }
            for i in 0..D {
                lo[i] -= reach;
                hi[i] += reach;
            }
            t.grid.for_each_in_box(&lo, &hi, |id, shift, image| {
                let centre = t.centres[id as usize] + shift;
                let radius = r + t.radii[id as usize];
                let obstacle = Obstacle {
                    surface: Surface::Ball { centre, radius },
                    key: particle_key(id, image),
                };
                for k in first..last {
                    let d2 = (self.bead(pose, k) - centre).norm2();
                    let m = radius + margin;
                    if d2 < m * m {
                        out.push(self.evaluate(pose, k, obstacle));
                    }
                }
            });
            first = last;
        }
        let (walls, nw) = t.container.wall_array();
        for &wall in &walls[..nw] {
            let obstacle = wall_obstacle(t.container, wall, r);
            for k in 0..self.shape.beads {
                let c = self.evaluate(pose, k, obstacle);
                if c.gap < margin {
                    out.push(c);
                }
            }
        }
    }

    /// Distance the chain can fall straight down before a bead touches a fixed
    /// particle or the floor (exact: each bead's centre meets an inflated ball on
    /// a vertical line).
    fn fall_distance(&self, pose: &Pose<D>) -> Real {
        let t = self.terrain;
        let r = self.shape.r;
        let mut best = Real::INFINITY;
        for k in 0..self.shape.beads {
            best = best.min(self.bead(pose, k)[D - 1] - r);
        }
        let reach = r + t.r_fixed_max;
        let mut first = 0;
        while first < self.shape.beads {
            let last = (first + self.chunk).min(self.shape.beads);
            let (mut lo, mut hi) = (self.bead(pose, first), self.bead(pose, first));
            for k in first + 1..last {
                let b = self.bead(pose, k);
                for i in 0..D {
                    lo[i] = lo[i].min(b[i]);
                    hi[i] = hi[i].max(b[i]);
                }
            }
            let low = lo[D - 1];
            for i in 0..D - 1 {
                lo[i] -= reach;
                hi[i] += reach;
            }
            lo[D - 1] = 0.0;
            t.grid.scan_down(&lo, &hi, |id, shift, _| {
                let c = t.centres[id as usize] + shift;
                let big_r = r + t.radii[id as usize];
                let r2 = big_r * big_r;
                for k in first..last {
                    let w = self.bead(pose, k) - c;
                    let h2 = w.horizontal().norm2();
                    // Below the obstacle's equator the fall moves away from it.
                    if h2 < r2 && w[D - 1] > 1e-9 * big_r {
                        let d = (w[D - 1] - (r2 - h2).sqrt()).max(0.0);
                        best = best.min(d);
                    }
                }
                low - best - reach
            });
            first = last;
        }
        best.max(0.0)
    }

    /// Restores `gap = 0` on the contacts of `set` by damped Gauss–Newton
    /// (Levenberg–Marquardt in the 6-dimensional generalised space, so nearly
    /// parallel contacts, such as a rod lying along another, give no wild
    /// steps). Returns the height change of the centre of mass, or `None` if it
    /// does not converge.
    ///
    /// Gaps in `[0, slack]` count as restored: supports met along the way by
    /// conservative advancement may be a little open, and nearly parallel
    /// contacts (a rod along a rod) cannot all close at once.
    fn project(&self, pose: &mut Pose<D>, set: &[(u32, Obstacle<D>)], slack: Real) -> Option<Real> {
        // Gaps cannot be resolved below the rounding of the coordinates.
        let scale = pose.com.0.iter().fold(0.0, |m: Real, x| m.max(x.abs()));
        let tol = 1e-14 * self.shape.r + 4.0 * Real::EPSILON * scale;
        let mut dz = 0.0;
        let mut worst: Real = Real::INFINITY;
        let rest_gap = REST_GAP * self.shape.r;
        for _ in 0..40 {
            worst = 0.0;
            let mut jtj = [[0.0; 6]; 6];
            let mut jtg = [0.0; 6];
            for &(bead, obstacle) in set {
                let c = self.evaluate(pose, bead, obstacle);
                // Open supports are closed fully (convergence only asks them
                // to be within the slack), except with the line search's wide
                // slack: then they are pulled back to it, not shut (shutting
                // them may be impossible with the others shut).
                let excess = if c.gap < 0.0 || (c.gap > slack && slack <= rest_gap) {
                    c.gap
                } else if c.gap > slack {
                    c.gap - slack
                } else {
                    continue;
                };
                worst = worst.max(if c.gap < 0.0 { -c.gap } else { c.gap - slack });
                for i in 0..6 {
                    jtg[i] -= c.row[i] * excess;
                    for j in 0..6 {
                        jtj[i][j] += c.row[i] * c.row[j];
                    }
                }
            }
            if worst <= tol {
                return Some(dz);
            }
            let diag = (0..6).map(|i| jtj[i][i]).fold(0.0, Real::max);
            for (i, row) in jtj.iter_mut().enumerate() {
                row[i] += 1e-12 * diag + 1e-300;
            }
            let y = solve(&mut jtj, &mut jtg, 6)?;
            dz += self.advance(pose, &Vector(y), 1.0);
        }
        (worst <= 100.0 * tol).then_some(dz)
    }

    /// Projects `pose` onto the contacts of `set`, adding any candidate that ends
    /// up penetrating, until nothing penetrates. Returns the height change.
    fn project_all(
        &self,
        pose: &mut Pose<D>,
        set: &mut Vec<(u32, Obstacle<D>)>,
        candidates: &[Candidate<D>],
        slack: Real,
    ) -> Option<Real> {
        let pen = PENETRATION_TOL * self.shape.r;
        let mut dz = 0.0;
        for _ in 0..8 {
            if !set.is_empty() {
                dz += self.project(pose, set, slack)?;
            }
            let before = set.len();
            for c in candidates {
                if self.evaluate(pose, c.bead, c.obstacle).gap < -pen
                    && !set
                        .iter()
                        .any(|&(b, o)| b == c.bead && o.key == c.obstacle.key)
                {
                    if set.len() >= MAX_TOUCHING {
                        return None;
                    }
                    set.push((c.bead, c.obstacle));
                }
            }
            if set.len() == before {
                return Some(dz);
            }
        }
        None
    }

    /// The force balance measured as the independent rest test measures it,
    /// for the rare case where the fast normal-equation NNLS cannot resolve a
    /// descent step: every shut contact (gap within `QR_SHUT`, no cap on their
    /// number), torques about the centre of mass scaled by the body's half
    /// length plus a radius, and Lawson–Hanson by Householder QR (nearly
    /// parallel supports, such as a rod in the groove of another, make the
    /// normal equations lose about half the digits). Returns the residual and
    /// the supports (contacts carrying a force).
    fn balance_qr(
        &self,
        candidates: &[Candidate<D>],
        supports: &mut Vec<(u32, Obstacle<D>)>,
    ) -> Real {
        self.balance_qr_vec(candidates, supports).norm()
    }

    /// [`Self::balance_qr`] returning the residual vector, in the checker's
    /// metric (torque slots scaled by `ρ / (half length + r)` relative to the
    /// engine's rows).
    #[cold]
    #[inline(never)]
    fn balance_qr_vec(
        &self,
        candidates: &[Candidate<D>],
        supports: &mut Vec<(u32, Obstacle<D>)>,
    ) -> Gen {
        let shut = QR_SHUT * self.shape.r;
        let scale = self.rho / (self.shape.half_length() + self.shape.r);
        let mut cols: Vec<[Real; 6]> = Vec::new();
        let mut from: Vec<usize> = Vec::new();
        for (i, c) in candidates.iter().enumerate() {
            if c.gap <= shut {
                let mut col = c.row.0;
                for v in &mut col[D..] {
                    *v *= scale;
                }
                cols.push(col);
                from.push(i);
            }
        }
        let q = if D == 2 { 3 } else { 6 };
        let mut target = [0.0; 6];
        target[D - 1] = 1.0;
        let (residual, x) = crate::math::nnls_qr(&cols, q, &target);
        let total: Real = x.iter().sum();
        supports.clear();
        for (k, &i) in from.iter().enumerate() {
            if x[k] > FORCE_TOL * total.max(1.0) {
                supports.push((candidates[i].bead, candidates[i].obstacle));
            }
        }
        Vector(residual)
    }

    /// Drives the force balance's residual down when the descent can no longer
    /// resolve a step by the height (near a rest the height changes by the
    /// square of the distance to it, the residual linearly, so the height is
    /// drowned in rounding long before the residual is): steps along the
    /// projected gradient of the QR balance, each accepted when the residual
    /// falls by a tenth, supports shut and nothing penetrating. Moves `pose`
    /// (by at most a few `1e-3 r`) and returns the last QR residual with its
    /// supports.
    #[cold]
    #[inline(never)]
    fn polish(
        &self,
        pose: &mut Pose<D>,
        candidates: &[Candidate<D>],
        supports: &mut Vec<(u32, Obstacle<D>)>,
    ) -> Real {
        let r = self.shape.r;
        let reach = self.shape.half_length() + r;
        let scale = self.rho / reach;
        let here: Vec<Candidate<D>> = candidates
            .iter()
            .map(|c| self.evaluate(pose, c.bead, c.obstacle))
            .collect();
        let mut res = self.balance_qr_vec(&here, supports);
        let start = *pose;
        let mut disp = 1e-4 * r;
        let mut trial_supports = Vec::new();
        let mut trial_here = Vec::with_capacity(here.len());
        for _ in 0..200 {
            if res.norm() <= QR_REST_TOL || supports.is_empty() {
                break;
            }
            // The checker-metric residual as an engine direction (see
            // `balance_qr_vec`): admissible for every shut contact.
            let mut u = -res;
            for v in &mut u.0[D..] {
                *v *= scale;
            }
            let mut uv: Real = 0.0;
            let mut uw: Real = 0.0;
            for i in 0..6 {
                if i < D {
                    uv += u[i] * u[i];
                } else {
                    uw += u[i] * u[i];
                }
            }
            let speed = uv.sqrt() + uw.sqrt() / self.rho * reach;
            let mut accepted = false;
            for _ in 0..40 {
                let mut trial = *pose;
                self.advance(&mut trial, &u, disp / speed);
                let mut set = supports.clone();
                if self
                    .project_all(&mut trial, &mut set, candidates, REST_GAP * r)
                    .is_some()
                    && self.reach(&start, &trial) <= 0.5 * MAX_STEP * r
                {
                    trial_here.clear();
                    trial_here.extend(
                        candidates
                            .iter()
                            .map(|c| self.evaluate(&trial, c.bead, c.obstacle)),
                    );
                    let t = self.balance_qr_vec(&trial_here, &mut trial_supports);
                    if t.norm() < 0.9 * res.norm() && !trial_supports.is_empty() {
                        *pose = trial;
                        res = t;
                        std::mem::swap(supports, &mut trial_supports);
                        accepted = true;
                        disp *= 2.0;
                        break;
                    }
                }
                disp *= 0.5;
            }
            if !accepted {
                break;
            }
        }
        res.norm()
    }

    /// The rare path, when the fast path can neither step nor certify a rest:
    /// a rest if the contacts within `QR_SHUT` balance the weight to
    /// `QR_REST_TOL` by [`Self::balance_qr`] (after [`Self::polish`] if
    /// needed), nothing overlaps by more than `QR_OVERLAP`, and the balance
    /// does not tip. On `Tipped` the pose is the tipped one; on `No` the pose
    /// is unchanged and `supports` are the QR balance's.
    #[cold]
    #[inline(never)]
    fn rare_rest<R: rand::Rng + ?Sized>(
        &self,
        pose: &mut Pose<D>,
        candidates: &[Candidate<D>],
        supports: &mut Vec<(u32, Obstacle<D>)>,
        rng: &mut R,
    ) -> Rare {
        let here: Vec<Candidate<D>> = candidates
            .iter()
            .map(|c| self.evaluate(pose, c.bead, c.obstacle))
            .collect();
        let overlap = |cs: &[Candidate<D>]| cs.iter().any(|c| c.gap < -QR_OVERLAP * self.shape.r);
        if overlap(&here) {
            if debug_on() {
                eprintln!("no QR balance: overlap");
            }
            return Rare::No;
        }
        let mut at = *pose;
        let mut residual = self.balance_qr(&here, supports);
        if residual > QR_REST_TOL {
            let mut set = Vec::new();
            let p = self.polish(&mut at, candidates, &mut set);
            if p > QR_REST_TOL {
                if debug_on() {
                    eprintln!("no QR balance: residual {residual:.3e}, polished {p:.3e}");
                }
                return Rare::No;
            }
            residual = p;
            *supports = set;
        }
        debug_assert!(residual <= QR_REST_TOL);
        match self.tip(&at, supports, candidates, rng) {
            Some(tipped) => {
                *pose = tipped;
                Rare::Tipped
            }
            None => {
                *pose = at;
                if debug_on() {
                    eprintln!("chain at rest by the QR balance: residual {residual:.3e}");
                }
                Rare::Rest
            }
        }
    }

    /// A tangent direction of the supports along which the chain goes down, if
    /// any (the balance is then unstable): the tipped pose.
    fn tip<R: rand::Rng + ?Sized>(
        &self,
        pose: &Pose<D>,
        supports: &[(u32, Obstacle<D>)],
        candidates: &[Candidate<D>],
        rng: &mut R,
    ) -> Option<Pose<D>> {
        let dof = if D == 2 { 3 } else { 6 };
        // Orthonormal basis of the supports' span (plus, in 3D, the spin about the
        // axis, which moves nothing), then its complement: the tangent directions.
        let mut span: Vec<Gen> = Vec::with_capacity(6);
        let add = |v: Gen, span: &mut Vec<Gen>| {
            let mut q = v;
            for b in span.iter() {
                q = q - *b * q.dot(b);
            }
            let n = q.norm();
            if n > 1e-9 * v.norm().max(1e-300) && span.len() < dof {
                span.push(q / n);
                true
            } else {
                false
            }
        };
        if D == 3 {
            let mut spin = Gen::zero();
            for i in 0..3 {
                spin[3 + i] = pose.axis[i];
            }
            add(spin, &mut span);
        }
        for &(bead, obstacle) in supports {
            add(self.evaluate(pose, bead, obstacle).row, &mut span);
        }
        let fixed = span.len();
        for i in 0..dof {
            add(Gen::axis(i), &mut span);
        }
        let tangent = &span[fixed..];
        if tangent.is_empty() {
            return None;
        }
        let mut random = Gen::zero();
        for t in tangent {
            random += *t * rng.random_range(-1.0..1.0);
        }
        let mut trials: Vec<Gen> = Vec::with_capacity(1 + 2 * tangent.len());
        if let Some(u) = random.normalized() {
            trials.push(u);
        }
        for t in tangent {
            trials.push(*t);
            trials.push(-*t);
        }
        let step = TIP_STEP * self.shape.r;
        for u in trials {
            let mut trial = *pose;
            let mut dz = self.advance(&mut trial, &u, step);
            let mut set = supports.to_vec();
            let Some(d) =
                self.project_all(&mut trial, &mut set, candidates, REST_GAP * self.shape.r)
            else {
                continue;
            };
            if self.reach(pose, &trial) > 0.5 * MAX_STEP * self.shape.r {
                continue; // carried out of the gathered neighbourhood
            }
            dz += d;
            if dz < -TIP_DROP * self.shape.r {
                return Some(trial);
            }
        }
        None
    }
}

/// Non-negative least squares in the generalised space: minimises
/// `|target − Σ λ_i a_i|` over `λ ≥ 0` (Lawson–Hanson active set, any number of
/// passive columns up to 6; the engine's sphere solver stops at three). Columns
/// that are numerically dependent on the passive set cannot improve the fit and
/// are left out. Returns the residual.
fn nnls6(a: &[Gen], target: Gen, lambda: &mut [Real]) -> Gen {
    // Small working arrays for the common case (clearing them is a
    // noticeable part of a 5-bead chain's cost).
    if a.len() <= 16 {
        nnls6_n::<16>(a, target, lambda)
    } else {
        nnls6_n::<MAX_TOUCHING>(a, target, lambda)
    }
}

/// [`nnls6`] with working arrays for at most `N` columns.
fn nnls6_n<const N: usize>(a: &[Gen], target: Gen, lambda: &mut [Real]) -> Gen {
    let m = a.len();
    lambda[..m].iter_mut().for_each(|l| *l = 0.0);
    let mut passive = [false; N];
    let mut banned = [false; N];
    let mut full = [0.0; N];
    let residual = |lambda: &[Real]| {
        let mut r = target;
        for i in 0..m {
            r -= a[i] * lambda[i];
        }
        r
    };
    for _ in 0..3 * m + 3 {
        let r = residual(lambda);
        let mut best = None;
        let mut best_w = 1e-14;
        for i in 0..m {
            if !passive[i] && !banned[i] {
                let w = a[i].dot(&r);
                if w > best_w {
                    best_w = w;
                    best = Some(i);
                }
            }
        }
        let Some(j) = best else { break };
        passive[j] = true;
        for _ in 0..3 * m + 3 {
            let mut idx = [0usize; 6];
            let mut k = 0;
            for i in 0..m {
                if passive[i] {
                    if k == 6 {
                        k = 7;
                        break;
                    }
                    idx[k] = i;
                    k += 1;
                }
            }
            let z = if k <= 6 {
                let mut g = [[0.0; 6]; 6];
                let mut b = [0.0; 6];
                let mut scale: Real = 0.0;
                for r in 0..k {
                    for c in 0..k {
                        g[r][c] = a[idx[r]].dot(&a[idx[c]]);
                    }
                    b[r] = a[idx[r]].dot(&target);
                    scale = scale.max(g[r][r]);
                }
                solve_checked(&mut g, &mut b, k, 1e-15 * scale)
            } else {
                None
            };
            let Some(z) = z else {
                passive[j] = false;
                banned[j] = true;
                break;
            };
            full[..m].fill(0.0);
            for (t, &i) in idx[..k].iter().enumerate() {
                full[i] = z[t];
            }
            if idx[..k].iter().all(|&i| full[i] > 0.0) {
                lambda[..m].copy_from_slice(&full[..m]);
                break;
            }
            let mut alpha: Real = 1.0;
            for &i in &idx[..k] {
                if full[i] <= 0.0 {
                    let d = lambda[i] - full[i];
                    if d > 0.0 {
                        alpha = alpha.min(lambda[i] / d);
                    }
                }
            }
            for i in 0..m {
                lambda[i] += alpha * (full[i] - lambda[i]);
                if passive[i] && lambda[i] <= 1e-15 {
                    lambda[i] = 0.0;
                    passive[i] = false;
                }
            }
        }
    }
    residual(lambda)
}

/// The outcome of [`Settler::rare_rest`].
enum Rare {
    /// At rest.
    Rest,
    /// An unstable balance, tipped.
    Tipped,
    /// No balance found.
    No,
}

/// Like [`solve`], refusing pivots below `tiny` (a nearly singular system).
fn solve_checked(
    a: &mut [[Real; 6]; 6],
    b: &mut [Real; 6],
    m: usize,
    tiny: Real,
) -> Option<[Real; 6]> {
    for col in 0..m {
        let p = (col..m).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[p][col].abs().partial_cmp(&tiny) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        a.swap(col, p);
        b.swap(col, p);
        for i in col + 1..m {
            let f = a[i][col] / a[col][col];
            for j in col..m {
                a[i][j] -= f * a[col][j];
            }
            b[i] -= f * b[col];
        }
    }
    let mut y = [0.0; 6];
    for i in (0..m).rev() {
        let mut s = b[i];
        for j in i + 1..m {
            s -= a[i][j] * y[j];
        }
        y[i] = s / a[i][i];
    }
    y.iter().all(|v| v.is_finite()).then_some(y)
}

/// Solves the `m × m` symmetric system `a y = b` (Gaussian elimination with
/// partial pivoting); `None` if singular.
fn solve(a: &mut [[Real; 6]; 6], b: &mut [Real; 6], m: usize) -> Option<[Real; 6]> {
    solve_checked(a, b, m, 1e-300)
}

/// Settles a chain entering at `start` (its horizontal position and axis; it is
/// first lowered to just above everything under it). Returns its resting pose
/// (not wrapped into a periodic box), or `None` if it found no rest within
/// [`MAX_ITERATIONS`].
pub(crate) fn settle_chain<const D: usize, R: rand::Rng + ?Sized>(
    terrain: &Terrain<'_, D>,
    shape: ChainShape,
    start: Pose<D>,
    rng: &mut R,
) -> Option<Pose<D>> {
    let r = shape.r;
    let settler = Settler {
        terrain,
        shape,
        rho: shape.gyration::<D>(),
        chunk: ((4.0 / shape.spacing).floor() as u32).max(1),
    };
    let mut pose = start;
    if let Some(a) = pose.axis.normalized() {
        pose.axis = a;
    } else {
        pose.axis = Vector::up();
    }
    {
        // Just above everything the chain could touch on its way down.
        let beads = shape.beads(pose.com, pose.axis);
        let (mut lo, mut hi) = (beads[0], beads[0]);
        let mut low = Real::INFINITY;
        for b in &beads {
            for i in 0..D {
                lo[i] = lo[i].min(b[i]);
                hi[i] = hi[i].max(b[i]);
            }
            low = low.min(b[D - 1]);
        }
        for i in 0..D - 1 {
            lo[i] -= r + terrain.r_fixed_max;
            hi[i] += r + terrain.r_fixed_max;
        }
        let top = terrain.grid.max_top(&lo, &hi);
        pose.com[D - 1] += top + r * (1.0 + 1e-6) - low;
    }
    let contact = CONTACT_TOL * r;
    let max_step = MAX_STEP * r;
    let mut candidates: Vec<Candidate<D>> = Vec::new();
    let mut touching = [Gen::zero(); MAX_TOUCHING];
    let mut which = [0usize; MAX_TOUCHING];
    let mut lambda = [0.0; MAX_TOUCHING];
    let mut supports: Vec<(u32, Obstacle<D>)> = Vec::new();
    // The touching contacts of the last iteration (bead, obstacle key).
    let mut held: Vec<(u32, u64)> = Vec::with_capacity(MAX_TOUCHING);
    let mut h_prev = Real::INFINITY;
    let mut target = Gen::zero();
    target[D - 1] = 1.0;
    // One iteration that counts only shut contacts (gap within `REST_GAP`) as
    // touching, after a balance whose supports could not all be shut.
    let mut tight = false;
    // Tipping moves tried after failed line searches.
    let mut nudges = 0;
    let debug = debug_on();
    let mut trace: std::collections::VecDeque<String> = Default::default();
    macro_rules! tr {
        ($($t:tt)*) => {
            if debug {
                push_trace(&mut trace, format_args!($($t)*));
            }
        };
    }
    for it in 0..MAX_ITERATIONS {
        settler.gather(&pose, max_step * 1.01 + contact, &mut candidates);
        let was_tight = std::mem::take(&mut tight);
        let band = if was_tight { REST_GAP * r } else { contact };
        let mut m = 0;
        for (i, c) in candidates.iter().enumerate() {
            // Hysteresis: a contact touching in the last iteration stays
            // touching up to twice the band, so that a support pinned near the
            // band's edge does not flicker in and out of the touching set
            // (each flicker changes the descent direction and cuts the step).
            let near = c.gap < band
                || (!was_tight
                    && c.gap < 2.0 * band
                    && held
                        .iter()
                        .any(|&(b, k)| b == c.bead && k == c.obstacle.key));
            if near {
                if m == MAX_TOUCHING {
                    // Keep the closest contacts (a tie of many is degenerate).
                    let (worst, _) = which[..m]
                        .iter()
                        .enumerate()
                        .max_by(|a, b| candidates[*a.1].gap.total_cmp(&candidates[*b.1].gap))
                        .expect("non-empty");
                    if candidates[which[worst]].gap > c.gap {
                        which[worst] = i;
                    }
                    continue;
                }
                which[m] = i;
                m += 1;
            }
        }
        held.clear();
        held.extend(
            which[..m]
                .iter()
                .map(|&i| (candidates[i].bead, candidates[i].obstacle.key)),
        );
        if m == 0 {
            pose.com[D - 1] -= settler.fall_distance(&pose);
            h_prev = Real::INFINITY;
            continue;
        }
        for j in 0..m {
            touching[j] = candidates[which[j]].row;
        }
        let residual = nnls6(&touching[..m], target, &mut lambda);
        let total: Real = lambda[..m].iter().sum();
        if debug {
            let gaps: Vec<_> = which[..m]
                .iter()
                .map(|&i| {
                    (
                        candidates[i].bead,
                        candidates[i].obstacle.key,
                        candidates[i].gap,
                    )
                })
                .collect();
            push_trace(
                &mut trace,
                format_args!(
                    "it {it} z {:.12} res {:.3e} m {m} tight {was_tight} gaps {gaps:?} lam {:?}",
                    pose.com[D - 1],
                    residual.norm(),
                    &lambda[..m]
                ),
            );
        }
        supports.clear();
        for j in 0..m {
            if lambda[j] > FORCE_TOL * total.max(1.0) {
                let c = &candidates[which[j]];
                supports.push((c.bead, c.obstacle));
            }
        }
        if residual.norm() <= REST_TOL * total.max(1.0) {
            // A balance: make the supports touch exactly, then test its stability.
            let mut set = supports.clone();
            let mut exact = pose;
            if settler
                .project_all(&mut exact, &mut set, &candidates, REST_GAP * r)
                .is_none()
            {
                if was_tight {
                    // Nearly parallel contacts within rounding of each other
                    // (a chain along a chain): the balance as the independent
                    // rest test measures it decides.
                    match settler.rare_rest(&mut pose, &candidates, &mut supports, rng) {
                        Rare::Rest => return Some(pose),
                        Rare::Tipped => {
                            h_prev = Real::INFINITY;
                            continue;
                        }
                        Rare::No => {}
                    }
                    for t in &trace {
                        eprintln!("  {t}");
                    }
                    dbg_fail("rest projection", it, &supports.len());
                    return None;
                }
                // Some support a little open cannot be shut while the others
                // stay shut: it is no support here. Look again with only the
                // contacts that are shut.
                tr!("   rest projection failed: tight");
                tight = true;
                continue;
            }
            let moved = (exact.com - pose.com).norm() + (exact.axis - pose.axis).norm() * r;
            pose = exact;
            if moved > contact {
                continue; // the projection moved it noticeably: look again
            }
            // The balance was measured before the projection, which may have
            // turned the normals (a move of `1e-7 r` turns them by about as
            // much): measure it again where the chain now is, forces
            // re-solved, as the independent rest test does.
            // Only contacts shut there count (the others carry no force).
            let mut k = 0;
            for j in 0..m {
                let c = &candidates[which[j]];
                let e = settler.evaluate(&pose, c.bead, c.obstacle);
                if e.gap <= REST_GAP * r {
                    touching[k] = e.row;
                    k += 1;
                }
            }
            let after = nnls6(&touching[..k], target, &mut lambda);
            let verdict = if after.norm() <= POST_REST_TOL {
                match settler.tip(&pose, &set, &candidates, rng) {
                    Some(tipped) => {
                        pose = tipped;
                        Rare::Tipped
                    }
                    None => Rare::Rest,
                }
            } else {
                // Forces that nearly cancel (a bead pinched between two
                // obstacles) make the relative test above weak, and nearly
                // parallel supports the normal equations: the balance
                // measured as the independent rest test does decides.
                tr!(
                    "   moved {moved:.3e}: residual after the projection {:.3e}",
                    after.norm()
                );
                let mut scratch = Vec::new();
                settler.rare_rest(&mut pose, &candidates, &mut scratch, rng)
            };
            match verdict {
                Rare::Rest => return Some(pose),
                Rare::Tipped => {
                    h_prev = Real::INFINITY;
                    continue;
                }
                // Not a balance after all: descend.
                Rare::No => {}
            }
        }
        // Steepest descent: u = −residual, along which the height falls at the
        // rate |u|² (in the kinetic metric).
        let u = -residual;
        let rate_z = u.norm2();
        let mut uv = 0.0;
        let mut uw = 0.0;
        for i in 0..6 {
            if i < D {
                uv += u[i] * u[i];
            } else {
                uw += u[i] * u[i];
            }
        }
        let (uv, uw) = (uv.sqrt(), uw.sqrt() / settler.rho);
        let speed = uv + uw * (shape.half_length() + r);
        let mut h = (2.0 * h_prev).min(max_step / speed);
        if uw > 0.0 {
            h = h.min(0.5 / uw);
        }
        for (i, c) in candidates.iter().enumerate() {
            if c.gap < band || (c.gap < 2.0 * band && which[..m].contains(&i)) {
                continue;
            }
            let rate = c.row.dot(&u);
            let kappa = uw * uw * shape.offset(c.bead).abs();
            let disc = (rate * rate + 4.0 * kappa * c.gap).sqrt() - rate;
            if disc > 0.0 {
                h = h.min(2.0 * c.gap / disc);
            }
        }
        // First with the supports shut (closing one that is a little open is
        // itself a descent when the rate of descent is below rounding); if
        // no step length works, with supports open by less than `contact`
        // left as they are: shutting them can be impossible (two neighbouring
        // beads of a rod on one obstacle, one at gap 0, one a little open).
        let mut accepted = false;
        let h0 = h;
        // How far the chain may get from where the candidates were gathered.
        let reach = max_step * 1.01;
        let rounding = 16.0 * Real::EPSILON * pose.com.0.iter().fold(r, |m, x| m.max(x.abs()));
        'slack: for slack in [0.0, 2.0 * contact] {
            h = h0;
            let mut unprojectable = 0;
            for _ in 0..60 {
                if h * speed <= rounding {
                    // A step below the rounding of the coordinates only
                    // seems to descend (a chain was caught cycling on the
                    // same pose with such steps): no step.
                    break;
                }
                let mut trial = pose;
                let mut dz = settler.advance(&mut trial, &u, h);
                let mut set = supports.clone();
                let projected = settler
                    .project_all(&mut trial, &mut set, &candidates, slack)
                    // A projection that carried a bead out of the gathered
                    // neighbourhood could hide an overlap with an obstacle
                    // never looked at: no projection.
                    .filter(|_| settler.reach(&pose, &trial) <= reach);
                match projected {
                    Some(d) => {
                        dz += d;
                        // The height's own change must agree: the summed
                        // increments can claim a descent of a few roundings
                        // while the projection puts the chain back where it
                        // was (a chain was caught cycling so on one pose).
                        if dz <= -0.1 * h * rate_z && trial.com[D - 1] < pose.com[D - 1] {
                            pose = trial;
                            accepted = true;
                            break 'slack;
                        }
                    }
                    // Supports that cannot be shut stay so at any step
                    // length: after a few tries, go on to leaving them open
                    // rather than paying for every halving.
                    None if slack == 0.0 => {
                        unprojectable += 1;
                        if unprojectable >= 4 {
                            continue 'slack;
                        }
                    }
                    None => {}
                }
                h *= 0.5;
            }
        }
        if !accepted {
            // No step along the descent direction is resolvable. If the shut
            // contacts balance the weight when measured as the independent
            // rest test does (QR, where the normal equations lost digits),
            // this is a balance: a rest unless it tips.
            match settler.rare_rest(&mut pose, &candidates, &mut supports, rng) {
                Rare::Rest => return Some(pose),
                Rare::Tipped => {
                    h_prev = Real::INFINITY;
                    continue;
                }
                Rare::No => {}
            }
            tr!("   no step, no QR balance ({} supports)", supports.len());
            // Otherwise (its rate is below rounding, or the supports cannot
            // follow it): try the tipping moves of a balance, which go a
            // finite distance along the supports' tangent directions.
            if nudges < MAX_NUDGES {
                if let Some(tipped) = settler.tip(&pose, &supports, &candidates, rng) {
                    nudges += 1;
                    pose = tipped;
                    h_prev = Real::INFINITY;
                    continue;
                }
            }
            for t in &trace {
                eprintln!("  {t}");
            }
            dbg_fail("line search", it, &(residual.norm(), m, supports.len(), h));
            return None;
        }
        tr!("   step h {h:.3e} rate {rate_z:.3e}");
        h_prev = h;
    }
    for t in &trace {
        eprintln!("  {t}");
    }
    dbg_fail("iterations", MAX_ITERATIONS, &());
    None
}

/// Keeps the last iterations' diagnostics (with `PACKBED_CHAIN_DEBUG`).
#[cold]
#[inline(never)]
fn push_trace(trace: &mut std::collections::VecDeque<String>, line: std::fmt::Arguments) {
    if trace.len() > 80 {
        trace.pop_front();
    }
    trace.push_back(line.to_string());
}

fn debug_on() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("PACKBED_CHAIN_DEBUG").is_some())
}

/// Explains a stuck chain on stderr when `PACKBED_CHAIN_DEBUG` is set (for
/// investigating re-drops).
fn dbg_fail(what: &str, it: usize, x: &dyn std::fmt::Debug) {
    if std::env::var_os("PACKBED_CHAIN_DEBUG").is_some() {
        eprintln!("chain stuck: {what} at iteration {it}: {x:?}");
    }
}
