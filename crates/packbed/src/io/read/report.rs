//! What a reader is told (the box hint) and what it tells back (the report).

use crate::math::Real;

/// A box for files that have none: extents `[W, H]` (2D) or `[W, D, H]` (3D).
#[derive(Clone, Debug, PartialEq)]
pub struct BoxHint {
    /// Extents; the length (2 or 3) also fixes the dimension of a plain table.
    pub size: Vec<Real>,
    /// Periodic side boundaries.
    pub periodic: bool,
}

/// Most particles a file may declare (a larger count is a corrupt header).
pub const MAX_PARTICLES: u64 = 2_000_000_000;

/// Where the box of a bed read from a file came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxSource {
    /// Given by the caller (`--box`, `--periodic`).
    Given,
    /// The bed file itself (dump bounds, XYZ lattice, VTU field data).
    File,
    /// The `summary.json` beside a `particles.csv`.
    SummaryBeside,
    /// Not read: the bed was built in memory (a Python `packbed.deposit`).
    Built,
}

impl BoxSource {
    /// How `summary.json` and the screen name it.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            BoxSource::Given => "options",
            BoxSource::File => "file",
            BoxSource::SummaryBeside => "summary.json",
            BoxSource::Built => "deposition",
        }
    }
}

/// What reading a bed file found out besides the bed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadReport {
    /// Where the box came from.
    pub box_source: BoxSource,
    /// Centres moved into `[0, W)` along periodic axes.
    pub wrapped: u64,
}

/// How far a particle may stick out of the box, relative to its radius:
/// DEM beds press particles a little into the walls.
pub const OUTSIDE_TOL: Real = 0.01;
