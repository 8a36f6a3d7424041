//! Particles as a reader collects them, the reader's error helpers, and the
//! bed built from them.

use super::report::BoxSource;
use crate::bed::Bed;
use crate::container::Container;
use crate::error::{echo, Error, Result};
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
    /// What the file calls species 0 (LAMMPS types count from 1).
    pub(super) first_species_id: u32,
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
            first_species_id: 0,
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
            .map_err(|_| self.err(line, format!("{what}: \"{}\" is not a number", echo(s))))?;
        if !v.is_finite() {
            return Err(self.err(line, format!("{what} is {}, not a finite number", echo(s))));
        }
        Ok(v)
    }

    /// A whole number >= 0 that fits `u32`, or an error naming `what`.
    pub(super) fn int(&self, line: usize, what: &str, s: &str) -> Result<u32> {
        s.parse().map_err(|_| {
            self.err(
                line,
                format!(
                    "{what}: \"{}\" is not a whole number >= 0 (up to 4294967295)",
                    echo(s)
                ),
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

/// Unused species indices a file may leave below its largest id before its ids
/// are renumbered: an id is an index into every per-species table.
const MAX_UNUSED_SPECIES: usize = 64;

/// Renumbers sparse species ids (`1000000000`, or LAMMPS types 1 and 7) to
/// dense indices in increasing order, each species named by the id the file
/// used, so no table is sized by a number read from the file. Dense ids, the
/// usual case, are kept as they are.
pub(super) fn densify_species(raw: &mut Raw) {
    let mut used: Vec<u32> = raw.species.clone();
    used.sort_unstable();
    used.dedup();
    let Some(&max) = used.last() else {
        return;
    };
    let described = raw.species_info.len();
    let known = used.iter().filter(|&&s| s as usize >= described).count() + described;
    if (max as usize + 1).saturating_sub(known) <= MAX_UNUSED_SPECIES {
        return;
    }
    let info: Vec<Species> = used
        .iter()
        .map(|&id| {
            let mut s = raw
                .species_info
                .get(id as usize)
                .cloned()
                .unwrap_or(Species {
                    name: String::new(),
                    shape: crate::species::Shape::Sphere,
                    size: crate::species::SizeDist::Fixed(mean_radius(raw, id)),
                    ratio: 1.0,
                    feed: None,
                });
            if s.name.is_empty() {
                s.name = (u64::from(id) + u64::from(raw.first_species_id)).to_string();
            }
            s
        })
        .collect();
    for s in raw.species.iter_mut() {
        // `used` holds every id of `raw.species`, so the search always finds it.
        *s = used.binary_search(s).unwrap_or(0) as u32;
    }
    raw.species_info = info;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw_with(species: &[u32]) -> Raw {
        let mut raw = Raw::new(2);
        for &s in species {
            raw.pos.push([1.0, 1.0, 0.0]);
            raw.radii.push(1.0);
            raw.species.push(s);
            raw.bodies.push(0);
            raw.lines.push(2);
        }
        raw
    }

    #[test]
    fn huge_species_ids_become_dense_indices_named_by_their_id() {
        let mut raw = raw_with(&[1_000_000_000, 7, 1_000_000_000]);
        densify_species(&mut raw);
        assert_eq!(raw.species, [1, 0, 1]);
        let names: Vec<&str> = raw.species_info.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["7", "1000000000"]);
    }

    #[test]
    fn lammps_types_are_named_as_the_file_has_them() {
        // The dump reader stores type t as species t - 1.
        let mut raw = raw_with(&[2_000_000_000, 0]);
        raw.first_species_id = 1;
        densify_species(&mut raw);
        let names: Vec<&str> = raw.species_info.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["1", "2000000001"]);
    }

    #[test]
    fn dense_species_ids_are_kept() {
        let mut raw = raw_with(&[0, 2, 1, 2]);
        densify_species(&mut raw);
        assert_eq!(raw.species, [0, 2, 1, 2]);
        assert!(raw.species_info.is_empty());
    }
}
