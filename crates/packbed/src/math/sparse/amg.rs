//! Conjugate gradients preconditioned by aggregation algebraic multigrid, for
//! the large graph-Laplacian systems of the pore network.
//!
//! A direct factor of a 3D network's Laplacian grows as `n^{4/3}` in memory
//! and `n²` in work (the top separator is dense): 14 s per factor at 6·10^5
//! pores, hours at 6·10^6. Multigrid keeps the work per step proportional to
//! `n`. Aggregates of strongly coupled nodes (Vaněk, Mandel & Brezina 1996)
//! become the coarse nodes, coarse operators are Galerkin products, the
//! coarsest is factored densely; a V-cycle with forward Gauss–Seidel before
//! and backward after is a symmetric preconditioner, as conjugate gradients
//! needs. The prolongator is the aggregates' plain indicator: smoothing it
//! (smoothed aggregation) cut no steps on pore networks (54 against 46 on
//! 6.5·10^4 pores) but made the coarse operators nearly dense (750 entries a
//! row at the third level) and the set-up on 6·10^5 pores ran out of memory.
//! The cycle runs in single precision and conjugate gradients in double
//! (see `sparse/lane.rs`). Every loop runs in a fixed order, so the answer
//! does not depend on the thread count.

// `!(a > b)` is meant: a NaN must take the failing branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::blocks::{self, dot, split, CHUNK};
use super::lane::Lane;
use crate::math::Real;
use rayon::prelude::*;

/// Symmetric sparse matrix, both triangles, rows in CSR, the diagonal first
/// in each row, the others in column order.
///
/// Gauss–Seidel is a chain: each row waits for the value its neighbour just
/// found. Where each row's couplings within its block start, where those
/// above the row start, and the inverse diagonal are kept so that a sweep
/// neither tests every column against the row nor divides (both sit on that
/// chain). Once the hierarchy is built, `Csr::cut_into_blocks` puts each row's
/// couplings to other blocks first (see `blocks`).
///
/// The values are `V`: double precision where the matrix is built and where
/// conjugate gradients multiply by it, single on the coarse levels, which
/// only the cycle reads (see `sparse/lane.rs`).
#[derive(Clone, Debug, Default)]
pub struct Csr<V = Real> {
    /// Where each row starts, and the end. 32-bit, as are `inner` and
    /// `upper`: a sweep reads all three for every row, and a plain
    /// aggregate's coarse operator has no more entries than its fine one, so
    /// the finest level's count bounds them all (checked in
    /// [`Csr::renumbered`]).
    ptr: Vec<u32>,
    col: Vec<u32>,
    val: Vec<V>,
    /// First entry of each row coupling it within its block.
    inner: Vec<u32>,
    /// First entry of each row coupling it to a later row of its block.
    upper: Vec<u32>,
    /// `1 / a_ii` (with the l1 term of an edge row, see
    /// [`Csr::cut_into_blocks`]), unshifted.
    inv: Vec<V>,
    /// The rows with a shift in some system (see [`Multigrid::shifted`]),
    /// ascending, and their inverse shifted diagonals, `systems` a row. Few
    /// rows have one (the flow's held nodes and the neighbours of its fixed
    /// ones): one inverse a row for each of three systems was 0.1 GB read
    /// twice a cycle at 10^6 spheres.
    shifted_rows: Vec<u32>,
    shifted_inv: Vec<V>,
    /// How many systems `shifted_inv` serves.
    systems: usize,
    /// Block boundaries of the rows.
    blocks: Vec<usize>,
    /// The rows coupled to another block, ascending.
    edges: Vec<u32>,
    /// Block boundaries of `edges`.
    edge_blocks: Vec<usize>,
    /// Each edge row's couplings to other blocks, again, side by side: an
    /// edge row's own entries lie far apart (a periodic side's partner is at
    /// the far end of the curve), and reading them there cost a tenth of a
    /// 10^6-sphere flow solve.
    edge_ptr: Vec<usize>,
    edge_col: Vec<u32>,
    edge_val: Vec<V>,
    /// Per edge row, the sum of its `|a_ij|` to other blocks.
    edge_l1: Vec<V>,
}

impl<V: Lane> Csr<V> {
    fn n(&self) -> usize {
        self.ptr.len() - 1
    }

    /// Row `i`'s entries, the diagonal included.
    fn entries(&self, i: usize) -> std::ops::Range<usize> {
        self.ptr[i] as usize..self.ptr[i + 1] as usize
    }

    /// Row `i`'s entries off the diagonal.
    fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.ptr[i] as usize + 1..self.ptr[i + 1] as usize
    }

    /// Row `i`'s inverse diagonal for each of `K` right-hand sides on a
    /// sweep up its block (one system's for all, or each its own); `next` is
    /// the first shifted row not yet passed, from [`Csr::shifted_from`] at
    /// the block's first row.
    #[inline(always)]
    fn inv_up<const K: usize>(&self, i: usize, next: &mut usize) -> [V; K] {
        let inv = self.inv_at(i, *next);
        *next += usize::from(self.shifted_rows.get(*next) == Some(&(i as u32)));
        inv
    }

    /// The same on a sweep down its block; `next` is one past the next
    /// shifted row, from [`Csr::shifted_from`] at the block's end.
    #[inline(always)]
    fn inv_down<const K: usize>(&self, i: usize, next: &mut usize) -> [V; K] {
        let at = next.wrapping_sub(1);
        let inv = self.inv_at(i, at);
        *next -= usize::from(self.shifted_rows.get(at) == Some(&(i as u32)));
        inv
    }

    /// Row `i`'s inverse diagonals, `next` the shifted row it may be.
    #[inline(always)]
    fn inv_at<const K: usize>(&self, i: usize, next: usize) -> [V; K] {
        if self.shifted_rows.get(next) == Some(&(i as u32)) {
            let s = &self.shifted_inv[next * self.systems..];
            if self.systems == 1 {
                [s[0]; K]
            } else {
                std::array::from_fn(|m| s[m])
            }
        } else {
            [self.inv[i]; K]
        }
    }

    /// Where the shifted rows from row `i` on start.
    fn shifted_from(&self, i: usize) -> usize {
        self.shifted_rows.partition_point(|&r| (r as usize) < i)
    }
}

impl Csr {
    fn new(ptr: Vec<usize>, col: Vec<u32>, val: Vec<Real>) -> Csr {
        let n = ptr.len() - 1;
        debug_assert!(col.len() < u32::MAX as usize);
        let upper = (0..n)
            .map(|i| {
                let row = &col[ptr[i] + 1..ptr[i + 1]];
                (ptr[i] + 1 + row.partition_point(|&c| (c as usize) < i)) as u32
            })
            .collect();
        let inner = ptr[..n].iter().map(|&p| p as u32 + 1).collect();
        let ptr = ptr.into_iter().map(|p| p as u32).collect();
        Csr {
            ptr,
            col,
            val,
            inner,
            upper,
            // Set by `invert` once the rows are cut into blocks.
            inv: Vec::new(),
            shifted_rows: Vec::new(),
            shifted_inv: Vec::new(),
            systems: 1,
            blocks: vec![0, n],
            edges: Vec::new(),
            edge_blocks: vec![0, 0],
            edge_ptr: vec![0],
            edge_col: Vec::new(),
            edge_val: Vec::new(),
            edge_l1: Vec::new(),
        }
    }

    /// Cuts the rows into the smoother's blocks and orders each row: the
    /// diagonal, the couplings to other blocks, those to earlier rows of the
    /// block, those to later ones (each group in column order). Only the
    /// sweeps and products read the rows afterwards, so the hierarchy (whose
    /// tie-breaks follow the entry order) is built on the column order.
    fn cut_into_blocks(&mut self, bounds: Vec<usize>) {
        let mut edge_blocks = vec![0];
        if bounds.len() > 2 {
            let mut row: Vec<(u32, Real)> = Vec::new();
            for w in bounds.windows(2) {
                let (lo, hi) = (w[0] as u32, w[1] as u32);
                for i in w[0]..w[1] {
                    let entries = self.row(i);
                    let all = entries.clone().map(|k| (self.col[k], self.val[k]));
                    row.clear();
                    row.extend(all.clone().filter(|e| e.0 < lo || e.0 >= hi));
                    let outside = row.len();
                    row.extend(all.clone().filter(|e| e.0 >= lo && (e.0 as usize) < i));
                    let below = row.len() - outside;
                    row.extend(all.filter(|e| (e.0 as usize) > i && e.0 < hi));
                    for (k, &(c, v)) in entries.clone().zip(&row) {
                        self.col[k] = c;
                        self.val[k] = v;
                    }
                    self.inner[i] = (entries.start + outside) as u32;
                    self.upper[i] = self.inner[i] + below as u32;
                    if outside > 0 {
                        self.edges.push(i as u32);
                        // The l1 hybrid sweep (Baker, Falgout, Kolev & Yang
                        // 2011): the couplings to other blocks, which the
                        // sweep takes from old values, are added to the
                        // diagonal. Without it a strong throat cut by a block
                        // boundary went undamped: 166 steps against 50.
                        let l1: Real = row[..outside].iter().map(|e| e.1.abs()).sum();
                        self.edge_l1.push(l1);
                        self.edge_col.extend(row[..outside].iter().map(|e| e.0));
                        self.edge_val.extend(row[..outside].iter().map(|e| e.1));
                        self.edge_ptr.push(self.edge_col.len());
                    }
                }
                edge_blocks.push(self.edges.len());
            }
        } else {
            edge_blocks.push(0);
        }
        self.blocks = bounds;
        self.edge_blocks = edge_blocks;
    }

    /// The inverse diagonals the sweeps use, once the rows are cut into
    /// blocks: `1 / (a_ii + l1_i + shift_im)` for each of `systems` systems
    /// (`shift` row by row, `systems` values a row; empty: no shift).
    fn invert(&mut self, shift: &[Real], systems: usize) {
        let n = self.n();
        let mut inv = vec![0.0; n];
        let (mut rows, mut shifted) = (Vec::new(), Vec::new());
        let mut e = 0;
        for i in 0..n {
            let mut d = self.diag(i);
            if e < self.edges.len() && self.edges[e] as usize == i {
                d += self.edge_l1[e];
                e += 1;
            }
            inv[i] = 1.0 / d;
            let s = shift.get(i * systems..(i + 1) * systems).unwrap_or(&[]);
            if s.iter().any(|&v| v != 0.0) {
                rows.push(i as u32);
                shifted.extend(s.iter().map(|&v| 1.0 / (d + v)));
            }
        }
        self.inv = inv;
        self.shifted_rows = rows;
        self.shifted_inv = shifted;
        self.systems = systems;
    }

    /// The matrix with diagonal `diag` and symmetric off-diagonal entries
    /// (`(i, j, a_ij)`, `i != j`, repeated pairs summed).
    #[cfg(test)]
    pub fn from_parts(diag: &[Real], off: &[(u32, u32, Real)]) -> Csr {
        let identity: Vec<u32> = (0..diag.len() as u32).collect();
        Csr::renumbered(diag, off.to_vec(), &identity).expect("a small test matrix")
    }

    /// The matrix with diagonal `diag` and symmetric off-diagonal entries
    /// (`(i, j, a_ij)`, `i != j`, repeated pairs summed), node `i`
    /// renumbered `new_of[i]`. The entries are renumbered where they lie
    /// (a copy at 6·10^6 pores is 0.2 GB); `None` when they would not fit
    /// 32-bit offsets (4·10^9, some 50 GB of matrix).
    ///
    /// Counting and placing the entries scatter them over the rows: each
    /// thread takes a range of rows and reads every entry, keeping those of
    /// its rows, in the entries' order, so every row receives its entries in
    /// the order one thread would give them (the same bits), and the random
    /// writes are shared out (serial, the two passes took 0.8 s at 10^6
    /// spheres).
    pub fn renumbered(
        diag: &[Real],
        mut off: Vec<(u32, u32, Real)>,
        new_of: &[u32],
    ) -> Option<Csr> {
        let n = diag.len();
        if n + 2 * off.len() >= u32::MAX as usize {
            return None;
        }
        off.par_chunks_mut(CHUNK).for_each(|off| {
            for e in off {
                (e.0, e.1) = (new_of[e.0 as usize], new_of[e.1 as usize]);
            }
        });
        let per = n.div_ceil(rayon::current_num_threads()).max(CHUNK);
        // Row i's count at `count[i + 1]`, with its diagonal.
        let mut count = vec![0usize; n + 1];
        count[1..]
            .par_chunks_mut(per)
            .enumerate()
            .for_each(|(k, count)| {
                count.fill(1);
                let (lo, len) = (k * per, count.len());
                for &(i, j, _) in &off {
                    for r in [i as usize, j as usize] {
                        if r.wrapping_sub(lo) < len {
                            count[r - lo] += 1;
                        }
                    }
                }
            });
        for k in 0..n {
            count[k + 1] += count[k];
        }
        let total = count[n];
        let mut fill = count;
        fill.truncate(n);
        let mut col = vec![0u32; total];
        let mut val = vec![0.0; total];
        {
            // Each range of rows with its part of `col` and `val`.
            let starts: Vec<usize> = (0..n).step_by(per).map(|lo| fill[lo]).collect();
            let mut pieces = Vec::new();
            let (mut col_rest, mut val_rest) = (&mut col[..], &mut val[..]);
            for (k, fill) in fill.chunks_mut(per).enumerate() {
                let end = starts.get(k + 1).copied().unwrap_or(total);
                let size = end - starts[k];
                let (c, cr) = std::mem::take(&mut col_rest).split_at_mut(size);
                let (v, vr) = std::mem::take(&mut val_rest).split_at_mut(size);
                (col_rest, val_rest) = (cr, vr);
                pieces.push((k * per, starts[k], fill, c, v));
            }
            let off = &off;
            pieces
                .into_par_iter()
                .for_each(|(lo, base, fill, col, val)| {
                    let len = fill.len();
                    let mut place = |r: usize, c: u32, a: Real| {
                        if r.wrapping_sub(lo) < len {
                            let f = &mut fill[r - lo];
                            col[*f - base] = c;
                            val[*f - base] = a;
                            *f += 1;
                        }
                    };
                    for (old, &d) in diag.iter().enumerate() {
                        let i = new_of[old];
                        place(i as usize, i, d);
                    }
                    for &(i, j, a) in off {
                        place(i as usize, j, a);
                        place(j as usize, i, a);
                    }
                });
        }
        drop(off);
        // `fill[i]` now ends row i. Each row is summed and sorted at the
        // front of its own entries, rows side by side on the threads, then
        // moved up to close the gaps: no second copy of the entries (1.1 s
        // on one thread at 10^6 spheres).
        let chunk = n.div_ceil(4 * rayon::current_num_threads()).max(4096);
        let mut len = vec![0u32; n];
        {
            let mut pieces = Vec::new();
            let (mut col_rest, mut val_rest) = (&mut col[..], &mut val[..]);
            let mut taken = 0;
            for lo in (0..n).step_by(chunk) {
                let hi = (lo + chunk).min(n);
                let end = fill[hi - 1] - taken;
                let (c, cr) = col_rest.split_at_mut(end);
                let (v, vr) = val_rest.split_at_mut(end);
                (col_rest, val_rest) = (cr, vr);
                taken += end;
                pieces.push((lo, c, v));
            }
            pieces
                .into_par_iter()
                .zip(len.par_chunks_mut(chunk))
                .for_each(|((lo, col, val), len)| {
                    let base = if lo == 0 { 0 } else { fill[lo - 1] };
                    let mut row: Vec<(u32, Real)> = Vec::new();
                    let mut start = 0;
                    for (l, i) in (lo..lo + len.len()).enumerate() {
                        let end = fill[i] - base;
                        row.clear();
                        let mut d = 0.0;
                        for k in start..end {
                            if col[k] as usize == i {
                                d += val[k];
                            } else {
                                row.push((col[k], val[k]));
                            }
                        }
                        row.sort_by_key(|e| e.0);
                        let mut write = start;
                        col[write] = i as u32;
                        val[write] = d;
                        write += 1;
                        let first = write;
                        for &(c, v) in &row {
                            if write > first && col[write - 1] == c {
                                val[write - 1] += v;
                            } else {
                                col[write] = c;
                                val[write] = v;
                                write += 1;
                            }
                        }
                        len[l] = (write - start) as u32;
                        start = end;
                    }
                });
        }
        let mut write = 0;
        let mut out_ptr = Vec::with_capacity(n + 1);
        out_ptr.push(0);
        for i in 0..n {
            let start = if i == 0 { 0 } else { fill[i - 1] };
            let l = len[i] as usize;
            col.copy_within(start..start + l, write);
            val.copy_within(start..start + l, write);
            write += l;
            out_ptr.push(write);
        }
        col.truncate(write);
        val.truncate(write);
        col.shrink_to_fit();
        val.shrink_to_fit();
        Some(Csr::new(out_ptr, col, val))
    }

    fn diag(&self, i: usize) -> Real {
        self.val[self.ptr[i] as usize]
    }

    /// The matrix with its values in single precision, for a level only
    /// the cycle reads.
    fn single(self) -> Csr<f32> {
        let single = |v: Vec<Real>| v.into_iter().map(f32::of).collect();
        Csr {
            ptr: self.ptr,
            col: self.col,
            val: single(self.val),
            inner: self.inner,
            upper: self.upper,
            inv: single(self.inv),
            shifted_rows: self.shifted_rows,
            shifted_inv: single(self.shifted_inv),
            systems: self.systems,
            blocks: self.blocks,
            edges: self.edges,
            edge_blocks: self.edge_blocks,
            edge_ptr: self.edge_ptr,
            edge_col: self.edge_col,
            edge_val: single(self.edge_val),
            edge_l1: single(self.edge_l1),
        }
    }

    /// `y = A x`, and `x · y` summed chunk by chunk and the chunks in order:
    /// the conjugate gradients' `p · A p` taken while both are at hand, which
    /// saves a pass over two vectors of the whole network per step.
    fn apply<const K: usize>(&self, x: &[[Real; K]], y: &mut [[Real; K]]) -> [Real; K] {
        let partial: Vec<[Real; K]> = y
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, y)| {
                let mut d = [0.0; K];
                for (l, yi) in y.iter_mut().enumerate() {
                    let i = c * CHUNK + l;
                    let mut s = [0.0; K];
                    for k in self.entries(i) {
                        let (v, xj) = (self.val[k], &x[self.col[k] as usize]);
                        for m in 0..K {
                            s[m] += v * xj[m];
                        }
                    }
                    *yi = s;
                    for m in 0..K {
                        d[m] += x[i][m] * s[m];
                    }
                }
                d
            })
            .collect();
        super::blocks::total(partial)
    }
}

/// The prolongator of plain aggregation, `P₀`: each fine node to its
/// aggregate with weight 1, so the aggregate's index is all it holds (4 bytes
/// a row against 20 for a general sparse row, read at every cycle's
/// restriction and correction); a node outside every aggregate
/// ([`OUTSIDE`]) has no entry.
#[derive(Clone, Debug, Default)]
struct Prolongator {
    agg: Vec<u32>,
    coarse: usize,
}

impl Prolongator {
    /// `fine += P coarse`.
    fn add_to<X: Lane, const K: usize>(&self, coarse: &[[X; K]], fine: &mut [[X; K]]) {
        fine.par_chunks_mut(CHUNK)
            .zip(self.agg.par_chunks(CHUNK))
            .for_each(|(fine, agg)| {
                for (f, &c) in fine.iter_mut().zip(agg) {
                    if c != OUTSIDE {
                        let cj = &coarse[c as usize];
                        for m in 0..K {
                            f[m] += cj[m];
                        }
                    }
                }
            });
    }

    /// `Pᵀ fine`. Each thread takes a range of aggregates and scans all the
    /// fine rows for their members: every aggregate sums its rows in
    /// ascending order, as one thread would, and no list of members is kept
    /// (it would be 0.04 GB at 10^6 spheres).
    fn restrict<X: Lane, const K: usize>(&self, fine: &[[X; K]], c: &mut [[X; K]]) {
        let per = self
            .coarse
            .div_ceil(rayon::current_num_threads())
            .max(CHUNK);
        c.par_chunks_mut(per).enumerate().for_each(|(k, c)| {
            c.fill([X::default(); K]);
            let lo = (k * per) as u32;
            let n = c.len() as u32;
            for (f, &a) in fine.iter().zip(&self.agg) {
                // `OUTSIDE` wraps far past every range.
                let at = a.wrapping_sub(lo);
                if at < n {
                    let ci = &mut c[at as usize];
                    for m in 0..K {
                        ci[m] += f[m];
                    }
                }
            }
        });
    }

    /// `Pᵀ s` for values `systems` a row (empty stays empty).
    fn restrict_rows(&self, s: &[Real], systems: usize) -> Vec<Real> {
        if s.is_empty() {
            return Vec::new();
        }
        let mut c = vec![0.0; self.coarse * systems];
        for (f, &a) in s.chunks(systems).zip(&self.agg) {
            if a != OUTSIDE {
                for (c, f) in c[a as usize * systems..][..systems].iter_mut().zip(f) {
                    *c += f;
                }
            }
        }
        c
    }

    /// The fine nodes of each aggregate, ascending: aggregate `c`'s are
    /// `rows[starts[c]..starts[c + 1]]` (a counting sort, `Pᵀ` by rows).
    fn transpose(&self) -> (Vec<usize>, Vec<u32>) {
        let mut starts = vec![0usize; self.coarse + 1];
        for &c in self.agg.iter().filter(|&&c| c != OUTSIDE) {
            starts[c as usize + 1] += 1;
        }
        for c in 0..self.coarse {
            starts[c + 1] += starts[c];
        }
        let mut fill = starts.clone();
        let mut rows = vec![0u32; starts[self.coarse]];
        for (i, &c) in self.agg.iter().enumerate() {
            if c != OUTSIDE {
                rows[fill[c as usize]] = i as u32;
                fill[c as usize] += 1;
            }
        }
        (starts, rows)
    }
}

/// A solve's buffers at one level: a cycle allocates nothing (fresh pages
/// the size of the finest level cost a tenth of a solve in page faults).
/// Single precision: see [`Lane`].
struct Work<const K: usize> {
    residual: Vec<[f32; K]>,
    coarse_rhs: Vec<[f32; K]>,
    coarse_x: Vec<[f32; K]>,
    /// Per edge row, its couplings to other blocks (see [`Csr::edges`]).
    edge: Vec<[f32; K]>,
}

/// The buffers of one solve's cycles: the finest level's correction, and
/// each level's [`Work`].
struct Cycles<const K: usize> {
    x: Vec<[f32; K]>,
    levels: Vec<Work<K>>,
}

/// One level: its matrix and the prolongator from the next coarser one.
struct Level<V = Real> {
    a: Csr<V>,
    p: Prolongator,
}

/// The multigrid hierarchy and the coarsest matrix's dense Cholesky factor,
/// one per system.
///
/// Systems that share their couplings and differ only in the diagonal
/// (`A + S_m`, `S_m` diagonal: the flow's axes, whose boundaries fix
/// different nodes) share one hierarchy: a plain aggregate's Galerkin product
/// of a diagonal is diagonal, `Pᵀ (A + S) P = Pᵀ A P + diag(Pᵀ s)`, so each
/// level holds one matrix and each system's summed shift, and the sweeps and
/// the coarsest solve take each system's own diagonal.
pub struct Multigrid {
    /// The finest level, in double precision (conjugate gradients multiply
    /// by its matrix); none when the matrix is small enough to factor.
    finest: Option<Level>,
    /// The levels below it, in single precision.
    levels: Vec<Level<f32>>,
    coarsest: Csr,
    factor: Vec<Vec<Real>>,
    /// How many systems (1: one matrix, however many right-hand sides).
    systems: usize,
    /// The finest level's rows with a shift, and their shifts (`systems` a
    /// row), for the products with the finest matrix.
    shift_rows: Vec<u32>,
    shift_vals: Vec<Real>,
}

/// Below this many unknowns a level is factored densely.
const COARSEST: usize = 600;
/// Strength of coupling: `|a_ij| ≥ θ √(a_ii a_jj)`. Measured on the flow
/// systems of a 10^5-sphere bed (steps to 1e-12 on z): θ = 0.08 (the usual
/// 3D value) 75, 0.12 64, 0.15 59, 0.2 64, 0.25 65, 0.35 78, 0.5 137.
const THETA: Real = 0.15;

impl Multigrid {
    /// The hierarchy of `a`; `None` when a coarse operator is not positive
    /// definite (the matrix is not).
    #[cfg(test)]
    pub fn new(a: Csr) -> Option<Multigrid> {
        Multigrid::cut(a, Vec::new(), blocks::bounds)
    }

    /// One hierarchy for the systems `A + diag(shifts[m])`, one per shift
    /// (each as long as `A`); a solve then takes one right-hand side per
    /// system, in the same order. `None` as for [`Multigrid::new`], or when
    /// a system is not positive definite.
    pub fn shifted(a: Csr, shifts: Vec<Vec<Real>>) -> Option<Multigrid> {
        Multigrid::cut(a, shifts, blocks::bounds)
    }

    /// The hierarchy of `a` with each level's rows cut into blocks at
    /// `bounds(rows)`.
    fn cut(a: Csr, shifts: Vec<Vec<Real>>, bounds: fn(usize) -> Vec<usize>) -> Option<Multigrid> {
        let systems = shifts.len().max(1);
        // Row by row, `systems` values a row.
        let mut shift: Vec<Real> = if shifts.is_empty() {
            Vec::new()
        } else {
            (0..a.n())
                .flat_map(|i| shifts.iter().map(move |s| s[i]))
                .collect()
        };
        drop(shifts);
        let (mut shift_rows, mut shift_vals) = (Vec::new(), Vec::new());
        for (i, s) in shift.chunks(systems).enumerate() {
            if s.iter().any(|&v| v != 0.0) {
                shift_rows.push(i as u32);
                shift_vals.extend_from_slice(s);
            }
        }
        let mut finest = None;
        let mut levels = Vec::new();
        let mut a = a;
        let mut theta = THETA;
        while a.n() > COARSEST && levels.len() < 40 {
            let (agg, count) = aggregate(&a, theta);
            if count * 10 > a.n() * 9 {
                // Coarsening stalled: weaker couplings count as strong, down
                // to every coupling.
                if theta == 0.0 {
                    break;
                }
                theta = if theta > 1e-6 { theta / 8.0 } else { 0.0 };
                continue;
            }
            let p = Prolongator { agg, coarse: count };
            let coarse = galerkin(&a, &p);
            let coarse_shift = p.restrict_rows(&shift, systems);
            // A level is cut once its coarse operator is built: the
            // aggregation's tie-breaks follow the column order.
            a.cut_into_blocks(bounds(a.n()));
            a.invert(&shift, systems);
            if finest.is_none() {
                finest = Some(Level { a, p });
            } else {
                levels.push(Level { a: a.single(), p });
            }
            a = coarse;
            shift = coarse_shift;
        }
        if a.n() > 8 * COARSEST {
            // Coarsening stalled far above a size worth factoring densely.
            return None;
        }
        let factor = (0..systems)
            .map(|m| dense_cholesky(&a, &shift, m, systems))
            .collect::<Option<Vec<_>>>()?;
        Some(Multigrid {
            finest,
            levels,
            coarsest: a,
            factor,
            systems,
            shift_rows,
            shift_vals,
        })
    }

    /// `y += S x` on the finest level, each right-hand side with its
    /// system's shift.
    /// `y += S x`; returns `x · S x`.
    fn add_shift<const K: usize>(&self, x: &[[Real; K]], y: &mut [[Real; K]]) -> [Real; K] {
        let s = self.systems;
        let mut d = [0.0; K];
        for (k, &i) in self.shift_rows.iter().enumerate() {
            let (xi, yi) = (&x[i as usize], &mut y[i as usize]);
            for m in 0..K {
                let sx = self.shift_vals[k * s + if s == 1 { 0 } else { m }] * xi[m];
                yi[m] += sx;
                d[m] += xi[m] * sx;
            }
        }
        d
    }

    /// `y = (A + S) x` on the finest level; returns `x · y`.
    fn apply<const K: usize>(&self, x: &[[Real; K]], y: &mut [[Real; K]]) -> [Real; K] {
        let a = self.finest().apply(x, y);
        let s = self.add_shift(x, y);
        std::array::from_fn(|m| a[m] + s[m])
    }

    fn finest(&self) -> &Csr {
        match &self.finest {
            Some(l) => &l.a,
            None => &self.coarsest,
        }
    }

    /// Levels, coarsest included.
    #[cfg(test)]
    pub fn depth(&self) -> usize {
        self.levels.len() + usize::from(self.finest.is_some()) + 1
    }

    /// One set of buffers per level for one solve.
    fn work<const K: usize>(&self) -> Cycles<K> {
        fn work<V: Lane, const K: usize>(l: &Level<V>) -> Work<K> {
            Work {
                residual: vec![[0.0; K]; l.a.n()],
                coarse_rhs: vec![[0.0; K]; l.p.coarse],
                coarse_x: vec![[0.0; K]; l.p.coarse],
                edge: vec![[0.0; K]; l.a.edges.len()],
            }
        }
        Cycles {
            x: vec![[0.0; K]; self.finest.as_ref().map_or(0, |l| l.a.n())],
            levels: self
                .finest
                .iter()
                .map(work)
                .chain(self.levels.iter().map(work))
                .collect(),
        }
    }

    /// `z = M⁻¹ r`, one V-cycle from a zero guess: an approximation of
    /// `A⁻¹ r`. The cycle runs in single precision (see [`Lane`]); `r` and
    /// `z` are the conjugate gradients' own. Returns `r · z` and `a · z`
    /// (`a` if given, else 0), taken as the last sweep writes `z`: three
    /// vectors fewer to read a step.
    fn precondition<const K: usize>(
        &self,
        r: &[[Real; K]],
        z: &mut [[Real; K]],
        a: Option<&[[Real; K]]>,
        work: &mut Cycles<K>,
    ) -> ([Real; K], [Real; K]) {
        if self.finest.is_none() {
            self.coarsest_solve(r, z);
            let az = a.map_or([0.0; K], |a| dot(a, z));
            return (dot(r, z), az);
        }
        self.cycle(0, r, &mut work.x, Some((z, a)), &mut work.levels)
    }

    /// The coarsest level's dense solve, in double precision.
    fn coarsest_solve<B: Lane, X: Lane, const K: usize>(&self, r: &[[B; K]], x: &mut [[X; K]]) {
        let n = self.coarsest.n();
        let mut y = vec![0.0; n];
        for m in 0..K {
            for (y, r) in y.iter_mut().zip(r) {
                *y = r[m].real();
            }
            let factor = &self.factor[if self.systems == 1 { 0 } else { m }];
            dense_solve(factor, n, &mut y);
            for (x, y) in x.iter_mut().zip(&y) {
                x[m] = X::of(*y);
            }
        }
    }

    /// One V-cycle on `r` from a zero guess into `x` (and, converted, into
    /// `out`): an approximation of `A⁻¹ r`. With `out`, the dots of
    /// [`backward_gauss_seidel`].
    fn cycle<B: Lane, const K: usize>(
        &self,
        level: usize,
        r: &[[B; K]],
        x: &mut [[f32; K]],
        out: Option<Out<K>>,
        work: &mut [Work<K>],
    ) -> ([Real; K], [Real; K]) {
        match (&self.finest, level) {
            (Some(l), 0) => self.cycle_at(l, level, r, x, out, work),
            (finest, _) => match self.levels.get(level - usize::from(finest.is_some())) {
                Some(l) => self.cycle_at(l, level, r, x, out, work),
                None => {
                    // Only a level above the coarsest is given an `out`.
                    self.coarsest_solve(r, x);
                    ([0.0; K], [0.0; K])
                }
            },
        }
    }

    /// [`Multigrid::cycle`] at level `l`, above the coarsest.
    fn cycle_at<V: Lane, B: Lane, const K: usize>(
        &self,
        l: &Level<V>,
        level: usize,
        r: &[[B; K]],
        x: &mut [[f32; K]],
        out: Option<Out<K>>,
        work: &mut [Work<K>],
    ) -> ([Real; K], [Real; K]) {
        let Level { a, p } = l;
        let (here, below) = work.split_first_mut().expect("a work set per level");
        smooth_from_zero(a, r, x, &mut here.residual);
        p.restrict(&here.residual, &mut here.coarse_rhs);
        self.cycle(level + 1, &here.coarse_rhs, &mut here.coarse_x, None, below);
        p.add_to(&here.coarse_x, x);
        backward_gauss_seidel(a, r, x, &mut here.edge, out)
    }

    /// Solves `A x = b` to a relative residual of `tol` by preconditioned
    /// conjugate gradients; `None` if it does not get there.
    #[cfg(test)]
    pub fn solve(&self, b: &[Real], tol: Real, max_steps: usize) -> Option<(Vec<Real>, usize)> {
        let ([x], steps) = self.solve_many([b], tol, max_steps)?;
        Some((x, steps))
    }

    /// Solves `A x = b` for `K` right-hand sides at once, each to a relative
    /// residual of `tol`; the steps taken by the slowest. One sweep serves
    /// them all: the matrix is read once per step, not `K` times, and the
    /// sweep's chains of rows run side by side.
    #[cfg(test)]
    pub fn solve_many<const K: usize>(
        &self,
        b: [&[Real]; K],
        tol: Real,
        max_steps: usize,
    ) -> Option<([Vec<Real>; K], usize)> {
        self.solve_deflated(b.map(<[Real]>::to_vec), None, tol, max_steps)
    }

    /// [`Multigrid::solve_many`] with each right-hand side's residual kept
    /// orthogonal to its own vector `w[m]` from the first step to the last
    /// (deflated conjugate gradients: Nicolaides 1987; Saad, Yeung, Erhel &
    /// Guyomarc'h 2000): the start is the best multiple of `w[m]`, and every
    /// search direction is made `A`-orthogonal to it. A zero `w[m]` deflates
    /// nothing.
    pub fn solve_deflated<const K: usize>(
        &self,
        b: [Vec<Real>; K],
        w: Option<[Vec<Real>; K]>,
        tol: Real,
        max_steps: usize,
    ) -> Option<([Vec<Real>; K], usize)> {
        assert!(
            self.systems == 1 || self.systems == K,
            "one right-hand side per system"
        );
        let n = self.finest().n();
        let interleave = |b: [Vec<Real>; K]| -> Vec<[Real; K]> {
            (0..n).map(|i| std::array::from_fn(|m| b[m][i])).collect()
        };
        let b = interleave(b);
        let norm_b = dot(&b, &b).map(Real::sqrt);
        // A right-hand side that is met stays where it is (no step moves it).
        let mut done = norm_b.map(|v| v == 0.0);
        let mut x = vec![[0.0; K]; n];
        let unpack = |x: &[[Real; K]]| -> [Vec<Real>; K] {
            std::array::from_fn(|m| x.iter().map(|v| v[m]).collect())
        };
        if done.iter().all(|&d| d) {
            return Some((unpack(&x), 0));
        }
        let mut r = b;
        // (w, A w, 1 / wᵀ A w), the last 0 where w is 0.
        // Taken by value: at 10^6 spheres each copy is 48 MB a side.
        let deflation = w.map(|w| {
            let w = interleave(w);
            let mut aw = vec![[0.0; K]; n];
            let inv = self.apply(&w, &mut aw).map(|c| {
                if c > 0.0 && c.is_finite() {
                    1.0 / c
                } else {
                    0.0
                }
            });
            (w, aw, inv)
        });
        if let Some((w, aw, inv)) = &deflation {
            let wr = dot(w, &r);
            let mu: [Real; K] = std::array::from_fn(|m| wr[m] * inv[m]);
            blocks::step(&mut x, &mut r, w, aw, mu);
        }
        let mut work = self.work::<K>();
        let mut z = vec![[0.0; K]; n];
        let aw = deflation.as_ref().map(|d| &d.1[..]);
        let (mut rz, awz) = self.precondition(&r, &mut z, aw, &mut work);
        let mut p = z.clone();
        if let Some((w, _, inv)) = &deflation {
            blocks::deflate(&mut p, w, std::array::from_fn(|m| awz[m] * inv[m]));
        }
        // `A p` and the preconditioned residual `z` share a buffer: `A p` is
        // spent once `x` and `r` have stepped, before the cycle writes `z`
        // (a vector fewer: 0.1 GB at 10^6 spheres).
        let mut ap = z;
        let mut finished = None;
        for step in 1..=max_steps {
            let pap = self.apply(&p, &mut ap);
            let mut alpha = [0.0; K];
            for m in 0..K {
                if done[m] {
                    continue;
                }
                if !(pap[m] > 0.0 && rz[m].is_finite()) {
                    return None;
                }
                alpha[m] = rz[m] / pap[m];
            }
            let rr = blocks::step(&mut x, &mut r, &p, &ap, alpha);
            for m in 0..K {
                done[m] |= rr[m].sqrt() <= tol * norm_b[m];
            }
            if done.iter().all(|&d| d) {
                finished = Some(step);
                break;
            }
            let z = &mut ap;
            let (rz_new, awz) = self.precondition(&r, z, aw, &mut work);
            let mu = match &deflation {
                Some((_, _, inv)) => std::array::from_fn(|m| awz[m] * inv[m]),
                None => [0.0; K],
            };
            let beta = std::array::from_fn(|m| if done[m] { 0.0 } else { rz_new[m] / rz[m] });
            rz = rz_new;
            match &deflation {
                Some((w, _, _)) => blocks::direction_deflated(&mut p, z, beta, w, mu),
                None => blocks::direction(&mut p, z, beta),
            }
        }
        let steps = finished?;
        // The buffers go before the answer is unpacked: at 10^6 spheres they
        // are 0.7 GB, and this was the flow's peak.
        drop((r, p, ap, work, deflation));
        Some((unpack(&x), steps))
    }
}

/// A forward Gauss–Seidel sweep on `A x = b` from `x = 0`, and the residual
/// `b − A x` after it, in one pass over the matrix. After the sweep row `i`'s
/// residual is `−Σ_{j>i} a_ij x_j` (the rest cancels): each row, once its
/// `x_i` is known, sends `−a_ij x_i` to its earlier neighbours. The separate
/// residual product cost a quarter of the solve (36.5 against 27.9 s on the
/// z system of a 10^6-sphere bed).
fn smooth_from_zero<V: Lane, B: Lane, X: Lane, const K: usize>(
    a: &Csr<V>,
    b: &[[B; K]],
    x: &mut [[X; K]],
    residual: &mut [[X; K]],
) {
    let bounds = &a.blocks;
    split(x, bounds)
        .into_par_iter()
        .zip(split(residual, bounds))
        .enumerate()
        .for_each(|(blk, (x, res))| {
            let lo = bounds[blk];
            res.fill([X::default(); K]);
            let mut shifted = a.shifted_from(lo);
            for (l, i) in (lo..lo + x.len()).enumerate() {
                let lower = a.inner[i] as usize..a.upper[i] as usize;
                let mut s: [X; K] = b[i].map(X::from_lane);
                for k in lower.clone() {
                    let (v, xj) = (X::from_lane(a.val[k]), &x[a.col[k] as usize - lo]);
                    for m in 0..K {
                        s[m] -= v * xj[m];
                    }
                }
                let inv = a.inv_up::<K>(i, &mut shifted);
                let xi: [X; K] = std::array::from_fn(|m| s[m] * X::from_lane(inv[m]));
                x[l] = xi;
                for k in lower {
                    let (v, rj) = (X::from_lane(a.val[k]), &mut res[a.col[k] as usize - lo]);
                    for m in 0..K {
                        rj[m] -= v * xi[m];
                    }
                }
            }
        });
    if !a.edges.is_empty() {
        // The couplings between blocks, once every block is swept (and the
        // l1 term, which `M x = b` left in the residual).
        let x: &[[X; K]] = x;
        split(residual, bounds)
            .into_par_iter()
            .enumerate()
            .for_each(|(blk, res)| {
                let lo = bounds[blk];
                for e in a.edge_blocks[blk]..a.edge_blocks[blk + 1] {
                    let (v, r) = (across(a, e, x), &mut res[a.edges[e] as usize - lo]);
                    for m in 0..K {
                        r[m] += v[m];
                    }
                }
            });
    }
}

/// `Σ_j (|a_ij| x_i − a_ij x_j)` over edge row `e`'s couplings to other
/// blocks.
fn across<V: Lane, X: Lane, const K: usize>(a: &Csr<V>, e: usize, x: &[[X; K]]) -> [X; K] {
    let l1 = X::from_lane(a.edge_l1[e]);
    let mut v = x[a.edges[e] as usize].map(|xi| l1 * xi);
    for k in a.edge_ptr[e]..a.edge_ptr[e + 1] {
        let (w, xj) = (X::from_lane(a.edge_val[k]), &x[a.edge_col[k] as usize]);
        for m in 0..K {
            v[m] -= w * xj[m];
        }
    }
    v
}

/// Where the finest backward sweep also writes its answer, in double
/// precision, and the vector `a` whose dot with it the sweep takes.
type Out<'a, const K: usize> = (&'a mut [[Real; K]], Option<&'a [[Real; K]]>);

/// Backward Gauss–Seidel sweep on `A x = b` (the forward one is
/// [`smooth_from_zero`]): the pair keeps the cycle symmetric. `edge` takes
/// each edge row's couplings to other blocks, from the values before the
/// sweep. The answer is also written, in double precision, to `out` if
/// given (the finest level's, for conjugate gradients: one pass fewer than
/// converting it after); then it returns `b · x` and `a · x` (0 without
/// `a`), each summed down a block and the blocks in order.
fn backward_gauss_seidel<V: Lane, B: Lane, X: Lane, const K: usize>(
    a: &Csr<V>,
    b: &[[B; K]],
    x: &mut [[X; K]],
    edge: &mut [[X; K]],
    out: Option<Out<K>>,
) -> ([Real; K], [Real; K]) {
    let bounds = &a.blocks;
    {
        let x: &[[X; K]] = x;
        edge.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, edge)| {
                for (l, v) in edge.iter_mut().enumerate() {
                    *v = across(a, c * CHUNK + l, x);
                }
            });
    }
    let edge: &[[X; K]] = edge;
    let (outs, with): (Vec<Option<&mut [[Real; K]]>>, _) = match out {
        Some((out, with)) => (split(out, bounds).into_iter().map(Some).collect(), with),
        None => ((1..bounds.len()).map(|_| None).collect(), None),
    };
    let sums: Vec<([Real; K], [Real; K])> = split(x, bounds)
        .into_par_iter()
        .zip(outs)
        .enumerate()
        .map(|(blk, (x, mut out))| {
            let lo = bounds[blk];
            let edges = &a.edges[a.edge_blocks[blk]..a.edge_blocks[blk + 1]];
            let mut next = edges.len();
            // One past the next shifted row on the way down.
            let mut shifted = a.shifted_from(lo + x.len());
            let (mut bz, mut az) = ([0.0; K], [0.0; K]);
            for i in (lo..lo + x.len()).rev() {
                let mut s: [X; K] = b[i].map(X::from_lane);
                if next > 0 && edges[next - 1] as usize == i {
                    next -= 1;
                    let e = &edge[a.edge_blocks[blk] + next];
                    for m in 0..K {
                        s[m] += e[m];
                    }
                }
                for k in a.inner[i] as usize..a.ptr[i + 1] as usize {
                    let (v, xj) = (X::from_lane(a.val[k]), &x[a.col[k] as usize - lo]);
                    for m in 0..K {
                        s[m] -= v * xj[m];
                    }
                }
                let inv = a.inv_down::<K>(i, &mut shifted);
                let xi: [X; K] = std::array::from_fn(|m| s[m] * X::from_lane(inv[m]));
                x[i - lo] = xi;
                if let Some(out) = out.as_deref_mut() {
                    let z = xi.map(X::real);
                    out[i - lo] = z;
                    for m in 0..K {
                        bz[m] += b[i][m].real() * z[m];
                    }
                    if let Some(w) = with {
                        for m in 0..K {
                            az[m] += w[i][m] * z[m];
                        }
                    }
                }
            }
            (bz, az)
        })
        .collect();
    sums.iter()
        .fold(([0.0; K], [0.0; K]), |(mut s, mut t), (u, v)| {
            for m in 0..K {
                s[m] += u[m];
                t[m] += v[m];
            }
            (s, t)
        })
}

/// Aggregates of strongly coupled nodes, in three passes: a node whose strong
/// neighbours are all free starts an aggregate with them; a free node joins
/// the first-pass aggregate it is most strongly coupled to; a node still free
/// starts an aggregate with its free strong neighbours, or else joins the
/// aggregate of its strongest neighbour, or stands alone. A node with no
/// coupling at all is left out of every aggregate (`OUTSIDE`): the smoother
/// solves its equation exactly.
///
/// The third pass matters: grouping the left-over nodes eight at a time in
/// index order, as this code did before, made coarse nodes of unrelated pores
/// and cost a third of the steps on pore networks (92 against 59 steps on
/// the z system of a 10^5-sphere bed, 100 against 52 on x).
fn aggregate(a: &Csr, theta: Real) -> (Vec<u32>, usize) {
    let n = a.n();
    const FREE: u32 = u32::MAX - 1;
    let mut agg = vec![FREE; n];
    let strong = |i: usize, k: usize| {
        let j = a.col[k] as usize;
        a.val[k] != 0.0 && a.val[k].abs() >= theta * (a.diag(i) * a.diag(j)).sqrt()
    };
    let row = |i: usize| a.row(i);
    let strongest =
        |k: &usize, l: &usize| a.val[*k].abs().total_cmp(&a.val[*l].abs()).then(l.cmp(k));
    let mut count = 0u32;
    for i in 0..n {
        if agg[i] != FREE {
            continue;
        }
        let neighbours = row(i).filter(|&k| strong(i, k));
        let mut any = false;
        let mut all_free = true;
        for k in neighbours.clone() {
            any = true;
            all_free &= agg[a.col[k] as usize] == FREE;
        }
        if any && all_free {
            agg[i] = count;
            for k in neighbours {
                agg[a.col[k] as usize] = count;
            }
            count += 1;
        }
    }
    let first = agg.clone();
    for i in 0..n {
        if agg[i] != FREE {
            continue;
        }
        if let Some(k) = row(i)
            .filter(|&k| strong(i, k) && first[a.col[k] as usize] != FREE)
            .max_by(strongest)
        {
            agg[i] = first[a.col[k] as usize];
        }
    }
    for i in 0..n {
        if agg[i] != FREE {
            continue;
        }
        let mut started = false;
        for k in row(i) {
            let j = a.col[k] as usize;
            if strong(i, k) && agg[j] == FREE {
                agg[j] = count;
                started = true;
            }
        }
        if started {
            agg[i] = count;
            count += 1;
            continue;
        }
        let joined = row(i)
            .filter(|&k| a.val[k] != 0.0 && agg[a.col[k] as usize] < FREE)
            .max_by(strongest);
        agg[i] = match joined {
            Some(k) => agg[a.col[k] as usize],
            None if row(i).all(|k| a.val[k] == 0.0) => OUTSIDE,
            None => {
                count += 1;
                count - 1
            }
        };
    }
    (agg, count as usize)
}

/// Not in any aggregate: a node with no coupling, solved by the smoother.
const OUTSIDE: u32 = u32::MAX;

/// The Galerkin product `Pᵀ A P`, coarse row by coarse row: row `r` sums
/// the rows of `A P` of its aggregate's fine rows, each worked out when it is
/// needed (a stored `A P` was 0.36 GB at 10^6 spheres). The coarse rows are
/// shared among the threads in chunks (1.6 s on one thread at 10^6 spheres);
/// a row's sums are taken in one order whatever the chunks. Each row is
/// written into room for as many entries as its fine rows hold, then the
/// rows are moved up to close the gaps: buffers of the threads' own, freed
/// after, stayed in their allocator's pools (0.09 GB more at the peak).
fn galerkin(a: &Csr, p: &Prolongator) -> Csr {
    let nc = p.coarse;
    let (t_ptr, t_row) = p.transpose();
    // Room for row r: the entries of its fine rows.
    let mut room = Vec::with_capacity(nc + 1);
    room.push(0usize);
    for r in 0..nc {
        let fine: usize = t_row[t_ptr[r]..t_ptr[r + 1]]
            .iter()
            .map(|&i| a.entries(i as usize).len())
            .sum();
        room.push(room[r] + fine.max(1));
    }
    let mut col = vec![0u32; room[nc]];
    let mut val = vec![0.0; room[nc]];
    let mut len = vec![0u32; nc];
    let per = nc.div_ceil(4 * rayon::current_num_threads()).max(1024);
    let mut pieces = Vec::new();
    {
        let (mut col_rest, mut val_rest) = (&mut col[..], &mut val[..]);
        for lo in (0..nc).step_by(per) {
            let hi = (lo + per).min(nc);
            let size = room[hi] - room[lo];
            let (c, cr) = std::mem::take(&mut col_rest).split_at_mut(size);
            let (v, vr) = std::mem::take(&mut val_rest).split_at_mut(size);
            (col_rest, val_rest) = (cr, vr);
            pieces.push((lo, c, v));
        }
    }
    pieces
        .into_par_iter()
        .zip(len.par_chunks_mut(per))
        .for_each(|((lo, col, val), len)| {
            // Row r of Pᵀ A P and row i of A P: (column, sum), in order of
            // first sight.
            let mut row: Vec<(u32, Real)> = Vec::new();
            let mut ap: Vec<(u32, Real)> = Vec::new();
            let add = |row: &mut Vec<(u32, Real)>, c: u32, v: Real| match row
                .iter_mut()
                .find(|e| e.0 == c)
            {
                Some(e) => e.1 += v,
                None => row.push((c, 0.0 + v)),
            };
            for (l, r) in (lo..lo + len.len()).enumerate() {
                row.clear();
                for &i in &t_row[t_ptr[r]..t_ptr[r + 1]] {
                    ap.clear();
                    for k in a.entries(i as usize) {
                        let c = p.agg[a.col[k] as usize];
                        if c != OUTSIDE {
                            add(&mut ap, c, a.val[k]);
                        }
                    }
                    for &(c, v) in &ap {
                        add(&mut row, c, v);
                    }
                }
                row.sort_unstable_by_key(|e| e.0);
                // The diagonal first, then the others.
                let at = room[r] - room[lo];
                let diag = row.iter().find(|e| e.0 as usize == r).map_or(0.0, |e| e.1);
                col[at] = r as u32;
                val[at] = diag;
                let mut w = at + 1;
                for &(c, v) in row.iter().filter(|e| e.0 as usize != r) {
                    col[w] = c;
                    val[w] = v;
                    w += 1;
                }
                len[l] = (w - at) as u32;
            }
        });
    let mut ptr = Vec::with_capacity(nc + 1);
    ptr.push(0usize);
    let mut write = 0;
    for r in 0..nc {
        let l = len[r] as usize;
        col.copy_within(room[r]..room[r] + l, write);
        val.copy_within(room[r]..room[r] + l, write);
        write += l;
        ptr.push(write);
    }
    col.truncate(write);
    val.truncate(write);
    col.shrink_to_fit();
    val.shrink_to_fit();
    Csr::new(ptr, col, val)
}

/// Dense Cholesky factor (row-major lower triangle) of a small matrix with
/// system `m`'s shift on its diagonal (`shift` row by row, `systems` a row,
/// or empty), `None` when it is not positive definite.
fn dense_cholesky(a: &Csr, shift: &[Real], m: usize, systems: usize) -> Option<Vec<Real>> {
    let n = a.n();
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for k in a.entries(i) {
            l[i * n + a.col[k] as usize] = a.val[k];
        }
        if !shift.is_empty() {
            l[i * n + i] += shift[i * systems + m];
        }
    }
    for j in 0..n {
        let mut d = l[j * n + j];
        for k in 0..j {
            d -= l[j * n + k] * l[j * n + k];
        }
        if !(d > 0.0) {
            return None;
        }
        let d = d.sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = l[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / d;
        }
    }
    Some(l)
}

/// Solves in place: `y` holds the right-hand side on entry.
fn dense_solve(l: &[Real], n: usize, y: &mut [Real]) {
    for i in 0..n {
        for k in 0..i {
            y[i] -= l[i * n + k] * y[k];
        }
        y[i] /= l[i * n + i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            y[i] -= l[k * n + i] * y[k];
        }
        y[i] /= l[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The 3D grid Laplacian with a ground term on one face.
    fn grid(m: usize) -> (Vec<Real>, Vec<(u32, u32, Real)>) {
        let id = |i: usize, j: usize, k: usize| (i + m * (j + m * k)) as u32;
        let mut diag = vec![0.0; m * m * m];
        let mut off = Vec::new();
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    let here = id(i, j, k);
                    for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        let (a, b, c) = (i + di, j + dj, k + dk);
                        if a < m && b < m && c < m {
                            // Conductances spread over three decades.
                            let g = 10f64.powf(((i * 7 + j * 3 + k * 5) % 4) as f64 - 1.0);
                            off.push((here, id(a, b, c), -g));
                            diag[here as usize] += g;
                            diag[id(a, b, c) as usize] += g;
                        }
                    }
                    if k == 0 {
                        diag[here as usize] += 1.0;
                    }
                }
            }
        }
        (diag, off)
    }

    /// The grid with one vertical link in five ten thousand times stronger:
    /// the strong throats of a pore network, some cut by block boundaries.
    fn rough_grid(m: usize) -> (Vec<Real>, Vec<(u32, u32, Real)>) {
        let (mut diag, mut off) = grid(m);
        for (n, e) in off.iter_mut().enumerate() {
            if e.1 - e.0 == (m * m) as u32 && n % 5 == 0 {
                let extra = -e.2 * 1e4;
                e.2 -= extra;
                diag[e.0 as usize] += extra;
                diag[e.1 as usize] += extra;
            }
        }
        (diag, off)
    }

    fn residual(diag: &[Real], off: &[(u32, u32, Real)], x: &[Real], b: &[Real]) -> Real {
        let mut ax: Vec<Real> = diag.iter().zip(x).map(|(d, x)| d * x).collect();
        for &(i, j, a) in off {
            ax[i as usize] += a * x[j as usize];
            ax[j as usize] += a * x[i as usize];
        }
        let r: Real = ax.iter().zip(b).map(|(a, b)| (a - b).powi(2)).sum();
        r.sqrt() / b.iter().map(|v| v * v).sum::<Real>().sqrt()
    }

    #[test]
    fn grid_laplacian_converges_in_few_steps() {
        let (diag, off) = grid(24);
        let mg = Multigrid::new(Csr::from_parts(&diag, &off)).unwrap();
        assert!(mg.depth() >= 2);
        let b: Vec<Real> = (0..diag.len())
            .map(|i| ((i * 37) % 11) as Real - 5.0)
            .collect();
        let (x, steps) = mg.solve(&b, 1e-10, 200).unwrap();
        assert!(residual(&diag, &off, &x, &b) < 1e-9);
        // Multigrid: a few dozen steps, where unpreconditioned CG needs hundreds.
        assert!(steps < 60, "{steps} steps");
        // Equal to the direct solve.
        let points: Vec<crate::math::Vector<3>> = (0..diag.len())
            .map(|i| crate::math::Vector([i as Real, 0.0, 0.0]))
            .collect();
        let direct =
            super::super::solve_spd(&points, &diag, &off, std::slice::from_ref(&b)).unwrap();
        let worst = x
            .iter()
            .zip(&direct[0])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, Real::max);
        let scale = direct[0].iter().map(|v| v.abs()).fold(0.0, Real::max);
        assert!(worst < 1e-7 * scale, "{worst} against {scale}");
    }

    /// Blocks of 300 rows: many couplings cross, among them strong ones.
    fn small_blocks(n: usize) -> Vec<usize> {
        let blocks = n.div_ceil(300).max(1);
        (0..=blocks).map(|b| b * n / blocks).collect()
    }

    #[test]
    fn the_hybrid_sweep_in_small_blocks_solves_and_converges() {
        let (diag, off) = rough_grid(20);
        let b: Vec<Real> = (0..diag.len())
            .map(|i| ((i * 13) % 7) as Real - 3.0)
            .collect();
        let (whole, whole_steps) = Multigrid::new(Csr::from_parts(&diag, &off))
            .unwrap()
            .solve(&b, 1e-10, 200)
            .unwrap();
        let mg = Multigrid::cut(Csr::from_parts(&diag, &off), Vec::new(), small_blocks).unwrap();
        assert!(mg.finest.as_ref().expect("a finest level").a.blocks.len() > 20);
        assert!(!mg
            .finest
            .as_ref()
            .expect("a finest level")
            .a
            .edges
            .is_empty());
        let (x, steps) = mg.solve(&b, 1e-10, 200).unwrap();
        assert!(residual(&diag, &off, &x, &b) < 1e-9);
        // The l1 term keeps the sweep a smoother across the cuts: 28 steps
        // cut or whole; without it this system did not converge in 200.
        assert!(
            steps <= whole_steps + whole_steps / 2,
            "{steps} against {whole_steps}"
        );
        let scale = whole.iter().map(|v| v.abs()).fold(0.0, Real::max);
        for (a, b) in x.iter().zip(&whole) {
            assert!((a - b).abs() < 1e-7 * scale);
        }
    }

    /// Three systems with the grid's couplings and different diagonals (the
    /// bottom layer tied down, one node grounded with a right-hand side that
    /// sums to zero, the top layer tied down harder), through one hierarchy:
    /// each residual is checked against its own matrix, and each answer
    /// against a hierarchy built for that matrix alone.
    #[test]
    fn systems_differing_in_their_diagonals_share_one_hierarchy() {
        let m = 14;
        let (_, off) = grid(m);
        let n = m * m * m;
        let mut lap = vec![0.0; n];
        for &(i, j, a) in &off {
            lap[i as usize] -= a;
            lap[j as usize] -= a;
        }
        let layer = n / m;
        let mut shifts = vec![vec![0.0; n]; 3];
        shifts[0][..layer].fill(1.0);
        shifts[1][7] = lap[7];
        shifts[2][n - layer..].fill(5.0);
        let mut b: Vec<Vec<Real>> = (0..3)
            .map(|s| (0..n).map(|i| ((i * (5 + s)) % 13) as Real - 6.0).collect())
            .collect();
        let mean = b[1].iter().sum::<Real>() / n as Real;
        b[1].iter_mut().for_each(|v| *v -= mean);
        let mg = Multigrid::cut(Csr::from_parts(&lap, &off), shifts.clone(), small_blocks).unwrap();
        assert!(mg.depth() >= 2);
        let rhs: [Vec<Real>; 3] = std::array::from_fn(|k| b[k].clone());
        let (x, _) = mg.solve_deflated(rhs, None, 1e-11, 400).unwrap();
        for k in 0..3 {
            let diag: Vec<Real> = lap.iter().zip(&shifts[k]).map(|(d, s)| d + s).collect();
            assert!(residual(&diag, &off, &x[k], &b[k]) < 1e-10, "system {k}");
            let alone = Multigrid::cut(Csr::from_parts(&diag, &off), Vec::new(), small_blocks)
                .unwrap()
                .solve(&b[k], 1e-11, 400)
                .unwrap()
                .0;
            let scale = alone.iter().fold(0.0, |a: Real, v| a.max(v.abs()));
            for (u, v) in x[k].iter().zip(&alone) {
                assert!((u - v).abs() < 1e-7 * scale, "system {k}: {u} {v}");
            }
        }
        // The grounded node holds p = 0, as if removed.
        assert!(x[1][7].abs() < 1e-7 * x[1].iter().fold(0.0, |a: Real, v| a.max(v.abs())));
    }

    /// The sweeps find each row's inverse diagonal, shifted or not, walking
    /// up and walking down every block: against `1 / (a_ii + l1_i + s_im)`
    /// worked out from the finest level's entries and the shifts given.
    #[test]
    fn the_sweeps_read_each_rows_shifted_inverse() {
        let (diag, off) = rough_grid(16);
        let n = diag.len();
        let mut shifts = vec![vec![0.0; n]; 3];
        for i in (0..n).step_by(7) {
            shifts[i % 3][i] = 0.5 + (i % 5) as Real;
        }
        shifts[1][n - 1] = 2.0;
        shifts[2][0] = 1.0;
        let mg =
            Multigrid::cut(Csr::from_parts(&diag, &off), shifts.clone(), small_blocks).unwrap();
        let a = mg.finest();
        assert!(a.blocks.len() > 2 && !a.edges.is_empty());
        let want = |i: usize| -> [Real; 3] {
            let l1: Real = a
                .edges
                .iter()
                .position(|&e| e as usize == i)
                .map_or(0.0, |e| a.edge_l1[e]);
            std::array::from_fn(|m| 1.0 / (a.diag(i) + l1 + shifts[m][i]))
        };
        for w in a.blocks.windows(2) {
            let mut up = a.shifted_from(w[0]);
            for i in w[0]..w[1] {
                assert_eq!(a.inv_up::<3>(i, &mut up), want(i), "row {i} on the way up");
            }
            let mut down = a.shifted_from(w[1]);
            for i in (w[0]..w[1]).rev() {
                assert_eq!(
                    a.inv_down::<3>(i, &mut down),
                    want(i),
                    "row {i} on the way down"
                );
            }
        }
        let listed = (0..n)
            .filter(|&i| shifts.iter().any(|s| s[i] != 0.0))
            .count();
        assert_eq!(a.shifted_rows.len(), listed);
        assert_eq!(a.shifted_inv.len(), 3 * listed);
    }

    #[test]
    fn two_right_hand_sides_at_once_are_each_solved_as_alone() {
        let (diag, off) = rough_grid(20);
        let mg = Multigrid::cut(Csr::from_parts(&diag, &off), Vec::new(), small_blocks).unwrap();
        let b1: Vec<Real> = (0..diag.len()).map(|i| (i as Real).sin()).collect();
        // A second side that needs more steps, and one already met.
        let b2: Vec<Real> = (0..diag.len()).map(|i| ((i * i) % 17) as Real).collect();
        let zero = vec![0.0; diag.len()];
        let (one, s1) = mg.solve(&b1, 1e-10, 200).unwrap();
        let (two, s2) = mg.solve(&b2, 1e-10, 200).unwrap();
        assert_ne!(s1, s2);
        let ([a, b], steps) = mg.solve_many([&b1, &b2], 1e-10, 200).unwrap();
        assert_eq!(steps, s1.max(s2));
        let same =
            |u: &[Real], v: &[Real]| u.iter().zip(v).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same(&a, &one) && same(&b, &two));
        let ([c, d], _) = mg.solve_many([&zero, &b1], 1e-10, 200).unwrap();
        assert!(c.iter().all(|&v| v == 0.0) && same(&d, &one));
    }

    /// A loose tolerance leaves the residual large, but orthogonal to the
    /// deflation vector to rounding (the plain solve does not), and the
    /// answer is as near the tight one as the plain solve's.
    #[test]
    fn deflated_residuals_stay_orthogonal_to_their_vector() {
        let (diag, off) = rough_grid(20);
        let mg = Multigrid::cut(Csr::from_parts(&diag, &off), Vec::new(), small_blocks).unwrap();
        let n = diag.len();
        let b1: Vec<Real> = (0..n).map(|i| ((i * 13) % 7) as Real - 3.0).collect();
        let b2: Vec<Real> = (0..n).map(|i| (i as Real * 0.37).cos()).collect();
        let ones = vec![1.0; n];
        let ramp: Vec<Real> = (0..n).map(|i| (i % 20) as Real - 7.5).collect();
        let resid = |x: &[Real], b: &[Real]| -> Vec<Real> {
            let mut r: Vec<Real> = b
                .iter()
                .zip(&diag)
                .zip(x)
                .map(|((b, d), x)| b - d * x)
                .collect();
            for &(i, j, a) in &off {
                r[i as usize] -= a * x[j as usize];
                r[j as usize] -= a * x[i as usize];
            }
            r
        };
        let along = |r: &[Real], w: &[Real]| -> Real {
            let d: Real = r.iter().zip(w).map(|(r, w)| r * w).sum();
            let scale: Real = r.iter().zip(w).map(|(r, w)| (r * w).abs()).sum();
            (d / scale).abs()
        };
        let (tight, _) = mg.solve_many([&b1, &b2], 1e-12, 300).unwrap();
        let (plain, _) = mg.solve_many([&b1, &b2], 1e-3, 300).unwrap();
        let ([x1, x2], _) = mg
            .solve_deflated(
                [b1.clone(), b2.clone()],
                Some([ones.clone(), ramp.clone()]),
                1e-3,
                300,
            )
            .unwrap();
        let (r1, r2) = (resid(&x1, &b1), resid(&x2, &b2));
        assert!(residual(&diag, &off, &x1, &b1) > 1e-6, "a loose solve");
        assert!(along(&r1, &ones) < 1e-10, "{}", along(&r1, &ones));
        assert!(along(&r2, &ramp) < 1e-10, "{}", along(&r2, &ramp));
        let plain_r = resid(&plain[0], &b1);
        assert!(along(&plain_r, &ones) > 1e-6, "{}", along(&plain_r, &ones));
        let err = |x: &[Real], t: &[Real]| -> Real {
            let e: Vec<Real> = x.iter().zip(t).map(|(x, t)| x - t).collect();
            e.iter().map(|v| v * v).sum::<Real>().sqrt()
        };
        for m in 0..2 {
            let x = if m == 0 { &x1 } else { &x2 };
            assert!(err(x, &tight[m]) < 10.0 * err(&plain[m], &tight[m]) + 1e-12);
        }
        // A zero vector deflates nothing: the plain solve, bit for bit.
        let zero = vec![0.0; n];
        let ([y1, _], _) = mg
            .solve_deflated(
                [b1.clone(), b2.clone()],
                Some([zero.clone(), zero]),
                1e-3,
                300,
            )
            .unwrap();
        assert!(y1
            .iter()
            .zip(&plain[0])
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }

    #[test]
    fn the_answer_does_not_depend_on_the_threads() {
        let (diag, off) = grid(20);
        let b: Vec<Real> = (0..diag.len()).map(|i| (i as Real).cos()).collect();
        let solve = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    Multigrid::cut(Csr::from_parts(&diag, &off), Vec::new(), small_blocks)
                        .unwrap()
                        .solve(&b, 1e-10, 200)
                        .unwrap()
                })
        };
        let one = solve(1);
        for threads in [2, 3] {
            let other = solve(threads);
            assert_eq!(one.1, other.1);
            assert!(one
                .0
                .iter()
                .zip(&other.0)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }

    /// A matrix large enough that its rows, and the coarse rows of its first
    /// level, are built in several chunks on the threads: against a plain
    /// assembly, row by row through ordered maps, entry for entry.
    #[test]
    fn matrices_built_in_chunks_match_a_plain_assembly() {
        use std::collections::BTreeMap;
        let (diag, mut off) = rough_grid(28);
        let n = diag.len();
        // Repeated pairs, in either order, are summed.
        for e in (0..off.len()).step_by(7) {
            let (i, j, a) = off[e];
            off.push((j, i, 0.5 * a));
        }
        // A scrambled numbering: n is prime to 7919.
        let new_of: Vec<u32> = (0..n).map(|i| ((i * 7919) % n) as u32).collect();
        let a = Csr::renumbered(&diag, off.clone(), &new_of).unwrap();
        let mut want: Vec<BTreeMap<u32, Real>> = vec![BTreeMap::new(); n];
        for (i, &d) in diag.iter().enumerate() {
            *want[new_of[i] as usize].entry(new_of[i]).or_default() += d;
        }
        for &(i, j, v) in &off {
            let (i, j) = (new_of[i as usize], new_of[j as usize]);
            *want[i as usize].entry(j).or_default() += v;
            *want[j as usize].entry(i).or_default() += v;
        }
        let close = |got: Real, want: Real| (got - want).abs() <= 1e-12 * (1.0 + want.abs());
        for (i, row) in want.iter().enumerate() {
            let got: Vec<(u32, Real)> = a.entries(i).map(|k| (a.col[k], a.val[k])).collect();
            assert_eq!(got[0].0 as usize, i, "the diagonal first");
            assert!(close(got[0].1, row[&(i as u32)]));
            let others: Vec<(&u32, &Real)> = row.iter().filter(|e| *e.0 as usize != i).collect();
            assert_eq!(got.len() - 1, others.len(), "row {i}");
            for (g, w) in got[1..].iter().zip(others) {
                assert_eq!(g.0, *w.0, "row {i}: columns in order");
                assert!(close(g.1, *w.1), "row {i}: {} against {}", g.1, w.1);
            }
        }
        let (agg, coarse) = aggregate(&a, THETA);
        assert!(coarse > 4 * 1024, "several chunks of coarse rows");
        let p = Prolongator { agg, coarse };
        let product = galerkin(&a, &p);
        let mut want: Vec<BTreeMap<u32, Real>> = vec![BTreeMap::new(); coarse];
        for i in 0..n {
            let r = p.agg[i];
            if r == OUTSIDE {
                continue;
            }
            for k in a.entries(i) {
                let c = p.agg[a.col[k] as usize];
                if c != OUTSIDE {
                    *want[r as usize].entry(c).or_default() += a.val[k];
                }
            }
        }
        for (r, row) in want.iter().enumerate() {
            let got: Vec<(u32, Real)> = product
                .entries(r)
                .map(|k| (product.col[k], product.val[k]))
                .collect();
            assert_eq!(got[0].0 as usize, r);
            assert!(close(
                got[0].1,
                row.get(&(r as u32)).copied().unwrap_or(0.0)
            ));
            let others: Vec<(&u32, &Real)> = row.iter().filter(|e| *e.0 as usize != r).collect();
            assert_eq!(got.len() - 1, others.len(), "coarse row {r}");
            for (g, w) in got[1..].iter().zip(others) {
                assert_eq!(g.0, *w.0);
                assert!(close(g.1, *w.1), "coarse row {r}: {} against {}", g.1, w.1);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// Random diagonally dominant graphs: solved to the tolerance.
        #[test]
        fn random_laplacians_are_solved(
            edges in prop::collection::vec((0u32..900, 0u32..900, 0.001f64..100.0), 1000..4000),
            ground in prop::collection::vec(0.0f64..0.01, 900),
        ) {
            let n = 900;
            let off: Vec<(u32, u32, Real)> =
                edges.iter().filter(|e| e.0 != e.1).map(|&(i, j, g)| (i, j, -g)).collect();
            let mut diag: Vec<Real> = ground.iter().map(|g| g + 1e-3).collect();
            for &(i, j, a) in &off {
                diag[i as usize] -= a;
                diag[j as usize] -= a;
            }
            let mg = Multigrid::new(Csr::from_parts(&diag, &off)).unwrap();
            let b: Vec<Real> = (0..n).map(|i| (i as Real).cos()).collect();
            let (x, _) = mg.solve(&b, 1e-10, 500).unwrap();
            prop_assert!(residual(&diag, &off, &x, &b) < 1e-9);
        }

        /// The coarse operator, the restriction and the correction of any
        /// aggregation (nodes left out included) against `Pᵀ A P`, `Pᵀ r`
        /// and `P c` formed densely.
        #[test]
        fn the_coarse_level_is_p_transpose_a_p(
            edges in prop::collection::vec((0u32..40, 0u32..40, 0.01f64..10.0), 20..120),
            agg in prop::collection::vec(prop::option::weighted(0.9, 0u32..9), 40),
        ) {
            let n = 40;
            let off: Vec<(u32, u32, Real)> =
                edges.iter().filter(|e| e.0 != e.1).map(|&(i, j, g)| (i, j, -g)).collect();
            let mut diag = vec![1.0; n];
            for &(i, j, a) in &off {
                diag[i as usize] -= a;
                diag[j as usize] -= a;
            }
            let a = Csr::from_parts(&diag, &off);
            let mut dense = vec![vec![0.0; n]; n];
            for (i, row) in dense.iter_mut().enumerate() {
                for k in a.entries(i) {
                    row[a.col[k] as usize] += a.val[k];
                }
            }
            let p = Prolongator {
                agg: agg.iter().map(|c| c.unwrap_or(OUTSIDE)).collect(),
                coarse: 9,
            };
            let weight = |i: usize, c: usize| Real::from(u8::from(p.agg[i] == c as u32));
            let coarse = galerkin(&a, &p);
            for r in 0..9 {
                for c in 0..9 {
                    let mut want = 0.0;
                    for i in 0..n {
                        for j in 0..n {
                            want += weight(i, r) * dense[i][j] * weight(j, c);
                        }
                    }
                    let got: Real = coarse
                        .entries(r)
                        .filter(|&k| coarse.col[k] as usize == c)
                        .map(|k| coarse.val[k])
                        .sum();
                    prop_assert!((got - want).abs() <= 1e-12 * (1.0 + want.abs()), "({r}, {c}): {got} against {want}");
                }
            }
            let fine: Vec<[Real; 1]> = (0..n).map(|i| [(i as Real).sin()]).collect();
            let mut restricted = vec![[0.0]; 9];
            p.restrict(&fine, &mut restricted);
            let coarse_x: Vec<[Real; 1]> = (0..9).map(|c| [c as Real - 4.0]).collect();
            let mut corrected = fine.clone();
            p.add_to(&coarse_x, &mut corrected);
            for c in 0..9 {
                let want: Real = (0..n).map(|i| weight(i, c) * fine[i][0]).sum();
                prop_assert!((restricted[c][0] - want).abs() <= 1e-12);
            }
            for i in 0..n {
                let want = fine[i][0] + (0..9).map(|c| weight(i, c) * coarse_x[c][0]).sum::<Real>();
                prop_assert!((corrected[i][0] - want).abs() <= 1e-12);
            }
        }
    }
}
