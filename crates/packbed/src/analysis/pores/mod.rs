//! The pore space of a bed (`spec/pores.md`): the regular triangulation of the
//! particle centres weighted by their squared radii, its cells (pores) and
//! facets (throats).

pub mod geometry;
mod hilbert;
pub mod network;
pub mod triangulation;
