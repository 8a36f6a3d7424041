//! packbed: exact sequential deposition ("drop and roll") of packed beds of spheres
//! (3D) and discs (2D), and the measures of their structure.
//!
//! The flow: [`config::Config`] → [`config::Plan`] → [`deposit`] → [`bed::Bed`] →
//! [`analysis`]. Everything is generic over the dimension `D` (2 or 3).

pub mod analysis;
pub mod bed;
pub mod config;
pub mod container;
pub mod deposit;
pub mod ensemble;
pub mod error;
pub mod geometry;
pub mod grid;
pub mod io;
pub mod math;
pub mod pipeline;
pub mod render;
pub mod species;

pub use error::{Error, Result};
