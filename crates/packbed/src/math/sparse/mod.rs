//! Sparse symmetric positive definite systems: the elimination order (nested
//! dissection), our supernodal Cholesky factorisation and its solves. Used by
//! the mechanics of `packbed fragment` (the stiffness matrix) and by the flow
//! through the pore network (the pressure equations).

pub mod amg;
mod blocks;
pub(crate) mod factor;
mod lane;
pub mod ordering;
mod spd;
mod supernodal;

#[cfg(test)]
pub(crate) use spd::{solve_spd, DIRECT_LIMIT};
pub use spd::{solve_spd_shifted, SpdError, Systems};

/// Item indices grouped by key, in a stable counting sort: key `k`'s items
/// are `order[starts[k]..starts[k + 1]]`, ascending. Keys must be below `n`.
pub(crate) fn group_by_key(keys: &[u32], n: usize) -> (Vec<usize>, Vec<u32>) {
    let mut starts = vec![0usize; n + 1];
    for &k in keys {
        starts[k as usize + 1] += 1;
    }
    for k in 0..n {
        starts[k + 1] += starts[k];
    }
    let mut fill = starts.clone();
    let mut order = vec![0u32; keys.len()];
    for (item, &k) in keys.iter().enumerate() {
        order[fill[k as usize]] = item as u32;
        fill[k as usize] += 1;
    }
    (starts, order)
}
