//! The multigrid's sweeps and the conjugate gradients' vector work on every
//! core, with the same answer whatever the number of threads.
//!
//! Gauss–Seidel is a chain from row to row. Hybrid Gauss–Seidel (as in
//! hypre) cuts the rows into a fixed number of contiguous blocks, sweeps each
//! block on its own and takes the couplings between blocks from the previous
//! values: block Jacobi between blocks, Gauss–Seidel within. The rows are in
//! Hilbert order, so a block is a compact region and few couplings cross.
//! The forward sweep uses `D + L_in` and the backward `D + U_in`, transposes
//! of each other, so the cycle stays symmetric; `M + Mᵀ − A = D − A_out` is
//! diagonally dominant on a pore network's Laplacian, so the sweep still
//! converges. The blocks and the order of every sum depend on the size of
//! the system only, never on the threads.

use crate::math::Real;
use rayon::prelude::*;

/// Rows per block at least: below two such blocks a level is swept as one.
const BLOCK_ROWS: usize = 16_384;
/// Blocks at most: enough to keep every core of a workstation busy; more
/// would only weaken the sweep.
const MAX_BLOCKS: usize = 8;
/// Entries per chunk of a vector operation (and per partial sum of a dot).
pub(super) const CHUNK: usize = 8_192;

/// Block boundaries of `n` rows: `0 = b_0 < … < b_B = n`.
pub(super) fn bounds(n: usize) -> Vec<usize> {
    let blocks = (n / BLOCK_ROWS).clamp(1, MAX_BLOCKS);
    (0..=blocks).map(|b| b * n / blocks).collect()
}

/// `v` cut at `bounds`.
pub(super) fn split<'a>(v: &'a mut [Real], bounds: &[usize]) -> Vec<&'a mut [Real]> {
    let mut out = Vec::with_capacity(bounds.len() - 1);
    let mut rest = v;
    for w in bounds.windows(2) {
        let (head, tail) = rest.split_at_mut(w[1] - w[0]);
        out.push(head);
        rest = tail;
    }
    out
}

/// `a · b`, summed chunk by chunk and the chunks in order.
pub(super) fn dot(a: &[Real], b: &[Real]) -> Real {
    let partial: Vec<Real> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x * y).sum::<Real>())
        .collect();
    partial.iter().sum()
}

/// `x += α p`, `r −= α q`, and the new `r · r` (one pass).
pub(super) fn step(x: &mut [Real], r: &mut [Real], p: &[Real], q: &[Real], alpha: Real) -> Real {
    let partial: Vec<Real> = x
        .par_chunks_mut(CHUNK)
        .zip(r.par_chunks_mut(CHUNK))
        .zip(p.par_chunks(CHUNK).zip(q.par_chunks(CHUNK)))
        .map(|((x, r), (p, q))| {
            let mut s = 0.0;
            for i in 0..x.len() {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
                s += r[i] * r[i];
            }
            s
        })
        .collect();
    partial.iter().sum()
}

/// `p = z + β p`.
pub(super) fn direction(p: &mut [Real], z: &[Real], beta: Real) {
    p.par_chunks_mut(CHUNK)
        .zip(z.par_chunks(CHUNK))
        .for_each(|(p, z)| {
            for (p, z) in p.iter_mut().zip(z) {
                *p = z + beta * *p;
            }
        });
}
