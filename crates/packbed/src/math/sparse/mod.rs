//! Sparse symmetric positive definite systems: the elimination order (nested
//! dissection), our supernodal Cholesky factorisation and its solves. Used by
//! the mechanics of `packbed fragment` (the stiffness matrix) and by the flow
//! through the pore network (the pressure equations).

pub mod amg;
pub(crate) mod factor;
pub mod ordering;
mod spd;
mod supernodal;

pub use spd::{solve_spd, SpdError, DIRECT_LIMIT};
