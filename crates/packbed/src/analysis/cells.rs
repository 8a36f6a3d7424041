//! Pair search for the analysis: a multilevel cell list (Ogarko & Luding 2012, "A
//! fast multilevel algorithm for contact detection of arbitrarily polydisperse
//! objects"), linear in time and memory whatever the spread of sizes.
//!
//! One grid with cells sized to the largest particle is fine for equal spheres,
//! but with a broad size distribution each cell then holds thousands of fine
//! particles and every query scans them all. Here the particles are split by
//! radius into levels (classes a factor 2 apart), each with its own grid sized
//! to its own largest particle. Pairs within a level come from neighbouring cells
//! as usual; a pair across levels is found once, from its smaller particle, by
//! looking into the coarser level's cells around it.
//!
//! The deposition engine has its own grid; the analysis deliberately does not use
//! it, so that the contacts and the checker in [`super::validate`] are an
//! independent test of the engine rather than a copy of its mistakes.

use crate::bed::Bed;
use crate::math::Real;
use rayon::prelude::*;

/// Relative margin by which cells exceed, and query boxes overreach, the range
/// they must cover: rounding in a cell index must never lose a pair at exactly
/// the range.
const SLACK: Real = 1e-6;

/// Relative margin on the distance test, so that rounding in the wrapped copies
/// of the centres never drops a pair the caller would accept.
const GENEROUS: Real = 1e-9;

/// Levels have at most this many cells per particle (plus a few): memory stays
/// linear even for a far outlier in imported data or a sparse level.
const CELLS_PER_PARTICLE: usize = 4;

/// Particles sorted by size into levels, each with cells at least as wide as the
/// largest pair range within it. A pair `(i, j)` is *in range* when the distance
/// of the centres (minimum image on periodic sides) is at most
/// `r_i + r_j + tol × min(r_i, r_j)` (a little more is allowed).
pub(crate) struct CellList<const D: usize> {
    /// Axis wraps around (periodic side of positive finite width).
    wrap: [bool; D],
    /// Period of each wrapping axis.
    period: [Real; D],
    /// Relative gap tolerance of the range (finite or infinite, never negative).
    tol: Real,
    /// Levels from the coarsest (largest particles) to the finest.
    levels: Vec<Level<D>>,
}

/// One level: a uniform grid over its own particles.
struct Level<const D: usize> {
    /// Largest radius in the level.
    r_max: Real,
    /// Cells per axis.
    dims: [usize; D],
    /// Coordinate of the low face of cell 0 on each axis.
    origin: [Real; D],
    /// Cell width on each axis.
    width: [Real; D],
    /// `start[c]..start[c + 1]` index the particles of cell `c` in the arrays below.
    start: Vec<u32>,
    /// Particle ids in cell order, ascending within a cell.
    ids: Vec<u32>,
    /// Centres in cell order, wrapped into the period on periodic axes.
    pos: Vec<[Real; D]>,
    /// Radii in cell order (negative or NaN radii as 0).
    rad: Vec<Real>,
}

/// The range of a pair of radii (see [`CellList`]).
#[inline]
fn reach(ra: Real, rb: Real, tol: Real) -> Real {
    let m = ra.min(rb);
    // 0 × ∞ would be NaN, which no distance passes.
    ra + rb + if m > 0.0 { tol * m } else { 0.0 }
}

/// Whether squared distance `d2` is within `range` (generously).
#[inline]
fn within(d2: Real, range: Real) -> bool {
    let r = range * (1.0 + GENEROUS);
    d2 <= r * r
}

impl<const D: usize> CellList<D> {
    /// Sorts the particles of `bed` into levels for the pairs within
    /// `r_i + r_j + tol × min(r_i, r_j)` (a negative or NaN `tol` counts as 0).
    /// Particles with a non-finite coordinate are never in range of anything and
    /// are left out.
    pub(crate) fn new(bed: &Bed<D>, tol: Real) -> Self {
        let tol = if tol > 0.0 { tol } else { 0.0 };
        let n = bed.len();
        let mut wrap = [false; D];
        let mut period = [0.0; D];
        for k in 0..D - 1 {
            let w = bed.container.size[k];
            if bed.container.periodic && w.is_finite() && w > 0.0 {
                wrap[k] = true;
                period[k] = w;
            }
        }
        // Centres in the frame of the cells; `None` for a non-finite one.
        let pos: Vec<Option<[Real; D]>> = bed
            .centres
            .iter()
            .map(|c| {
                let mut p = [0.0; D];
                for k in 0..D {
                    if !c[k].is_finite() {
                        return None;
                    }
                    p[k] = if wrap[k] {
                        c[k].rem_euclid(period[k])
                    } else {
                        c[k]
                    };
                }
                Some(p)
            })
            .collect();
        let rad: Vec<Real> = bed
            .radii
            .iter()
            .map(|&r| if r > 0.0 { r } else { 0.0 })
            .collect();
        let mut lo = [Real::INFINITY; D];
        let mut hi = [Real::NEG_INFINITY; D];
        let mut r_big: Real = 0.0;
        for (p, &r) in pos.iter().zip(&rad) {
            if let Some(p) = p {
                for k in 0..D {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
                r_big = r_big.max(r);
            }
        }
        // Size classes a factor 2 apart from the largest radius down; radius 0 (or
        // a radius too small to matter) in the last.
        const CLASSES: usize = 64;
        let class_of = |r: Real| -> usize {
            if r_big <= 0.0 || !r_big.is_finite() {
                0
            } else if r > 0.0 {
                let c = (r_big / r).log2().floor();
                if c >= 0.0 {
                    (c as usize).min(CLASSES - 1)
                } else {
                    0
                }
            } else {
                CLASSES - 1
            }
        };
        let class: Vec<u8> = (0..n)
            .map(|i| {
                if pos[i].is_some() {
                    class_of(rad[i]) as u8
                } else {
                    u8::MAX
                }
            })
            .collect();
        let mut count = [0usize; CLASSES];
        let mut class_r = [0.0 as Real; CLASSES];
        for (&c, &r) in class.iter().zip(&rad) {
            if c != u8::MAX {
                count[c as usize] += 1;
                class_r[c as usize] = class_r[c as usize].max(r);
            }
        }
        // Natural cells of a grid of width `w` over the whole bed.
        let extent: [Real; D] = std::array::from_fn(|k| {
            if wrap[k] {
                period[k]
            } else if hi[k] >= lo[k] {
                hi[k] - lo[k]
            } else {
                0.0
            }
        });
        let natural_cells = |w: Real| -> Real {
            (0..D)
                .map(|k| (extent[k] / w).floor().max(1.0))
                .product::<Real>()
        };
        // Classes become levels from the coarsest down. A class too sparse to put
        // one particle into every few cells of the level above joins that level:
        // its own level would cost every finer particle a look into a grid of
        // nearly empty cells, while in the level above it adds less than that.
        let mut level_of_class = [usize::MAX; CLASSES];
        let mut level_r: Vec<Real> = Vec::new();
        for c in 0..CLASSES {
            if count[c] == 0 {
                continue;
            }
            let join = level_r.last().is_some_and(|&r| {
                let w = reach(r, r, tol);
                let cells = if w > 0.0 { natural_cells(w) } else { 1.0 };
                (count[c] << D) as Real <= cells
            });
            if !join {
                level_r.push(class_r[c]);
            }
            level_of_class[c] = level_r.len() - 1;
        }
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); level_r.len()];
        for i in 0..n {
            if class[i] != u8::MAX {
                members[level_of_class[class[i] as usize]].push(i as u32);
            }
        }
        let levels = members
            .iter()
            .zip(&level_r)
            .map(|(m, &r)| Level::new(m, &pos, &rad, r, tol, wrap, period))
            .collect();
        CellList {
            wrap,
            period,
            tol,
            levels,
        }
    }

    /// Calls `f(i, j)` once for every unordered pair `i < j` in range, in
    /// ascending `(i, j)`.
    #[cfg(test)]
    pub(crate) fn for_each_pair(&self, f: impl FnMut(usize, usize)) {
        self.for_each_pair_where(|_, _| true, f)
    }

    /// [`Self::for_each_pair`] for the pairs `wanted(i, j)` only. The pairs are
    /// gathered before `f` sees them: the others must not be, since one chain
    /// of heavily overlapping beads has billions of pairs of its own.
    pub(crate) fn for_each_pair_where(
        &self,
        wanted: impl Fn(usize, usize) -> bool + Sync,
        mut f: impl FnMut(usize, usize),
    ) {
        let mut pairs = self.close_pairs(|i, j| wanted(i, j).then_some((i as u32, j as u32)));
        pairs.par_sort_unstable();
        for (i, j) in pairs {
            f(i as usize, j as usize);
        }
    }

    /// For every unordered pair in range, the value `keep(i, j)` with `i < j` if
    /// it is `Some`, in an order fixed by the bed alone (whatever the thread
    /// count): level by level, cell by cell, then the pairs across levels from
    /// the finer particle, in cell order.
    pub(crate) fn close_pairs<T: Send>(
        &self,
        keep: impl Fn(usize, usize) -> Option<T> + Sync,
    ) -> Vec<T> {
        enum Task {
            /// Pairs within level `0` from cells `1..2`.
            Within(usize, usize, usize),
            /// Pairs of level `0`'s particles `1..2` with coarser levels.
            Across(usize, usize, usize),
        }
        let mut tasks = Vec::new();
        for (l, level) in self.levels.iter().enumerate() {
            let cells = level.start.len() - 1;
            let chunk = cells.div_ceil(64).max(1);
            for a in (0..cells).step_by(chunk) {
                tasks.push(Task::Within(l, a, (a + chunk).min(cells)));
            }
        }
        for (l, level) in self.levels.iter().enumerate().skip(1) {
            let m = level.ids.len();
            let chunk = m.div_ceil(64).max(1024);
            for a in (0..m).step_by(chunk) {
                tasks.push(Task::Across(l, a, (a + chunk).min(m)));
            }
        }
        let work = |task: Task| {
            let mut out = Vec::new();
            match task {
                Task::Within(l, a, b) => self.within_level(l, a..b, &keep, &mut out),
                Task::Across(l, a, b) => {
                    let level = &self.levels[l];
                    for p in a..b {
                        let i = level.ids[p] as usize;
                        for coarse in &self.levels[..l] {
                            self.across(i, &level.pos[p], level.rad[p], coarse, &keep, &mut out);
                        }
                    }
                }
            }
            out
        };
        let parts: Vec<Vec<T>> = tasks.into_par_iter().map(work).collect();
        parts.into_iter().flatten().collect()
    }

    /// The pairs of level `l` with a first particle in one of `cells`.
    fn within_level<T>(
        &self,
        l: usize,
        cells: std::ops::Range<usize>,
        keep: &impl Fn(usize, usize) -> Option<T>,
        out: &mut Vec<T>,
    ) {
        let level = &self.levels[l];
        // With fewer than three cells across a period one neighbour cell can be
        // reached through two offsets (and with another image); there every
        // neighbour cell is taken once, each pair from its lower cell, at the
        // minimum image.
        let narrow = (0..D).any(|k| self.wrap[k] && level.dims[k] < 3);
        let offsets = if narrow {
            all_offsets::<D>()
        } else {
            forward_offsets::<D>()
        };
        let mut neigh: Vec<(usize, [Real; D])> = Vec::with_capacity(offsets.len());
        for cell in cells {
            let (a0, a1) = (level.start[cell] as usize, level.start[cell + 1] as usize);
            if a0 == a1 {
                continue;
            }
            let idx = level.unlinear(cell);
            neigh.clear();
            'offsets: for o in &offsets {
                let mut m = [0usize; D];
                let mut shift = [0.0; D];
                for k in 0..D {
                    let n = level.dims[k] as isize;
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
                let nc = level.linear(&m);
                if !narrow || nc > cell {
                    neigh.push((nc, shift));
                }
            }
            if narrow {
                neigh.sort_unstable_by_key(|e| e.0);
                neigh.dedup_by_key(|e| e.0);
            }
            for a in a0..a1 {
                let (pa, ra) = (level.pos[a], level.rad[a]);
                for b in a + 1..a1 {
                    let d2 = if narrow {
                        self.dist2(&pa, &level.pos[b])
                    } else {
                        dist2_shifted(&pa, &level.pos[b], &[0.0; D])
                    };
                    if within(d2, reach(ra, level.rad[b], self.tol)) {
                        emit(level.ids[a], level.ids[b], keep, out);
                    }
                }
                for &(nc, shift) in &neigh {
                    let (b0, b1) = (level.start[nc] as usize, level.start[nc + 1] as usize);
                    for b in b0..b1 {
                        let d2 = if narrow {
                            self.dist2(&pa, &level.pos[b])
                        } else {
                            dist2_shifted(&pa, &level.pos[b], &shift)
                        };
                        if within(d2, reach(ra, level.rad[b], self.tol)) {
                            emit(level.ids[a], level.ids[b], keep, out);
                        }
                    }
                }
            }
        }
    }

    /// The pairs of particle `i` (centre `p`, radius `r`) with the particles of
    /// the coarser level `coarse`: those in the cells overlapping the box around
    /// `p` that reaches any of them.
    fn across<T>(
        &self,
        i: usize,
        p: &[Real; D],
        r: Real,
        coarse: &Level<D>,
        keep: &impl Fn(usize, usize) -> Option<T>,
        out: &mut Vec<T>,
    ) {
        // min(r, r_j) <= r, whatever r_j.
        let h = reach(r, coarse.r_max, self.tol) * (1.0 + SLACK);
        // Per axis: first cell (unwrapped on periodic axes) and number of cells.
        let mut first = [0isize; D];
        let mut span = [0usize; D];
        for k in 0..D {
            let n = coarse.dims[k];
            let t0 = floor((p[k] - h - coarse.origin[k]) / coarse.width[k]);
            let t1 = floor((p[k] + h - coarse.origin[k]) / coarse.width[k]);
            if self.wrap[k] {
                // NaN (an infinite reach) fails the test and takes every cell.
                if t1 - t0 + 1.0 < n as Real {
                    first[k] = t0 as isize;
                    span[k] = (t1 - t0) as usize + 1;
                } else {
                    first[k] = 0;
                    span[k] = n;
                }
            } else {
                let top = (n - 1) as Real;
                let a = if t0 > 0.0 { t0.min(top) } else { 0.0 };
                let b = if t1 < top { t1.max(0.0) } else { top };
                if t1 < 0.0 || t0 > top {
                    // The box misses every particle of the level on this axis.
                    return;
                }
                first[k] = a as isize;
                span[k] = (b - a) as usize + 1;
            }
        }
        // The usual case: a few cells per axis, each reached through one image,
        // so the image shift is known per cell and the minimum image need not be
        // sought per candidate (the bulk of the cost on broad size distributions).
        const FEW: usize = 4;
        if (0..D).all(|k| span[k] <= FEW && (!self.wrap[k] || span[k] < coarse.dims[k])) {
            let mut part = [[0usize; FEW]; D];
            let mut shift = [[0.0 as Real; FEW]; D];
            let mut stride = 1;
            for k in 0..D {
                let n = coarse.dims[k] as isize;
                for s in 0..span[k] {
                    let j = first[k] + s as isize;
                    let (m, image) = if self.wrap[k] {
                        (j.rem_euclid(n), j.div_euclid(n) as Real * self.period[k])
                    } else {
                        (j, 0.0)
                    };
                    part[k][s] = m as usize * stride;
                    shift[k][s] = image;
                }
                stride *= coarse.dims[k];
            }
            let mut step = [0usize; D];
            loop {
                let mut c = 0;
                let mut sh = [0.0; D];
                for k in 0..D {
                    c += part[k][step[k]];
                    sh[k] = shift[k][step[k]];
                }
                for b in coarse.start[c] as usize..coarse.start[c + 1] as usize {
                    let d2 = dist2_shifted(p, &coarse.pos[b], &sh);
                    if within(d2, reach(r, coarse.rad[b], self.tol)) {
                        emit(i as u32, coarse.ids[b], keep, out);
                    }
                }
                if !next_cell(&mut step, &span) {
                    return;
                }
            }
        }
        let mut step = [0usize; D];
        loop {
            let mut m = [0usize; D];
            for k in 0..D {
                let j = first[k] + step[k] as isize;
                m[k] = if self.wrap[k] {
                    j.rem_euclid(coarse.dims[k] as isize) as usize
                } else {
                    j as usize
                };
            }
            let c = coarse.linear(&m);
            for b in coarse.start[c] as usize..coarse.start[c + 1] as usize {
                let d2 = self.dist2(p, &coarse.pos[b]);
                if within(d2, reach(r, coarse.rad[b], self.tol)) {
                    emit(i as u32, coarse.ids[b], keep, out);
                }
            }
            if !next_cell(&mut step, &span) {
                return;
            }
        }
    }

    /// Squared distance of wrapped centres at the minimum image.
    #[inline]
    fn dist2(&self, a: &[Real; D], b: &[Real; D]) -> Real {
        let mut d2 = 0.0;
        for k in 0..D {
            let mut d = b[k] - a[k];
            if self.wrap[k] {
                let p = self.period[k];
                if d > 0.5 * p {
                    d -= p;
                } else if d < -0.5 * p {
                    d += p;
                }
            }
            d2 += d * d;
        }
        d2
    }
}

/// `t.floor()` without the library call that it compiles to on plain x86-64,
/// which showed in the profile of the cross-level queries.
#[inline]
fn floor(t: Real) -> Real {
    if t.abs() < 4e15 {
        let f = t as i64 as Real;
        if f > t {
            f - 1.0
        } else {
            f
        }
    } else {
        // NaN, infinities and integers already.
        t.floor()
    }
}

/// Squared distance from `a` to `b + shift`.
#[inline]
fn dist2_shifted<const D: usize>(a: &[Real; D], b: &[Real; D], shift: &[Real; D]) -> Real {
    (0..D).map(|k| (b[k] + shift[k] - a[k]).powi(2)).sum()
}

/// Hands the pair of particles `a`, `b` to `keep` in the order `i < j`.
#[inline]
fn emit<T>(a: u32, b: u32, keep: &impl Fn(usize, usize) -> Option<T>, out: &mut Vec<T>) {
    let (i, j) = (a.min(b) as usize, a.max(b) as usize);
    if let Some(t) = keep(i, j) {
        out.push(t);
    }
}

/// Every neighbour offset but zero.
fn all_offsets<const D: usize>() -> Vec<[isize; D]> {
    (0..3usize.pow(D as u32))
        .map(|code| {
            let mut o = [0isize; D];
            let mut c = code;
            for ok in o.iter_mut() {
                *ok = (c % 3) as isize - 1;
                c /= 3;
            }
            o
        })
        .filter(|o| o.iter().any(|&x| x != 0))
        .collect()
}

/// The forward half of the neighbour offsets: the first non-zero component,
/// from the last axis down, is +1.
fn forward_offsets<const D: usize>() -> Vec<[isize; D]> {
    all_offsets::<D>()
        .into_iter()
        .filter(|o| o.iter().rev().find(|&&x| x != 0) == Some(&1))
        .collect()
}

impl<const D: usize> Level<D> {
    /// The grid of the particles `members` (ascending ids, finite centres),
    /// largest radius `r_max`.
    fn new(
        members: &[u32],
        pos: &[Option<[Real; D]>],
        rad: &[Real],
        r_max: Real,
        tol: Real,
        wrap: [bool; D],
        period: [Real; D],
    ) -> Self {
        let n = members.len();
        let at = |i: u32| pos[i as usize].unwrap_or([0.0; D]);
        let mut lo = [Real::INFINITY; D];
        let mut hi = [Real::NEG_INFINITY; D];
        for &i in members {
            let p = at(i);
            for k in 0..D {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let mut origin = [0.0; D];
        let mut extent = [0.0 as Real; D];
        for k in 0..D {
            extent[k] = if wrap[k] {
                period[k]
            } else if hi[k] >= lo[k] {
                origin[k] = lo[k];
                hi[k] - lo[k]
            } else {
                0.0
            };
        }
        let mut cell = reach(r_max, r_max, tol) * (1.0 + SLACK);
        if cell.is_nan() || cell <= 0.0 {
            // Radius 0: only coincident centres pair up; any width is correct,
            // so take one with about a particle per cell.
            let widest = extent.iter().copied().fold(0.0, Real::max);
            cell = widest / (n.max(1) as Real).powf(1.0 / D as Real);
            if cell.is_nan() || cell <= 0.0 {
                cell = 1.0;
            }
        }
        // A far outlier or a sparse level must not make the dense grid huge: grow
        // the cells until there are at most a few per particle. Larger cells stay
        // correct, only slower.
        let budget = CELLS_PER_PARTICLE * n + 64;
        let (mut dims, mut width);
        loop {
            dims = [1usize; D];
            width = [cell; D];
            for k in 0..D {
                let m = (extent[k] / cell).floor();
                if wrap[k] {
                    dims[k] = if m >= 1.0 { m.min(1e9) as usize } else { 1 };
                    width[k] = period[k] / dims[k] as Real;
                } else {
                    dims[k] = (m.min(1e9) as usize).saturating_add(1);
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
        let mut level = Level {
            r_max,
            dims,
            origin,
            width,
            start: Vec::new(),
            ids: Vec::new(),
            pos: Vec::new(),
            rad: Vec::new(),
        };
        let total: usize = dims.iter().product();
        let cells: Vec<u32> = members
            .iter()
            .map(|&i| level.cell_of(&at(i)) as u32)
            .collect();
        let mut start = vec![0u32; total + 1];
        for &c in &cells {
            start[c as usize + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut slot = vec![0u32; n];
        for (s, &c) in slot.iter_mut().zip(&cells) {
            *s = fill[c as usize];
            fill[c as usize] += 1;
        }
        drop(fill);
        let mut ids = vec![0u32; n];
        let mut cpos = vec![[0.0; D]; n];
        let mut crad = vec![0.0; n];
        for (&s, &i) in slot.iter().zip(members) {
            ids[s as usize] = i;
            cpos[s as usize] = at(i);
            crad[s as usize] = rad[i as usize];
        }
        level.start = start;
        level.ids = ids;
        level.pos = cpos;
        level.rad = crad;
        level
    }

    /// Linear index of the cell holding point `p` (clamped into the grid).
    fn cell_of(&self, p: &[Real; D]) -> usize {
        let mut idx = [0usize; D];
        for k in 0..D {
            let t = floor((p[k] - self.origin[k]) / self.width[k]);
            idx[k] = if t > 0.0 {
                (t.min(1e18) as usize).min(self.dims[k] - 1)
            } else {
                0
            };
        }
        self.linear(&idx)
    }

    /// Linear index of a cell from its per-axis indices.
    fn linear(&self, idx: &[usize; D]) -> usize {
        let mut l = 0;
        for k in (0..D).rev() {
            l = l * self.dims[k] + idx[k];
        }
        l
    }

    /// Per-axis indices of a cell from its linear index.
    fn unlinear(&self, mut cell: usize) -> [usize; D] {
        let mut idx = [0usize; D];
        for k in 0..D {
            idx[k] = cell % self.dims[k];
            cell /= self.dims[k];
        }
        idx
    }
}

/// Steps `step` to the next cell of a box `span` cells wide per axis, first
/// axis fastest; false once every cell has been visited.
#[inline]
fn next_cell<const D: usize>(step: &mut [usize; D], span: &[usize; D]) -> bool {
    for k in 0..D {
        step[k] += 1;
        if step[k] < span[k] {
            return true;
        }
        step[k] = 0;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use crate::math::Vector;
    use proptest::prelude::*;
    use std::collections::BTreeSet;

    type Pairs = BTreeSet<(usize, usize)>;

    /// The pairs in range by brute force over all pairs: `(must, may)`, those
    /// clearly within and those up to a little beyond the range.
    fn brute<const D: usize>(bed: &Bed<D>, tol: Real) -> (Pairs, Pairs) {
        let (mut must, mut may) = (BTreeSet::new(), BTreeSet::new());
        for i in 0..bed.len() {
            for j in i + 1..bed.len() {
                let d = bed
                    .container
                    .displacement(&bed.centres[i], &bed.centres[j])
                    .norm();
                let range = reach(bed.radii[i].max(0.0), bed.radii[j].max(0.0), tol);
                if d <= range * (1.0 - 1e-9) {
                    must.insert((i, j));
                }
                if d <= range * (1.0 + 1e-6) {
                    may.insert((i, j));
                }
            }
        }
        (must, may)
    }

    /// Checks both pair visitors of the cell list against brute force.
    fn agrees<const D: usize>(bed: &Bed<D>, tol: Real) -> Result<(), TestCaseError> {
        let (must, may) = brute(bed, tol);
        let cells = CellList::new(bed, tol);
        let mut seen = Vec::new();
        cells.for_each_pair(|i, j| seen.push((i, j)));
        prop_assert!(
            seen.windows(2).all(|w| w[0] < w[1]),
            "not ascending, or twice"
        );
        let listed = cells.close_pairs(|i, j| Some((i, j)));
        let mut sorted = listed.clone();
        sorted.sort_unstable();
        prop_assert_eq!(&sorted, &seen);
        let set: Pairs = seen.into_iter().collect();
        prop_assert!(
            must.is_subset(&set),
            "missed {:?}",
            must.difference(&set).collect::<Vec<_>>()
        );
        prop_assert!(
            set.is_subset(&may),
            "extra {:?}",
            set.difference(&may).collect::<Vec<_>>()
        );
        // The order of `close_pairs` depends on the bed alone.
        prop_assert_eq!(listed, cells.close_pairs(|i, j| Some((i, j))));
        Ok(())
    }

    /// Radii spread over a factor 2^spread, some of them 0.
    fn radius(u: Real, spread: Real, zero: bool) -> Real {
        if zero {
            0.0
        } else {
            (-u * spread * std::f64::consts::LN_2).exp()
        }
    }

    proptest! {
        #[test]
        fn multilevel_pairs_are_exactly_the_brute_force_pairs_3d(
            periodic in any::<bool>(),
            w in 0.5f64..40.0,
            spread in 0.0f64..8.0,
            pts in prop::collection::vec(
                (0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0, prop::bool::weighted(0.03)),
                0..300,
            ),
            tol in prop_oneof![Just(0.0), 0.0f64..0.5],
        ) {
            let mut bed = Bed::new(
                Container { size: Vector([w, 0.7 * w, 10.0]), periodic },
                Vec::new(),
            );
            for &(x, y, z, u, zero) in &pts {
                bed.push(Vector([x * w, y * 0.7 * w, z * 10.0]), radius(u, spread, zero), 0);
            }
            agrees(&bed, tol)?;
        }

        #[test]
        fn multilevel_pairs_are_exactly_the_brute_force_pairs_2d(
            periodic in any::<bool>(),
            w in 0.5f64..60.0,
            spread in 0.0f64..10.0,
            pts in prop::collection::vec(
                (-0.1f64..1.1, 0.0f64..1.0, 0.0f64..1.0, prop::bool::weighted(0.03)),
                0..300,
            ),
            tol in prop_oneof![Just(0.0), 0.0f64..0.5],
        ) {
            // Some centres outside the side walls or beyond the period too.
            let discs: Vec<(Real, Real, Real)> = pts
                .iter()
                .map(|&(x, y, u, zero)| (x * w, y * 20.0, radius(u, spread, zero)))
                .collect();
            agrees(&Bed::of_discs([w, 20.0], periodic, &discs), tol)?;
        }
    }

    #[test]
    fn a_coarse_class_beside_many_fines_finds_every_pair() {
        // Radii 1:1000 with the fines packed around the large ones, periodic.
        let mut discs = Vec::new();
        for k in 0..4 {
            discs.push((5.0 + 10.0 * k as Real, 5.0, 5.0));
        }
        for a in 0..40 {
            for b in 0..12 {
                discs.push((
                    a as Real + 0.5,
                    b as Real + 0.5,
                    0.005 * (1 + (a + b) % 3) as Real,
                ));
            }
        }
        let bed = Bed::of_discs([40.0, 12.0], true, &discs);
        let cells = CellList::new(&bed, 0.5);
        assert!(cells.levels.len() >= 2);
        let mut seen = Vec::new();
        cells.for_each_pair(|i, j| seen.push((i, j)));
        let (must, may) = brute(&bed, 0.5);
        let set: Pairs = seen.iter().copied().collect();
        assert_eq!(set.len(), seen.len());
        assert!(must.is_subset(&set) && set.is_subset(&may));
    }

    #[test]
    fn outliers_and_non_finite_centres_keep_the_grid_small() {
        // Far out along the height, which never wraps.
        let mut discs = vec![(1.0, 1.0, 1.0), (2.4, 1.0, 0.5), (1.0, 1e300, 1.0)];
        discs.push((Real::NAN, 1.0, 1.0));
        discs.push((2.0, Real::INFINITY, 0.1));
        for periodic in [false, true] {
            let bed = Bed::of_discs([10.0, 10.0], periodic, &discs);
            let cells = CellList::new(&bed, 0.0);
            assert!(cells.levels.iter().all(|l| l.start.len() <= 4 * 5 + 65));
            let mut seen = Vec::new();
            cells.for_each_pair(|i, j| seen.push((i, j)));
            assert_eq!(seen, vec![(0, 1)]);
        }
    }

    #[test]
    fn zero_radii_pair_only_when_coincident() {
        let bed = Bed::of_discs(
            [10.0, 10.0],
            true,
            &[
                (1.0, 1.0, 0.0),
                (1.0, 1.0, 0.0),
                (1.5, 1.0, 0.0),
                (11.0, 1.0, 0.0),
            ],
        );
        let mut seen = Vec::new();
        CellList::new(&bed, 0.1).for_each_pair(|i, j| seen.push((i, j)));
        assert_eq!(seen, vec![(0, 1), (0, 3), (1, 3)]);
    }
}
