//! Points along a Hilbert curve: the order of insertion of the triangulation
//! (each point is found a few cells from the one before it) and of the flow
//! unknowns (neighbours close in memory).

use rayon::prelude::*;

/// Bits per axis of the curve's grid (2^16 cells per axis is finer than any
/// bed's spacing needs for locality).
const BITS: u32 = 16;

/// The indices of `points` in Hilbert order (ties by index, so the order is a
/// function of the points alone).
pub fn order<const D: usize>(points: &[[f64; D]]) -> Vec<u32> {
    let (lo, hi) = super::bounds(points);
    let cells = ((1u64 << BITS) - 1) as f64;
    let mut keyed: Vec<(u64, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let mut x = [0u32; D];
            for k in 0..D {
                let span = hi[k] - lo[k];
                let t = if span > 0.0 {
                    (p[k] - lo[k]) / span
                } else {
                    0.0
                };
                x[k] = (t.clamp(0.0, 1.0) * cells) as u32;
            }
            (key(x), i as u32)
        })
        .collect();
    // The pairs are distinct, so the parallel sort's answer is unique.
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The position along the Hilbert curve of a grid cell (Skilling 2004,
/// "Programming the Hilbert curve": axes to transposed index, then interleave).
fn key<const D: usize>(mut x: [u32; D]) -> u64 {
    let m = 1u32 << (BITS - 1);
    // Inverse undo of the excess work.
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..D {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    // Gray encode.
    for i in 1..D {
        x[i] ^= x[i - 1];
    }
    let mut t = 0;
    let mut q = m;
    while q > 1 {
        if x[D - 1] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for v in x.iter_mut() {
        *v ^= t;
    }
    // Interleave the transposed bits, most significant first.
    let mut h = 0u64;
    for b in (0..BITS).rev() {
        for v in &x {
            h = (h << 1) | u64::from((v >> b) & 1);
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Consecutive cells of the curve are grid neighbours, and every cell is
    /// visited once: checked on a 16 × 16 grid and an 8 × 8 × 8 grid.
    fn walk_is_a_hilbert_curve<const D: usize>(side: u32) {
        let mut cells: Vec<([u32; D], u64)> = Vec::new();
        let shift = BITS - side.trailing_zeros();
        let n = (side as usize).pow(D as u32);
        for i in 0..n {
            let mut x = [0u32; D];
            let mut r = i;
            for k in 0..D {
                x[k] = (r % side as usize) as u32;
                r /= side as usize;
            }
            // Scaled to the curve's grid: the first cell of each coarse block.
            let scaled = x.map(|v| v << shift);
            cells.push((x, key(scaled)));
        }
        cells.sort_by_key(|c| c.1);
        let keys: Vec<u64> = cells.iter().map(|c| c.1).collect();
        let mut unique = keys.clone();
        unique.dedup();
        assert_eq!(unique.len(), n);
        for w in cells.windows(2) {
            let steps: u32 = (0..D).map(|k| w[0].0[k].abs_diff(w[1].0[k])).sum();
            assert_eq!(steps, 1, "{:?} -> {:?}", w[0].0, w[1].0);
        }
    }

    #[test]
    fn consecutive_cells_are_neighbours() {
        walk_is_a_hilbert_curve::<2>(16);
        walk_is_a_hilbert_curve::<3>(8);
    }

    #[test]
    fn order_is_a_permutation() {
        let pts: Vec<[f64; 3]> = (0..100)
            .map(|i| [(i * 37 % 100) as f64, (i * 11 % 7) as f64, 1.0])
            .collect();
        let mut o = order(&pts);
        o.sort_unstable();
        assert_eq!(o, (0..100).collect::<Vec<u32>>());
    }
}
