//! packbed: exact sequential deposition ("drop and roll") of packed beds of spheres
//! (3D) and discs (2D), and the measures of their structure.
//!
//! The flow: [`config::Config`] → [`config::Plan`] → [`deposit`] → [`bed::Bed`] →
//! [`analysis`]. Everything is generic over the dimension `D` (2 or 3).
//!
//! One bed from a config written as TOML, deposited and analysed:
//!
//! ```
//! use packbed::config::Config;
//!
//! let config = Config::from_toml(
//!     "dim = 2\nseed = 5\n[box]\npreset = \"thesis\"\n\
//!      [[species]]\nradius = 10\n[[species]]\nradius = 20\n",
//!     "example",
//! )?;
//! let plan = config.plan::<2>()?;
//! let (bed, report) = packbed::deposit::deposit(&plan, &mut |_| {})?;
//! // The fill stops at the 101st particle that would stick out above the roof.
//! assert_eq!(report.roof_overflows, 101);
//! let (_contacts, summary) = packbed::analysis::analyze(&bed, 1e-9);
//! assert!(summary.packing.as_ref().unwrap().global > 0.7 && summary.packing.as_ref().unwrap().global < 0.85);
//! // Large means a radius of at least 20 here, whatever the species.
//! assert_eq!(summary.percolation.as_ref().unwrap().large_radius, 20.0);
//! # Ok::<(), packbed::Error>(())
//! ```

pub mod analysis;
pub mod bed;
pub mod bench;
pub mod config;
pub mod container;
pub mod deposit;
pub mod ensemble;
pub mod error;
pub mod geometry;
pub mod grid;
pub mod io;
pub mod math;
pub mod output;
pub mod pipeline;
pub mod render;
pub mod species;

pub use error::{Error, Result};
