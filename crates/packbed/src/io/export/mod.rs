//! Exports for other tools: VTK XML unstructured grid (`bed.vtu`, ParaView), LAMMPS
//! dump (`bed.dump`, OVITO, LAMMPS `read_dump`), extended XYZ (`bed.xyz`, OVITO,
//! ASE). Every export carries positions, radius, species, body and coordination
//! number, and the box with its periodic flags; [`super::read::read_bed`] reads
//! all three back to the same particles (numbers written in shortest round-trip
//! form, so exactly).
//!
//! 2D beds are written in the x–y plane with z = 0 and a thin z extent (as LAMMPS
//! and OVITO expect of 2D data): packbed's vertical y stays y.

use crate::bed::Bed;
use crate::error::{Error, Result};
use std::io::Write;

mod dump;
mod vtu;
mod xyz;

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// VTK XML unstructured grid of vertices, `bed.vtu`.
    Vtk,
    /// LAMMPS dump, `bed.dump`.
    Dump,
    /// Extended XYZ, `bed.xyz`.
    Xyz,
}

impl Format {
    /// The file name a run gives this export.
    pub fn file_name(&self) -> &'static str {
        match self {
            Format::Vtk => "bed.vtu",
            Format::Dump => "bed.dump",
            Format::Xyz => "bed.xyz",
        }
    }

    /// Parses a comma-separated list such as `vtk,dump,xyz` (duplicates dropped).
    pub fn parse_list(s: &str) -> Result<Vec<Format>> {
        let mut out = Vec::new();
        for word in s.split(',').map(str::trim).filter(|w| !w.is_empty()) {
            let f = match word.to_ascii_lowercase().as_str() {
                "vtk" | "vtu" => Format::Vtk,
                "dump" | "lammps" => Format::Dump,
                "xyz" | "extxyz" => Format::Xyz,
                other => {
                    return Err(Error::setting(
                        "export",
                        format!("unknown format \"{other}\" (choose from vtk, dump, xyz)"),
                    ))
                }
            };
            if !out.contains(&f) {
                out.push(f);
            }
        }
        if out.is_empty() {
            return Err(Error::setting(
                "export",
                "no format given (choose from vtk, dump, xyz)",
            ));
        }
        Ok(out)
    }

    /// Writes `bed` in this format; `coordination` holds one number per particle.
    pub fn write<const D: usize>(
        &self,
        w: &mut dyn Write,
        bed: &Bed<D>,
        coordination: &[u32],
    ) -> std::io::Result<()> {
        check_lengths(bed, coordination)?;
        let x = Export {
            bed,
            coordination,
            box3: box3(bed),
        };
        match self {
            Format::Vtk => vtu::write(w, &x),
            Format::Dump => dump::write(w, &x),
            Format::Xyz => xyz::write(w, &x),
        }
    }
}

/// A bed checked for export (finite, one coordination number per particle),
/// with its box as three extents.
#[derive(Clone, Copy)]
struct Export<'a, const D: usize> {
    bed: &'a Bed<D>,
    coordination: &'a [u32],
    box3: [f64; 3],
}

fn check_lengths<const D: usize>(bed: &Bed<D>, coordination: &[u32]) -> std::io::Result<()> {
    if coordination.len() != bed.len() {
        return Err(std::io::Error::other(format!(
            "{} coordination numbers for {} particles",
            coordination.len(),
            bed.len()
        )));
    }
    for (i, c) in bed.centres.iter().enumerate() {
        if c.0.iter().any(|v| !v.is_finite()) || !bed.radii[i].is_finite() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("particle {i} has a non-finite position or radius; refusing to write it"),
            ));
        }
    }
    Ok(())
}

/// Position as three coordinates (z = 0 in 2D).
fn position<const D: usize>(bed: &Bed<D>, i: usize) -> [f64; 3] {
    let c = bed.centres[i];
    if D == 2 {
        [c[0], c[1], 0.0]
    } else {
        [c[0], c[1], c[D - 1]]
    }
}

/// The box as three extents; in 2D a z extent of one largest diameter.
fn box3<const D: usize>(bed: &Bed<D>) -> [f64; 3] {
    let s = bed.container.size;
    if D == 2 {
        [s[0], s[1], thin_z(bed)]
    } else {
        [s[0], s[1], s[D - 1]]
    }
}

/// Thickness of the z slab of a 2D bed: one largest diameter (1 for an empty bed).
fn thin_z<const D: usize>(bed: &Bed<D>) -> f64 {
    let d = 2.0 * bed.r_max();
    if d > 0.0 {
        d
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_lists() {
        assert_eq!(
            Format::parse_list("vtk, dump,xyz,vtk").unwrap(),
            vec![Format::Vtk, Format::Dump, Format::Xyz]
        );
        assert!(Format::parse_list("pdb")
            .unwrap_err()
            .to_string()
            .contains("pdb"));
        assert!(Format::parse_list(" , ").is_err());
    }
}
