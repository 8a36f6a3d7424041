//! Keeping contacts shut: the Gauss–Newton projection of a pose onto its supports.

use super::{Candidate, Pose, Settler, MAX_TOUCHING, REST_GAP};
use crate::deposit::obstacle::Obstacle;
use crate::math::{solve_pivoted, Real, Vector};

/// Penetration that the projection must remove (times the bead radius).
const PENETRATION_TOL: Real = 1e-12;

impl<const D: usize> Settler<'_, '_, D> {
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
            let y = solve_pivoted(&mut jtj, &mut jtg, 6, 1e-300)?;
            dz += self.advance(pose, &Vector(y), 1.0);
        }
        (worst <= 100.0 * tol).then_some(dz)
    }

    /// Projects `pose` onto the contacts of `set`, adding any candidate that ends
    /// up penetrating, until nothing penetrates. Returns the height change.
    pub(super) fn project_all(
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
}
