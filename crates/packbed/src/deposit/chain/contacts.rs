//! Where the chain meets the bed: the candidate contacts near a pose, and how far
//! it can fall straight down.

use super::{Candidate, Pose, Settler};
use crate::deposit::obstacle::{particle_key, wall_obstacle, Obstacle};
use crate::geometry::Surface;
use crate::math::{Real, Vector};

impl<const D: usize> Settler<'_, '_, D> {
    /// The smallest box holding the centres of beads `first..last`.
    pub(super) fn bead_box(&self, pose: &Pose<D>, first: u32, last: u32) -> (Vector<D>, Vector<D>) {
        let (mut lo, mut hi) = (self.bead(pose, first), self.bead(pose, first));
        for k in first + 1..last {
            let b = self.bead(pose, k);
            for i in 0..D {
                lo[i] = lo[i].min(b[i]);
                hi[i] = hi[i].max(b[i]);
            }
        }
        (lo, hi)
    }

    /// Every bead–obstacle pair whose gap is below `margin` (fixed particles
    /// through their periodic images, walls and floor).
    pub(super) fn gather(&self, pose: &Pose<D>, margin: Real, out: &mut Vec<Candidate<D>>) {
        out.clear();
        let t = self.terrain;
        let r = self.shape.r;
        let mut first = 0;
        while first < self.shape.beads {
            let last = (first + self.chunk).min(self.shape.beads);
            let (lo, hi) = self.bead_box(pose, first, last);
            t.grid
                .for_each_in_box(&lo, &hi, r + margin, |id, shift, image| {
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
    pub(super) fn fall_distance(&self, pose: &Pose<D>) -> Real {
        let t = self.terrain;
        let r = self.shape.r;
        let mut best = Real::INFINITY;
        for k in 0..self.shape.beads {
            best = best.min(self.bead(pose, k)[D - 1] - r);
        }
        let mut first = 0;
        while first < self.shape.beads {
            let last = (first + self.chunk).min(self.shape.beads);
            let (mut lo, hi) = self.bead_box(pose, first, last);
            let low = lo[D - 1];
            lo[D - 1] = 0.0;
            t.grid.scan_down(&lo, &hi, r, |id, shift, _| {
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
                low - best
            });
            first = last;
        }
        best.max(0.0)
    }
}
