//! packbed: exact sequential deposition ("drop and roll") of packed beds of
//! spheres (3D) and discs (2D), rigid chains included, and the measures of
//! their structure: packing, coordination, percolation, voids, orientation,
//! segregation.
//!
//! The flow: [`Config`] (the TOML schema, or a dict in Python) → deposition →
//! [`Bed`] → analysis ([`Summary`]) → files. A bed of either dimension travels
//! as an [`AnyBed`], whose methods spare callers a match on the dimension.
//! The front door is this page: the types and functions re-exported here are
//! the API the command and the Python package are built on.
//!
//! # A bed from a config
//!
//! ```
//! use packbed::{run_bed, Config};
//!
//! let config = Config::from_toml(
//!     "dim = 2\nseed = 5\n[box]\npreset = \"thesis\"\n\
//!      [[species]]\nradius = 10\n[[species]]\nradius = 20\n",
//!     "example",
//! )?;
//! let run = run_bed(&config, &mut |_placed| {})?;
//! // The fill stops at the 101st particle that would stick out above the roof.
//! assert_eq!(run.summary.counts.roof_overflows, 101);
//! let measures = &run.summary.analysis;
//! let packing = measures.packing.as_ref().expect("all measures by default");
//! assert!(packing.global > 0.7 && packing.global < 0.85);
//! // Large means a radius of at least 20 here, whatever the species.
//! assert_eq!(measures.percolation.as_ref().unwrap().large_radius, 20.0);
//! assert_eq!((run.bed.dim(), run.bed.len()), (2, run.summary.counts.particles as usize));
//! # Ok::<(), packbed::Error>(())
//! ```
//!
//! # Reading a bed file and analysing it
//!
//! Any file `packbed analyze` reads (packbed's `particles.csv`, a plain
//! `x y [z] r` table, a LAMMPS dump, XYZ, VTU); a file without a box takes it
//! from a [`BoxHint`].
//!
//! ```
//! use packbed::{analyze_file, AnalysisConfig, BoxHint, Measure};
//!
//! let dir = std::env::temp_dir().join(format!("packbed-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! let file = dir.join("three.txt");
//! // Three discs of radius 1 in a row on the floor of a 6 × 4 box.
//! std::fs::write(&file, "1 1 1\n3 1 1\n5 1 1\n").unwrap();
//! let hint = BoxHint { size: vec![6.0, 4.0], periodic: false };
//! let settings = AnalysisConfig {
//!     measures: Some(vec![Measure::Coordination]),
//!     ..AnalysisConfig::default()
//! };
//! let analyzed = analyze_file(&file, Some(&hint), &settings)?;
//! let coordination = analyzed.summary.analysis.coordination.as_ref().unwrap();
//! // The middle disc touches two, the end discs one each: 4 / 3 on average.
//! assert!((coordination.mean - 4.0 / 3.0).abs() < 1e-12);
//! assert_eq!(coordination.floor_contacts, 3);
//! // Measures not asked for are left out, and the summary says so.
//! assert!(analyzed.summary.analysis.packing.is_none());
//! assert!(analyzed.summary.analysis.measures_left_out.contains(&"packing"));
//! assert_eq!(analyzed.contacts.pairs.len(), 2);
//! std::fs::remove_dir_all(&dir).unwrap();
//! # Ok::<(), packbed::Error>(())
//! ```
//!
//! # An ensemble of replicate beds
//!
//! Replicate `i` is seeded from the master seed alone, so the statistics do
//! not depend on the number of threads.
//!
//! ```
//! use packbed::{run_ensemble, Config, EnsembleOptions, Overrides};
//!
//! let mut config = Config::default();
//! Overrides {
//!     dim: Some(2),
//!     radii: Some(vec![10.0]),
//!     count: Some(40),
//!     ..Overrides::default()
//! }
//! .apply(&mut config)?;
//! let out = std::env::temp_dir().join(format!("packbed-doc-ens-{}", std::process::id()));
//! let options = EnsembleOptions { runs: 3, pictures: false, ..EnsembleOptions::default() };
//! let outcome = run_ensemble(&config, &options, &out, &|_tick| {})?;
//! let stats = &outcome.points[0].aggregate;
//! assert_eq!(stats.replicates, 3);
//! let global = stats.measures.iter().find(|m| m.name == "packing.global").unwrap();
//! assert_eq!(global.stats.n, 3);
//! assert!(global.stats.min <= global.stats.mean && global.stats.mean <= global.stats.max);
//! assert!(out.join("ensemble.csv").exists());
//! std::fs::remove_dir_all(&out).unwrap();
//! # Ok::<(), packbed::Error>(())
//! ```
// Every public item says what it is (issue 62); CI denies the warning (clippy -D warnings).
#![warn(missing_docs)]

// The modules are private: what the command, the Python package, the fuzz
// targets, the benches and the library's own tests use is re-exported below
// (issue 62), and five families stay whole namespaces (`bench`, `compare`,
// `render`, `slurm`, `text`).
mod analysis;
mod bed;
pub mod bench;
mod config;
mod container;
mod deposit;
mod ensemble;
mod error;
mod geometry;
mod grid;
mod input;
mod io;
mod math;
mod mechanics;
mod memory;
mod output;
mod pipeline;
#[cfg(feature = "render")]
pub mod render;
mod species;
pub mod text;

// The front door: everything the command and the Python package use is here,
// at the root, so that the modules below can change shape without them.
pub use analysis::orientation::AngleFrom;
pub use analysis::pores::Column as PoreColumn;
pub use analysis::{find_contacts, AnalysisOptions, Contacts, LargeRule, Summary, BULK_MIN_BODIES};
pub use config::{contact_tol_problem, parse_numbers, LengthUnit, Mode, DEFAULT_CONTACT_TOL};
/// Ensembles side by side: the groups of ensemble directories read, their
/// measures compared, the comparison written.
pub mod compare {
    pub use crate::ensemble::compare::{compare, read_groups, write_comparison};
}
/// Slurm job arrays of an ensemble.
pub use ensemble::slurm;
pub use ensemble::{
    merge_with as merge_ensembles, runs_of as ensemble_runs, validate as validate_ensemble,
    worker_threads, Shard, Tick,
};
pub use error::{one_line, one_line_naming, panic_line, usage_line};
pub use io::atomic::abandon_in_flight;
pub use io::export::Format as ExportFormat;
pub use io::tables::particles_header;
pub use mechanics::{Breaks, FragmentationConfig, Load};
pub use memory::Allocator;
pub use output::check_out_dir;

pub use bed::{AnyBed, Bed};
pub use config::{AnalysisConfig, BoxSpec, Config, Edit, Measure, MeasureList, Numbers, Overrides};
pub use ensemble::{run as run_ensemble, EnsembleOptions, Outcome};
pub use error::{Error, Result};
pub use io::read::{read_bed, read_bed_report, BoxHint, BoxSource, ReadReport};
pub use io::{AnalyzeSummary, RunSummary};
pub use output::RunExtras;
pub use pipeline::{
    analyze_bed, analyze_file, analyze_read_bed, check_box_hint, fragment_file, fragment_file_with,
    fragment_read_bed, picture_is_svg, planned, run_bed, run_bed_or_stop, run_planned, AnalyzedBed,
    AnyFragmentation, FinishedBed, FragmentedBed,
};
#[cfg(feature = "render")]
pub use pipeline::{render_file, render_to};

// The parts the library's integration tests, the benches and the fuzz targets
// check on their own (the exact deposition, the checker, single measures, the
// solver); the command and the Python package do not use them.
pub use analysis::capture::{capture, mesh_mid_plane, CaptureSummary};
pub use analysis::filtration::FiltrationSummary;
pub use analysis::orientation::{body_axes, orientation};
pub use analysis::packing::{bulk_fraction, global_fraction, particle_volumes, surface_height};
pub use analysis::percolation::percolation;
pub use analysis::pores::triangulation::Triangulation;
pub use analysis::profile::profile;
pub use analysis::regions::regional_packing;
pub use analysis::validate::{
    check_bed, check_bed_with, InvariantChecks, Report as CheckReport, Supports,
};
pub use analysis::voids::voids;
pub use analysis::{analyze, analyze_with, bulk_region, coordination, PercolationOptions};
pub use config::{BaseLayerKind, Fill, Settling, SettlingConfig, SizeConfig, SpeciesConfig};
pub use container::{Container, Wall};
pub use deposit::chain::{ChainShape, Pose};
pub use deposit::compaction::CompactionStop;
pub use deposit::{build, deposit, drop_onto, DepositReport, Entry};
pub use ensemble::seeds::replicate_seed;
pub use ensemble::{run_dir as ensemble_run_dir, ENSEMBLE_FILES, MANIFEST, SWEEP_FILES};
pub use io::summary::SUMMARY_KEYS;
pub use io::Timing;
pub use math::{Real, Vector, LENGTH_RANGE};
pub use mechanics::solver::{Solver, Springs};
pub use mechanics::{fragment, Fragmentation};
pub use output::write_run;
pub use species::{SizeDist, SizeTable, Within};
