//! A plain cell list for finding neighbouring particles in O(n).
//!
//! The deposition engine has its own grid; the analysis deliberately does not use
//! it, so that the contacts and the checker in [`super::validate`] are an
//! independent test of the engine rather than a copy of its mistakes.

use crate::bed::Bed;
use crate::math::{Real, Vector};
use rayon::prelude::*;

/// Particles sorted into cubic cells at least `range` wide, so that every pair
/// closer than `range` (minimum image on periodic sides) lies in neighbouring cells.
pub(crate) struct CellList<const D: usize> {
    /// Cells per axis.
    dims: [usize; D],
    /// Coordinate of the low face of cell 0 on each axis.
    origin: [Real; D],
    /// Cell width on each axis.
    width: [Real; D],
    /// Axis wraps around (periodic side of positive finite width).
    wrap: [bool; D],
    /// Period of each wrapping axis.
    period: [Real; D],
    /// `items[start[c]..start[c + 1]]` are the particles of cell `c`, ascending.
    start: Vec<usize>,
    /// Particle ids grouped by cell.
    items: Vec<u32>,
}

impl<const D: usize> CellList<D> {
    /// Builds the cell list for the particles of `bed`; pairs up to centre distance
    /// `range` are guaranteed to be visited by [`CellList::for_each_pair`].
    pub(crate) fn new(bed: &Bed<D>, range: Real) -> Self {
        let n = bed.len();
        let mut lo = [Real::INFINITY; D];
        let mut hi = [Real::NEG_INFINITY; D];
        for c in &bed.centres {
            for k in 0..D {
                if c[k].is_finite() {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
        }
        let mut wrap = [false; D];
        let mut period = [0.0; D];
        for k in 0..D - 1 {
            let w = bed.container.size[k];
            if bed.container.periodic && w.is_finite() && w > 0.0 {
                wrap[k] = true;
                period[k] = w;
            }
        }
        let mut origin = [0.0; D];
        for k in 0..D {
            if !wrap[k] {
                origin[k] = if lo[k].is_finite() { lo[k] } else { 0.0 };
            }
        }
        // An infinite range (huge user tolerance) gives one cell per axis below; a
        // zero range (all radii zero) only needs coincident points together.
        let mut cell = if range > 0.0 { range } else { 1.0 };
        // A far outlier (imported data) must not make the dense grid huge: grow the
        // cells until there are at most a few per particle. Larger cells stay
        // correct, only slower.
        let budget = 4 * n + 64;
        let (mut dims, mut width);
        loop {
            dims = [1usize; D];
            width = [cell; D];
            for k in 0..D {
                if wrap[k] {
                    let m = (period[k] / cell).floor();
                    dims[k] = if m >= 1.0 { m.min(1e9) as usize } else { 1 };
                    width[k] = period[k] / dims[k] as Real;
                } else {
                    let span = if hi[k] >= lo[k] { hi[k] - lo[k] } else { 0.0 };
                    dims[k] = ((span / cell).floor().min(1e9) as usize).saturating_add(1);
                }
            }
            let total = dims.iter().fold(1usize, |a, &d| a.saturating_mul(d));
            if total <= budget {
                break;
            }
            cell *= 2.0;
            if !cell.is_finite() {
                // Coordinates near the float limits: one cell per axis.
                dims = [1; D];
                for k in 0..D {
                    width[k] = if wrap[k] { period[k] } else { Real::INFINITY };
                }
                break;
            }
        }
        let mut list = CellList {
            dims,
            origin,
            width,
            wrap,
            period,
            start: Vec::new(),
            items: Vec::new(),
        };
        let total: usize = dims.iter().product();
        let cells: Vec<usize> = bed.centres.iter().map(|c| list.cell_of(c)).collect();
        let mut start = vec![0usize; total + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; n];
        for (i, &c) in cells.iter().enumerate() {
            items[fill[c]] = i as u32;
            fill[c] += 1;
        }
        list.start = start;
        list.items = items;
        list
    }

    /// Index along each axis of the cell holding point `p` (clamped into the grid).
    fn coords(&self, p: &Vector<D>) -> [usize; D] {
        let mut idx = [0usize; D];
        for k in 0..D {
            let x = if self.wrap[k] {
                p[k].rem_euclid(self.period[k])
            } else {
                p[k] - self.origin[k]
            };
            // Non-finite coordinates land in some cell; their gaps are never
            // "touching", since every comparison with NaN is false.
            let t = (x / self.width[k]).floor();
            idx[k] = if t > 0.0 {
                (t.min(1e18) as usize).min(self.dims[k] - 1)
            } else {
                0
            };
        }
        idx
    }

    /// Linear cell index of point `p`.
    fn cell_of(&self, p: &Vector<D>) -> usize {
        self.linear(&self.coords(p))
    }

    /// Linear index of a cell from its per-axis indices.
    fn linear(&self, idx: &[usize; D]) -> usize {
        let mut l = 0;
        for k in (0..D).rev() {
            l = l * self.dims[k] + idx[k];
        }
        l
    }

    /// Calls `f(i, j)` once for every unordered pair `i < j` of particles in the
    /// same or neighbouring cells (a superset of the pairs within `range`).
    pub(crate) fn for_each_pair(&self, mut f: impl FnMut(usize, usize)) {
        let total = self.start.len() - 1;
        let mut neigh: Vec<usize> = Vec::with_capacity(27);
        for cell in 0..total {
            if self.start[cell] == self.start[cell + 1] {
                continue;
            }
            let mut idx = [0usize; D];
            let mut rest = cell;
            for k in 0..D {
                idx[k] = rest % self.dims[k];
                rest /= self.dims[k];
            }
            neigh.clear();
            for code in 0..3usize.pow(D as u32) {
                let mut m = [0usize; D];
                let mut c = code;
                let mut inside = true;
                for k in 0..D {
                    let off = (c % 3) as isize - 1;
                    c /= 3;
                    let n = self.dims[k] as isize;
                    let j = idx[k] as isize + off;
                    if self.wrap[k] {
                        m[k] = j.rem_euclid(n) as usize;
                    } else if j < 0 || j >= n {
                        inside = false;
                    } else {
                        m[k] = j as usize;
                    }
                }
                if inside {
                    neigh.push(self.linear(&m));
                }
            }
            // With only one or two cells across a period, several offsets wrap to
            // the same cell; visiting it twice would report a pair twice.
            neigh.sort_unstable();
            neigh.dedup();
            for a in self.start[cell]..self.start[cell + 1] {
                let i = self.items[a] as usize;
                for &nc in &neigh {
                    for b in self.start[nc]..self.start[nc + 1] {
                        let j = self.items[b] as usize;
                        if j > i {
                            f(i, j);
                        }
                    }
                }
            }
        }
    }

    /// For every unordered pair of particles whose centres are closer than
    /// `range` (minimum image; a little more is allowed), the value `keep(i, j)`
    /// with `i < j` if it is `Some`, in an order fixed by the bed alone (whatever
    /// the thread count). Cells are processed in parallel slabs; each cell pairs
    /// with half of its neighbours, over centres copied into cell order, so the
    /// inner loop reads memory in sequence.
    pub(crate) fn close_pairs<T: Send>(
        &self,
        bed: &Bed<D>,
        range: Real,
        keep: impl Fn(usize, usize) -> Option<T> + Sync,
    ) -> Vec<T> {
        // With fewer than three cells across a period one neighbour cell can be
        // reached through two offsets; the plain all-neighbour sweep handles it.
        let narrow = (0..D).any(|k| self.wrap[k] && self.dims[k] < 3);
        if narrow {
            let mut out = Vec::new();
            self.for_each_pair(|i, j| out.extend(keep(i, j)));
            return out;
        }
        // Centres in cell order, wrapped into the period on periodic axes (the
        // frame the cells were assigned in).
        let pos: Vec<[Real; D]> = self
            .items
            .iter()
            .map(|&i| {
                let c = &bed.centres[i as usize];
                let mut p = [0.0; D];
                for k in 0..D {
                    p[k] = if self.wrap[k] {
                        c[k].rem_euclid(self.period[k])
                    } else {
                        c[k]
                    };
                }
                p
            })
            .collect();
        // The forward half of the neighbour offsets: the first non-zero
        // component, from the last axis down, is +1.
        let offsets: Vec<[isize; D]> = (0..3usize.pow(D as u32))
            .map(|code| {
                let mut o = [0isize; D];
                let mut c = code;
                for ok in o.iter_mut() {
                    *ok = (c % 3) as isize - 1;
                    c /= 3;
                }
                o
            })
            .filter(|o| o.iter().rev().find(|&&x| x != 0) == Some(&1))
            .collect();
        // Slightly generous, so that rounding in the wrapped copies never drops
        // a pair `keep` would accept.
        let r2 = (range * (1.0 + 1e-9)).powi(2);
        let total = self.start.len() - 1;
        let chunk = total.div_ceil(64).max(1);
        let parts: Vec<Vec<T>> = (0..total.div_ceil(chunk))
            .into_par_iter()
            .map(|part| {
                let mut out = Vec::new();
                for cell in part * chunk..((part + 1) * chunk).min(total) {
                    self.cell_pairs(cell, &pos, &offsets, r2, &keep, &mut out);
                }
                out
            })
            .collect();
        parts.into_iter().flatten().collect()
    }

    /// The pairs of `close_pairs` with a first particle in `cell`.
    fn cell_pairs<T>(
        &self,
        cell: usize,
        pos: &[[Real; D]],
        offsets: &[[isize; D]],
        r2: Real,
        keep: &impl Fn(usize, usize) -> Option<T>,
        out: &mut Vec<T>,
    ) {
        let (a0, a1) = (self.start[cell], self.start[cell + 1]);
        if a0 == a1 {
            return;
        }
        let mut idx = [0usize; D];
        let mut rest = cell;
        for k in 0..D {
            idx[k] = rest % self.dims[k];
            rest /= self.dims[k];
        }
        let mut visit = |a: usize, b: usize| {
            let (i, j) = (self.items[a] as usize, self.items[b] as usize);
            if let Some(t) = keep(i.min(j), i.max(j)) {
                out.push(t);
            }
        };
        for a in a0..a1 {
            for b in a + 1..a1 {
                let d2: Real = (0..D).map(|k| (pos[b][k] - pos[a][k]).powi(2)).sum();
                if d2 <= r2 {
                    visit(a, b);
                }
            }
        }
        'offsets: for o in offsets {
            let mut m = [0usize; D];
            let mut shift = [0.0; D];
            for k in 0..D {
                let n = self.dims[k] as isize;
                let j = idx[k] as isize + o[k];
                if self.wrap[k] {
                    m[k] = j.rem_euclid(n) as usize;
                    if j < 0 {
                        shift[k] = -self.period[k];
                    } else if j >= n {
                        shift[k] = self.period[k];
                    }
                } else if j < 0 || j >= n {
                    continue 'offsets;
                } else {
                    m[k] = j as usize;
                }
            }
            let nc = self.linear(&m);
            for a in a0..a1 {
                let pa = pos[a];
                for b in self.start[nc]..self.start[nc + 1] {
                    let d2: Real = (0..D).map(|k| (pos[b][k] + shift[k] - pa[k]).powi(2)).sum();
                    if d2 <= r2 {
                        visit(a, b);
                    }
                }
            }
        }
    }
}
