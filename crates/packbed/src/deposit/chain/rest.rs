//! Deciding a rest: the QR force balance of the rare path, its polish, and the
//! tipping test of a balance.

use super::{debug_on, Candidate, Pose, Settler, FORCE_TOL, MAX_STEP, REST_GAP};
use crate::deposit::obstacle::Obstacle;
use crate::math::{nnls_qr, Gen, Real, Vector};
use rand::RngExt;

/// Size of the tipping trial move at a balance (times the bead radius).
const TIP_STEP: Real = 1e-3;
/// Height drop of a tipping trial that counts as going down (times the bead
/// radius): far above rounding, far below the drop of a real unstable balance
/// (about `TIP_STEP² r / (2 (1 + R/r))`).
const TIP_DROP: Real = 1e-10;
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

impl<const D: usize> Settler<'_, '_, D> {
    /// The force balance measured as the independent rest test measures it,
    /// for the rare case where the fast normal-equation NNLS cannot resolve a
    /// descent step: every shut contact (gap within `QR_SHUT`, no cap on their
    /// number), torques about the centre of mass scaled by the body's half
    /// length plus a radius, and Lawson–Hanson by Householder QR (nearly
    /// parallel supports, such as a rod in the groove of another, make the
    /// normal equations lose about half the digits). Returns the residual and
    /// the supports (contacts carrying a force).
    pub(super) fn balance_qr(
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
        let (residual, x) = nnls_qr(&cols, q, &target);
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
            let (speed, _) = self.speed(&u);
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
    pub(super) fn rare_rest<R: rand::Rng + ?Sized>(
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
    pub(super) fn tip<R: rand::Rng + ?Sized>(
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

/// The outcome of [`Settler::rare_rest`].
pub(super) enum Rare {
    /// At rest.
    Rest,
    /// An unstable balance, tipped.
    Tipped,
    /// No balance found.
    No,
}
