//! The still-available space of random sequential addition, tracked on voxels
//! (Zhang & Torquato, Phys. Rev. E 88, 053312, 2013).
//!
//! A point is available when the smallest particle fits there: outside every
//! exclusion ball (a placed particle's centre, radius `r_i + r_min`) and inside
//! the box shrunk by `r_min`. A voxel is dropped once one exclusion ball holds it
//! whole (its farthest corner inside the ball); the voxels left always contain
//! all available space, so sampling uniformly over them and rejecting what does
//! not fit is exactly uniform sampling of the available space. Voxels covered
//! only by a union of balls are split into `2^D` children, level after level,
//! until a single ball covers each child or a particle lands there.

use crate::math::{Real, Vector};

/// A safety factor on squared radii: a voxel counts as covered only when its
/// farthest corner is inside the ball by more than rounding, so that no voxel
/// with a sliver of available space is ever dropped.
const COVER_MARGIN: Real = 1.0 - 1e-12;

/// Equal voxels (one level of refinement) that may still hold available space.
#[derive(Clone, Debug)]
pub(super) struct Voxels<const D: usize> {
    /// Side of every voxel along each axis.
    pub side: Vector<D>,
    /// Low corner of each voxel.
    pub corners: Vec<Vector<D>>,
}

/// An exclusion ball: the smallest particle's centre may not enter it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ball<const D: usize> {
    /// Centre (with its periodic image shift applied).
    pub centre: Vector<D>,
    /// Squared exclusion radius `(r_i + r_min)²`.
    pub radius2: Real,
}

/// Squared distance from `c` to the farthest point of the box `[lo, lo + side]`.
#[inline]
pub(super) fn farthest2<const D: usize>(lo: &Vector<D>, side: &Vector<D>, c: &Vector<D>) -> Real {
    let mut s = 0.0;
    for k in 0..D {
        let a = (lo[k] - c[k]).abs();
        let b = (lo[k] + side[k] - c[k]).abs();
        let f = a.max(b);
        s += f * f;
    }
    s
}

/// Squared distance from `c` to the nearest point of the box `[lo, lo + side]`.
#[inline]
pub(super) fn nearest2<const D: usize>(lo: &Vector<D>, side: &Vector<D>, c: &Vector<D>) -> Real {
    let mut s = 0.0;
    for k in 0..D {
        let d = if c[k] < lo[k] {
            lo[k] - c[k]
        } else if c[k] > lo[k] + side[k] {
            c[k] - lo[k] - side[k]
        } else {
            0.0
        };
        s += d * d;
    }
    s
}

/// True when one of `balls` holds the whole box `[lo, lo + side]`.
#[inline]
pub(super) fn covered<const D: usize>(lo: &Vector<D>, side: &Vector<D>, balls: &[Ball<D>]) -> bool {
    balls
        .iter()
        .any(|b| farthest2(lo, side, &b.centre) < b.radius2 * COVER_MARGIN)
}

/// The regular grid of level 0 over the domain of available centres.
#[derive(Clone, Debug)]
pub(super) struct Lattice<const D: usize> {
    /// Low corner of the domain.
    pub lo: Vector<D>,
    /// Voxel side along each axis.
    pub side: Vector<D>,
    /// Voxels along each axis.
    pub counts: [usize; D],
    /// Axes that wrap around (the domain is then one whole period).
    pub wrap: [bool; D],
}

impl<const D: usize> Lattice<D> {
    /// A lattice of voxels of side close to `target` (at most `max_voxels` in
    /// all, widened if needed) over `[lo, hi]`.
    pub fn new(
        lo: Vector<D>,
        hi: Vector<D>,
        target: Real,
        max_voxels: usize,
        wrap: [bool; D],
    ) -> Self {
        let mut s = target;
        loop {
            let mut counts = [1usize; D];
            let mut total: Real = 1.0;
            for k in 0..D {
                let n = ((hi[k] - lo[k]) / s).ceil().max(1.0);
                counts[k] = n as usize;
                total *= n;
            }
            if total <= max_voxels as Real {
                let mut side = Vector::zero();
                for k in 0..D {
                    side[k] = (hi[k] - lo[k]).max(0.0) / counts[k] as Real;
                }
                return Lattice {
                    lo,
                    side,
                    counts,
                    wrap,
                };
            }
            s *= 1.25;
        }
    }

    /// Number of voxels.
    pub fn len(&self) -> usize {
        self.counts.iter().product()
    }

    /// Marks in `mask` (one bit per voxel, axis 0 fastest) every voxel the
    /// exclusion ball `(c, R)` holds whole. On a wrapping axis an index beyond the
    /// domain names the image of a voxel one period away, so one call covers every
    /// periodic image of the ball.
    pub fn mark_covered(&self, c: &Vector<D>, radius: Real, mask: &mut [u64]) {
        // Per axis, the voxel index range the ball's bounding box meets.
        let mut first = [0isize; D];
        let mut last = [0isize; D];
        for k in 0..D {
            if self.side[k] == 0.0 {
                // A domain of no width along this axis: one layer of flat voxels.
                if (c[k] - self.lo[k]).abs() >= radius {
                    return;
                }
                continue;
            }
            let a = ((c[k] - radius - self.lo[k]) / self.side[k]).floor();
            let b = ((c[k] + radius - self.lo[k]) / self.side[k]).floor();
            if !(a.is_finite() && b.is_finite()) {
                return;
            }
            let (mut a, mut b) = (a as isize, b as isize);
            if !self.wrap[k] {
                a = a.max(0);
                b = b.min(self.counts[k] as isize - 1);
            }
            if a > b {
                return;
            }
            first[k] = a;
            last[k] = b;
        }
        let r2 = radius * radius * COVER_MARGIN;
        // Odometer over the axes 1..D; along axis 0 the covered voxels form one
        // run, found in closed form.
        let mut idx = first;
        loop {
            let mut rem = r2;
            let mut flat_outer = 0usize;
            let mut stride = self.counts[0];
            for k in 1..D {
                let lo = self.lo[k] + idx[k] as Real * self.side[k];
                let f = (lo - c[k]).abs().max((lo + self.side[k] - c[k]).abs());
                rem -= f * f;
                flat_outer += self.wrapped(k, idx[k]) * stride;
                stride *= self.counts[k];
            }
            if rem > 0.0 {
                let q = rem.sqrt();
                if self.side[0] == 0.0 {
                    if (c[0] - self.lo[0]).abs() < q {
                        let bit = flat_outer;
                        mask[bit / 64] |= 1 << (bit % 64);
                    }
                } else {
                    // Voxel i is whole inside when lo0 + i s ≥ c − q and lo0 + (i+1) s ≤ c + q.
                    let a = ((c[0] - q - self.lo[0]) / self.side[0]).ceil() as isize;
                    let b = ((c[0] + q - self.lo[0]) / self.side[0]).floor() as isize - 1;
                    let (a, b) = if self.wrap[0] {
                        (a, b.min(a + self.counts[0] as isize - 1))
                    } else {
                        (a.max(0), b.min(self.counts[0] as isize - 1))
                    };
                    for i in a..=b {
                        // Guard the closed form against rounding at the run's ends.
                        let lo0 = self.lo[0] + i as Real * self.side[0];
                        let f = (lo0 - c[0]).abs().max((lo0 + self.side[0] - c[0]).abs());
                        if f * f < rem {
                            let bit = flat_outer + self.wrapped(0, i);
                            mask[bit / 64] |= 1 << (bit % 64);
                        }
                    }
                }
            }
            // Next index over axes 1..D.
            let mut k = 1;
            loop {
                if k == D {
                    return;
                }
                if idx[k] < last[k] {
                    idx[k] += 1;
                    break;
                }
                idx[k] = first[k];
                k += 1;
            }
        }
    }

    /// Index `i` along axis `k`, wrapped into range on a periodic axis.
    #[inline]
    fn wrapped(&self, k: usize, i: isize) -> usize {
        if self.wrap[k] {
            i.rem_euclid(self.counts[k] as isize) as usize
        } else {
            i as usize
        }
    }

    /// Indices of the voxels whose bit in `mask` is clear (lattices hold fewer
    /// than 2^32 voxels: see `Lattice::new`'s callers).
    pub fn uncovered(&self, mask: &[u64]) -> Vec<u32> {
        let mut out = Vec::new();
        let n = self.len();
        for (w, &word) in mask.iter().enumerate() {
            let mut free = !word;
            while free != 0 {
                let flat = w * 64 + free.trailing_zeros() as usize;
                if flat >= n {
                    break;
                }
                out.push(flat as u32);
                free &= free - 1;
            }
        }
        out
    }

    /// True when voxel `flat`'s bit in `mask` is set.
    #[inline]
    pub fn is_marked(mask: &[u64], flat: usize) -> bool {
        mask[flat / 64] & (1 << (flat % 64)) != 0
    }

    /// Low corner of voxel `flat`.
    #[inline]
    pub fn corner(&self, flat: usize) -> Vector<D> {
        let mut rest = flat;
        let mut corner = self.lo;
        for k in 0..D {
            let i = rest % self.counts[k];
            rest /= self.counts[k];
            corner[k] += i as Real * self.side[k];
        }
        corner
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::SQRT_2;

    /// Brute force: the voxels a ball holds whole, by testing every voxel.
    fn brute<const D: usize>(
        lat: &Lattice<D>,
        c: &Vector<D>,
        r: Real,
        period: &Vector<D>,
    ) -> Vec<bool> {
        let n = lat.len();
        let mut out = vec![false; n];
        for (flat, o) in out.iter_mut().enumerate() {
            let corner = lat.corner(flat);
            // Every image of the ball along wrapping axes.
            let mut shifts = vec![Vector::<D>::zero()];
            for k in 0..D {
                if lat.wrap[k] {
                    let mut more = Vec::new();
                    for s in &shifts {
                        for m in [-1.0, 1.0] {
                            let mut t = *s;
                            t[k] += m * period[k];
                            more.push(t);
                        }
                    }
                    shifts.extend(more);
                }
            }
            *o = shifts
                .iter()
                .any(|s| farthest2(&corner, &lat.side, &(*c + *s)) < r * r * COVER_MARGIN);
        }
        out
    }

    fn check<const D: usize>(lat: &Lattice<D>, c: Vector<D>, r: Real, period: Vector<D>) {
        let words = lat.len().div_ceil(64);
        let mut mask = vec![0u64; words];
        lat.mark_covered(&c, r, &mut mask);
        let want = brute(lat, &c, r, &period);
        for (flat, w) in want.iter().enumerate() {
            let got = mask[flat / 64] & (1 << (flat % 64)) != 0;
            assert_eq!(got, *w, "voxel {flat}, ball {c:?} r {r}");
        }
    }

    #[test]
    fn rasterised_balls_match_brute_force() {
        let lat2 = Lattice::new(
            Vector([1.0, 1.0]),
            Vector([9.0, 7.0]),
            0.37,
            1 << 20,
            [false; 2],
        );
        let per2 = Lattice::new(
            Vector([0.0, 1.0]),
            Vector([10.0, 7.0]),
            0.37,
            1 << 20,
            [true, false],
        );
        let lat3 = Lattice::new(
            Vector([0.0, 0.0, 1.0]),
            Vector([6.0, 5.0, 6.0]),
            0.41,
            1 << 20,
            [true, true, false],
        );
        let mut x: u64 = 12345;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as Real / (1u64 << 53) as Real
        };
        for _ in 0..200 {
            let c = Vector([next() * 12.0 - 1.0, next() * 9.0 - 1.0]);
            let r = 0.2 + 3.0 * next();
            check(&lat2, c, r, Vector([10.0, 0.0]));
            check(&per2, c, r, Vector([10.0, 0.0]));
            let c3 = Vector([next() * 6.0, next() * 5.0, next() * 8.0 - 1.0]);
            check(&lat3, c3, r, Vector([6.0, 5.0, 0.0]));
        }
    }

    #[test]
    fn a_voxel_is_covered_only_by_a_ball_holding_it_whole() {
        let side = Vector([1.0, 1.0]);
        let lo = Vector([0.0, 0.0]);
        let ball = |x: Real, y: Real, r: Real| Ball {
            centre: Vector([x, y]),
            radius2: r * r,
        };
        // Farthest corner at distance √2 from the voxel's low corner.
        assert!(covered(&lo, &side, &[ball(0.0, 0.0, SQRT_2 + 1e-6)]));
        assert!(!covered(&lo, &side, &[ball(0.0, 0.0, SQRT_2 - 1e-6)]));
        // Two balls that cover it together but neither alone.
        assert!(!covered(
            &lo,
            &side,
            &[ball(-0.5, 0.5, 1.2), ball(1.5, 0.5, 1.2)]
        ));
        assert_eq!(nearest2(&lo, &side, &Vector([3.0, 0.5])), 4.0);
        assert_eq!(farthest2(&lo, &side, &Vector([3.0, 0.5])), 9.25);
    }
}
