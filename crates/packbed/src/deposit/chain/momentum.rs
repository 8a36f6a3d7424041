//! The momentum rule for a rigid chain: the way out of a pocket.
//!
//! A chain at rest with kinetic energy left (as a height, `Motion`) leaves
//! its pocket as a sphere does: it lets one support go and climbs on the
//! others, away from the one let go, to the top of that climb, and on down
//! the far side with the energy it has left; of the ways out its energy
//! clears, it takes the one with the lowest barrier (the climb plus the
//! friction on the way). A sphere's climb keeps `D − 1` supports and has
//! one path, a circle; a chain keeps its other supports and still has up to
//! `2D − 1 − k` degrees of freedom, so its path is chosen: the one that moves
//! away from the support let go at the least kinetic energy, the generalised
//! normal of that support with its components along the kept supports'
//! normals taken out (in the kinetic metric of the descent). For one bead it
//! is the sphere's circle. The climb is followed in steps bounded as the
//! descent's are (conservative advancement against every other obstacle),
//! with the kept supports shut exactly after each step, so the geometry
//! stays exact. A climb that meets another particle or a wall is no way
//! out, unless `climb_over`: then the particle met is kept as a support too,
//! with the impact's loss, and the climb goes on. A chain on the floor has no
//! way out (as a sphere on the floor).

use super::{Candidate, Pose, Settler, FORCE_TOL, MAX_STEP, MAX_TOUCHING};
use crate::deposit::obstacle::{is_floor, Obstacle};
use crate::deposit::roll::Motion;
use crate::math::{nnls_gen, Gen, Real};

/// Steps after which a climb that has not reached its top is given up.
const MOST_STEPS: usize = 400;
/// Bisections that place the top of a climb within its last step.
const TOP_BISECTIONS: usize = 24;
/// Halvings of a climb's step that cannot be taken before the climb is
/// given up.
const HALVINGS: usize = 12;

/// A chain's way out of its pocket.
pub(super) struct Exit<const D: usize> {
    /// Just past the top, on the far side.
    pub pose: Pose<D>,
    /// The energy left there.
    pub energy: Real,
    /// Steps taken by the climbs weighed (the settling's move count).
    pub steps: u64,
}

/// One climb that cleared its top.
struct Climbed<const D: usize> {
    pose: Pose<D>,
    energy: Real,
    barrier: Real,
}

impl<const D: usize> Settler<'_, '_, D> {
    /// The lowest way out of the pocket where the chain rests at `pose`,
    /// within the energy of `motion`; `band` is the gap below which an
    /// obstacle touches.
    pub(super) fn way_out(&self, pose: &Pose<D>, motion: &Motion, band: Real) -> Option<Exit<D>> {
        if motion.energy() <= 0.0 {
            return None;
        }
        let margin = MAX_STEP * self.shape.r * 1.01 + band;
        let mut candidates = Vec::new();
        self.gather(pose, margin, &mut candidates);
        let touching: Vec<Candidate<D>> = candidates
            .iter()
            .filter(|c| c.gap <= band)
            .copied()
            .collect();
        if touching.is_empty()
            || touching.len() > MAX_TOUCHING
            || touching.iter().any(|c| is_floor(c.obstacle.key))
        {
            return None;
        }
        let rows: Vec<Gen> = touching.iter().map(|c| c.row).collect();
        let mut lambda = [0.0; MAX_TOUCHING];
        let mut up = Gen::zero();
        up[D - 1] = 1.0;
        nnls_gen(&rows, up, &mut lambda);
        let total: Real = lambda[..rows.len()].iter().sum();
        let supports: Vec<(u32, Obstacle<D>)> = touching
            .iter()
            .zip(&lambda)
            .filter(|(_, &l)| l > FORCE_TOL * total.max(1.0))
            .map(|(c, _)| (c.bead, c.obstacle))
            .collect();
        let mut best: Option<Climbed<D>> = None;
        let mut steps = 0;
        for gone in 0..supports.len() {
            let kept: Vec<_> = supports
                .iter()
                .enumerate()
                .filter(|&(i, _)| i != gone)
                .map(|(_, s)| *s)
                .collect();
            let climbed = self.climb(pose, kept, supports[gone], motion, band, &mut steps);

            if let Some(c) = climbed {
                // The lowest barrier; a tie goes to the first support.
                if best.as_ref().is_none_or(|b| c.barrier < b.barrier) {
                    best = Some(c);
                }
            }
        }
        best.map(|c| Exit {
            pose: c.pose,
            energy: c.energy,
            steps,
        })
    }

    /// Climbs from `start` away from the support `gone`, keeping `kept`
    /// shut, to just past the top of the climb; `None` where the
    /// energy runs out first, another obstacle is met (without
    /// `climb_over`), or the kept supports leave no freedom.
    fn climb(
        &self,
        start: &Pose<D>,
        mut kept: Vec<(u32, Obstacle<D>)>,
        gone: (u32, Obstacle<D>),
        motion: &Motion,
        band: Real,
        steps: &mut u64,
    ) -> Option<Climbed<D>> {
        let r = self.shape.r;
        let margin = MAX_STEP * r * 1.01 + band;
        let mut at = *start;
        let mut energy = motion.energy();
        let mut candidates = Vec::new();
        let mut climbed = false;
        for _ in 0..MOST_STEPS {
            *steps += 1;
            self.gather(&at, margin, &mut candidates);
            let d = self.away(&at, &kept, gone)?;
            if d[D - 1] <= 0.0 {
                // Not a climb (the support carried no load); or, after a
                // blocker was kept, the way on already goes down: over the
                // crest at the blocker.
                return climbed.then(|| Climbed {
                    pose: at,
                    energy,
                    barrier: motion.energy() - energy,
                });
            }
            // Another obstacle that touches and closes along the climb blocks it.
            let blocker = candidates.iter().find(|c| {
                c.gap < band
                    && !is_kept(&kept, c)
                    && !(c.bead == gone.0 && c.obstacle.key == gone.1.key)
                    && c.row.dot(&d) < -1e-12
            });
            if let Some(b) = blocker {
                if !motion.climb_over() || kept.len() >= MAX_TOUCHING - 1 {
                    return None;
                }
                let cos = b.row.dot(&d) / b.row.norm();
                energy *= motion.kept_at_impact(cos * cos);
                kept.push((b.bead, b.obstacle));
                continue;
            }
            // A step that cannot keep the supports shut or reaches too far
            // is halved (a few times at most).
            let mut h = self.climb_step(&d, &candidates, &kept, gone, band);
            let mut stepped = None;
            for _ in 0..HALVINGS {
                stepped = self.step_along(&at, &d, h, &kept, &candidates);
                if stepped.is_some() {
                    break;
                }
                h *= 0.5;
            }
            let (next, dz) = stepped?;
            climbed = true;
            if self.away(&next, &kept, gone)?[D - 1] > 0.0 {
                energy -= dz + motion.mu() * (next.com - at.com).horizontal().norm();
                if energy <= 0.0 {
                    return None;
                }
                at = next;
                continue;
            }
            // The top lies within this step: place it by bisection (the
            // first point found past it), and pay the climb to it; the
            // descent goes on from there, down the far side.
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..TOP_BISECTIONS {
                let mid = 0.5 * (lo + hi);
                let (p, _) = self.step_along(&at, &d, mid, &kept, &candidates)?;
                if self.away(&p, &kept, gone)?[D - 1] > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let (top, dz_top) = self.step_along(&at, &d, hi, &kept, &candidates)?;
            let at_top = energy - dz_top - motion.mu() * (top.com - at.com).horizontal().norm();
            if at_top <= 0.0 {
                return None;
            }
            return Some(Climbed {
                pose: top,
                energy: at_top,
                barrier: motion.energy() - at_top,
            });
        }
        None
    }

    /// The unit direction of the climb at `pose`: the generalised normal of
    /// `gone` with its components along the kept supports' normals removed
    /// (Gram–Schmidt); `None` where the kept supports leave no freedom.
    fn away(
        &self,
        pose: &Pose<D>,
        kept: &[(u32, Obstacle<D>)],
        gone: (u32, Obstacle<D>),
    ) -> Option<Gen> {
        let mut basis = [Gen::zero(); MAX_TOUCHING];
        let mut n = 0;
        for &(bead, obstacle) in kept {
            let mut v = self.evaluate(pose, bead, obstacle).row;
            let scale = v.norm();
            for b in &basis[..n] {
                v = v - *b * v.dot(b);
            }
            let len = v.norm();
            if len > 1e-9 * scale {
                basis[n] = v / len;
                n += 1;
            }
        }
        let g = self.evaluate(pose, gone.0, gone.1).row;
        let mut d = g;
        for b in &basis[..n] {
            d = d - *b * d.dot(b);
        }
        let len = d.norm();
        (len > 1e-9 * g.norm()).then(|| d / len)
    }

    /// The step along `d`: the descent's bounds on how far any point and the
    /// turn may go, and conservative advancement against every obstacle that
    /// is neither kept nor let go.
    fn climb_step(
        &self,
        d: &Gen,
        candidates: &[Candidate<D>],
        kept: &[(u32, Obstacle<D>)],
        gone: (u32, Obstacle<D>),
        band: Real,
    ) -> Real {
        let (speed, turn) = self.speed(d);
        let mut h = MAX_STEP * self.shape.r / speed;
        if turn > 0.0 {
            h = h.min(0.5 / turn);
        }
        for c in candidates {
            if is_kept(kept, c) || (c.bead == gone.0 && c.obstacle.key == gone.1.key) {
                continue;
            }
            if c.gap < band && c.row.dot(d) >= -1e-12 {
                continue; // touching, not closing
            }
            h = h.min(self.advancement(c, d, turn));
        }
        h
    }

    /// The pose `h` along `d` from `at` with the kept supports shut again,
    /// and its centre of mass's rise; `None` if they cannot be shut, or the
    /// step would reach past the gathered neighbourhood or into an obstacle.
    fn step_along(
        &self,
        at: &Pose<D>,
        d: &Gen,
        h: Real,
        kept: &[(u32, Obstacle<D>)],
        candidates: &[Candidate<D>],
    ) -> Option<(Pose<D>, Real)> {
        let mut next = *at;
        let mut dz = self.advance(&mut next, d, h);
        let mut set = kept.to_vec();
        dz += self.project_all(&mut next, &mut set, candidates, 0.0)?;
        // Something met on the way (the projection had to add it), or a
        // move beyond the neighbourhood searched: no such step.
        if set.len() != kept.len() || self.reach(at, &next) > MAX_STEP * self.shape.r * 1.01 {
            return None;
        }
        Some((next, dz))
    }
}

/// Whether the candidate is one of the kept supports.
fn is_kept<const D: usize>(kept: &[(u32, Obstacle<D>)], c: &Candidate<D>) -> bool {
    kept.iter()
        .any(|&(b, o)| b == c.bead && o.key == c.obstacle.key)
}
