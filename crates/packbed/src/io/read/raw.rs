//! Particles as a reader collects them, the reader's error helpers, and the
//! bed built from them.

use super::report::BoxSource;
use crate::bed::Bed;
use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use crate::species::Species;
use std::path::Path;

/// Particles as read, before the dimension is fixed.
pub(super) struct Raw {
    pub(super) dim: usize,
    /// Positions with three components (z unused in 2D).
    pub(super) pos: Vec<[Real; 3]>,
    pub(super) radii: Vec<Real>,
    pub(super) species: Vec<u32>,
    pub(super) bodies: Vec<u32>,
    /// Line of each particle, for error messages.
    pub(super) lines: Vec<usize>,
    /// Box extents (`dim` of them) and periodic flag, if the file has them.
    pub(super) size: Option<(Vec<Real>, bool)>,
    /// Box origin, subtracted from the positions (packbed's box starts at 0).
    pub(super) origin: [Real; 3],
    /// Where `size` came from, when set.
    pub(super) box_source: BoxSource,
    pub(super) species_info: Vec<Species>,
}

impl Raw {
    pub(super) fn new(dim: usize) -> Raw {
        Raw {
            dim,
            pos: Vec::new(),
            radii: Vec::new(),
            species: Vec::new(),
            bodies: Vec::new(),
            lines: Vec::new(),
            size: None,
            origin: [0.0; 3],
            box_source: BoxSource::File,
            species_info: Vec::new(),
        }
    }
}

/// Reads one file; its errors name the file and the line.
pub(super) struct Reader<'a> {
    /// The file read.
    pub(super) path: &'a Path,
}

impl Reader<'_> {
    /// An [`Error::Data`] at `line` of the file.
    pub(super) fn err(&self, line: usize, message: impl Into<String>) -> Error {
        Error::Data {
            path: self.path.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    /// A finite number, or an error naming `what`.
    pub(super) fn num(&self, line: usize, what: &str, s: &str) -> Result<Real> {
        let v: Real = s
            .parse()
            .map_err(|_| self.err(line, format!("{what}: \"{s}\" is not a number")))?;
        if !v.is_finite() {
            return Err(self.err(line, format!("{what} is {s}, not a finite number")));
        }
        Ok(v)
    }

    /// A whole number >= 0 that fits `u32`, or an error naming `what`.
    pub(super) fn int(&self, line: usize, what: &str, s: &str) -> Result<u32> {
        s.parse().map_err(|_| {
            self.err(
                line,
                format!("{what}: \"{s}\" is not a whole number >= 0 (up to 4294967295)"),
            )
        })
    }
}

/// Mean radius of species `s` (1 when it has no particle).
pub(super) fn mean_radius(raw: &Raw, s: u32) -> Real {
    let (mut sum, mut n) = (0.0, 0usize);
    for (r, &q) in raw.radii.iter().zip(&raw.species) {
        if q == s {
            sum += r;
            n += 1;
        }
    }
    if n == 0 {
        1.0
    } else {
        sum / n as Real
    }
}

/// The bed of `raw` in dimension `D`, in the given box.
pub(super) fn build<const D: usize>(raw: &Raw, size: &[Real], periodic: bool) -> Bed<D> {
    let mut s = [0.0; D];
    s.copy_from_slice(&size[..D]);
    let mut bed = Bed::new(
        Container {
            size: Vector(s),
            periodic,
        },
        raw.species_info.clone(),
    );
    for k in 0..raw.pos.len() {
        let mut c = [0.0; D];
        c.copy_from_slice(&raw.pos[k][..D]);
        bed.push_bead(Vector(c), raw.radii[k], raw.species[k], raw.bodies[k]);
    }
    bed
}
