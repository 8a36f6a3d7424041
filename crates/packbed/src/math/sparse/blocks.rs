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
/// Blocks at most. On two cores, the 10^5-sphere bed's flow (its systems
/// one after the other): 4 blocks 4.44 s, 8 4.18 s, 16 4.41 s (the same
/// steps; more blocks, more rows coupled across). The count is fixed, not the thread count: the answer
/// must not depend on the machine.
const MAX_BLOCKS: usize = 8;
/// Entries per chunk of a vector operation (and per partial sum of a dot).
pub(super) const CHUNK: usize = 8_192;

/// Block boundaries of `n` rows: `0 = b_0 < … < b_B = n`.
pub(super) fn bounds(n: usize) -> Vec<usize> {
    let blocks = (n / BLOCK_ROWS).clamp(1, MAX_BLOCKS);
    (0..=blocks).map(|b| b * n / blocks).collect()
}

/// `v` cut at `bounds`.
pub(super) fn split<'a, T>(v: &'a mut [T], bounds: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(bounds.len() - 1);
    let mut rest = v;
    for w in bounds.windows(2) {
        let (head, tail) = rest.split_at_mut(w[1] - w[0]);
        out.push(head);
        rest = tail;
    }
    out
}

/// The sum of the chunks' partial sums, in order.
pub(super) fn total<const K: usize>(partial: Vec<[Real; K]>) -> [Real; K] {
    partial.iter().fold([0.0; K], |mut t, p| {
        for m in 0..K {
            t[m] += p[m];
        }
        t
    })
}

/// `a · b` for each of the `K` vectors, summed chunk by chunk and the chunks
/// in order.
pub(super) fn dot<const K: usize>(a: &[[Real; K]], b: &[[Real; K]]) -> [Real; K] {
    total(
        a.par_chunks(CHUNK)
            .zip(b.par_chunks(CHUNK))
            .map(|(a, b)| {
                let mut s = [0.0; K];
                for (a, b) in a.iter().zip(b) {
                    for m in 0..K {
                        s[m] += a[m] * b[m];
                    }
                }
                s
            })
            .collect(),
    )
}

/// `x += α p`, `r −= α q`, and the new `r · r` (one pass).
pub(super) fn step<const K: usize>(
    x: &mut [[Real; K]],
    r: &mut [[Real; K]],
    p: &[[Real; K]],
    q: &[[Real; K]],
    alpha: [Real; K],
) -> [Real; K] {
    total(
        x.par_chunks_mut(CHUNK)
            .zip(r.par_chunks_mut(CHUNK))
            .zip(p.par_chunks(CHUNK).zip(q.par_chunks(CHUNK)))
            .map(|((x, r), (p, q))| {
                let mut s = [0.0; K];
                for i in 0..x.len() {
                    for m in 0..K {
                        x[i][m] += alpha[m] * p[i][m];
                        r[i][m] -= alpha[m] * q[i][m];
                        s[m] += r[i][m] * r[i][m];
                    }
                }
                s
            })
            .collect(),
    )
}

/// `p = z + β p`.
pub(super) fn direction<const K: usize>(p: &mut [[Real; K]], z: &[[Real; K]], beta: [Real; K]) {
    p.par_chunks_mut(CHUNK)
        .zip(z.par_chunks(CHUNK))
        .for_each(|(p, z)| {
            for (p, z) in p.iter_mut().zip(z) {
                for m in 0..K {
                    p[m] = z[m] + beta[m] * p[m];
                }
            }
        });
}

/// `p = (z + β p) − μ w`: [`direction`] and the deflation of `w` out of
/// it in one pass over `p` (the same bits as the two passes).
pub(super) fn direction_deflated<const K: usize>(
    p: &mut [[Real; K]],
    z: &[[Real; K]],
    beta: [Real; K],
    w: &[[Real; K]],
    mu: [Real; K],
) {
    p.par_chunks_mut(CHUNK)
        .zip(z.par_chunks(CHUNK).zip(w.par_chunks(CHUNK)))
        .for_each(|(p, (z, w))| {
            for ((p, z), w) in p.iter_mut().zip(z).zip(w) {
                for m in 0..K {
                    let d = z[m] + beta[m] * p[m];
                    p[m] = d - mu[m] * w[m];
                }
            }
        });
}

/// `p −= mu · w`, per right-hand side.
pub(super) fn deflate<const K: usize>(p: &mut [[Real; K]], w: &[[Real; K]], mu: [Real; K]) {
    p.par_chunks_mut(CHUNK)
        .zip(w.par_chunks(CHUNK))
        .for_each(|(p, w)| {
            for (p, w) in p.iter_mut().zip(w) {
                for m in 0..K {
                    p[m] -= mu[m] * w[m];
                }
            }
        });
}
