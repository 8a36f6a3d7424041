//! Exports for other tools: VTK XML unstructured grid (`bed.vtu`, ParaView), LAMMPS
//! dump (`bed.dump`, OVITO, LAMMPS `read_dump`), extended XYZ (`bed.xyz`, OVITO,
//! ASE). Every export carries positions, radius, species, body and coordination
//! number, and the box with its periodic flags; [`super::read::read_bed`] reads
//! all three back to the same particles (numbers written in shortest round-trip
//! form, so exactly).
//!
//! 2D beds are written in the x–y plane with z = 0 and a thin z extent (as LAMMPS
//! and OVITO expect of 2D data): packbed's vertical y stays y.

use super::tables::Num;
use crate::bed::Bed;
use crate::error::{Error, Result};
use std::io::Write;

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
            Format::Vtk => write_vtu(w, &x),
            Format::Dump => write_dump(w, &x),
            Format::Xyz => write_xyz(w, &x),
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
fn xyz<const D: usize>(bed: &Bed<D>, i: usize) -> [f64; 3] {
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

/// VTK XML unstructured grid: one vertex cell per particle, point data `radius`,
/// `species`, `body`, `coordination`, `id`; field data `box`, `periodic`, `dim`.
fn write_vtu<const D: usize>(w: &mut dyn Write, x: &Export<D>) -> std::io::Result<()> {
    let Export {
        bed,
        coordination,
        box3: b,
    } = *x;
    let n = bed.len();
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    writeln!(w, "<FieldData>")?;
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="box" NumberOfTuples="1" NumberOfComponents="3" format="ascii">{} {} {}</DataArray>"#,
        Num(b[0]),
        Num(b[1]),
        Num(b[2])
    )?;
    writeln!(
        w,
        r#"<DataArray type="Int32" Name="periodic" NumberOfTuples="1" format="ascii">{}</DataArray>"#,
        u8::from(bed.container.periodic)
    )?;
    writeln!(
        w,
        r#"<DataArray type="Int32" Name="dim" NumberOfTuples="1" format="ascii">{D}</DataArray>"#
    )?;
    writeln!(w, "</FieldData>")?;
    writeln!(w, r#"<Piece NumberOfPoints="{n}" NumberOfCells="{n}">"#)?;
    writeln!(w, r#"<PointData Scalars="radius">"#)?;
    let array = |w: &mut dyn Write,
                 ty: &str,
                 name: &str,
                 f: &dyn Fn(usize) -> String|
     -> std::io::Result<()> {
        writeln!(w, r#"<DataArray type="{ty}" Name="{name}" format="ascii">"#)?;
        for i in 0..n {
            writeln!(w, "{}", f(i))?;
        }
        writeln!(w, "</DataArray>")
    };
    array(w, "Float64", "radius", &|i| Num(bed.radii[i]).to_string())?;
    array(w, "Int32", "species", &|i| bed.species[i].to_string())?;
    array(w, "Int32", "body", &|i| bed.bodies[i].to_string())?;
    array(w, "Int32", "coordination", &|i| coordination[i].to_string())?;
    array(w, "Int64", "id", &|i| i.to_string())?;
    writeln!(w, "</PointData>")?;
    writeln!(w, "<Points>")?;
    writeln!(
        w,
        r#"<DataArray type="Float64" NumberOfComponents="3" format="ascii">"#
    )?;
    for i in 0..n {
        let p = xyz(bed, i);
        writeln!(w, "{} {} {}", Num(p[0]), Num(p[1]), Num(p[2]))?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Points>")?;
    writeln!(w, "<Cells>")?;
    array(w, "Int64", "connectivity", &|i| i.to_string())?;
    array(w, "Int64", "offsets", &|i| (i + 1).to_string())?;
    // VTK_VERTEX.
    array(w, "UInt8", "types", &|_| "1".to_string())?;
    writeln!(w, "</Cells>")?;
    writeln!(w, "</Piece>")?;
    writeln!(w, "</UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}

/// The LAMMPS boundary flags: `pp` for periodic axes, `ff` for walls. 2D beds are
/// periodic in the thin z direction, as LAMMPS requires of 2D boxes.
pub fn boundary_flags<const D: usize>(periodic: bool) -> [&'static str; 3] {
    let side = if periodic { "pp" } else { "ff" };
    if D == 2 {
        [side, "ff", "pp"]
    } else {
        [side, side, "ff"]
    }
}

/// LAMMPS dump: `ITEM: ATOMS id type x y z radius mol c_coord`, ids and types
/// 1-based as LAMMPS numbers them (`id = row + 1`, `type = species + 1`,
/// `mol = body + 1`).
fn write_dump<const D: usize>(w: &mut dyn Write, x: &Export<D>) -> std::io::Result<()> {
    let Export {
        bed,
        coordination,
        box3: b,
    } = *x;
    let flags = boundary_flags::<D>(bed.container.periodic);
    writeln!(w, "ITEM: TIMESTEP\n0")?;
    writeln!(w, "ITEM: NUMBER OF ATOMS\n{}", bed.len())?;
    writeln!(w, "ITEM: BOX BOUNDS {} {} {}", flags[0], flags[1], flags[2])?;
    writeln!(w, "0 {}", Num(b[0]))?;
    writeln!(w, "0 {}", Num(b[1]))?;
    if D == 2 {
        writeln!(w, "{} {}", Num(-b[2] / 2.0), Num(b[2] / 2.0))?;
    } else {
        writeln!(w, "0 {}", Num(b[2]))?;
    }
    writeln!(w, "ITEM: ATOMS id type x y z radius mol c_coord")?;
    for i in 0..bed.len() {
        let p = xyz(bed, i);
        writeln!(
            w,
            "{} {} {} {} {} {} {} {}",
            i + 1,
            bed.species[i] + 1,
            Num(p[0]),
            Num(p[1]),
            Num(p[2]),
            Num(bed.radii[i]),
            bed.bodies[i] + 1,
            coordination[i]
        )?;
    }
    Ok(())
}

/// Extended XYZ: a count line, a comment line with `Lattice`, `Origin`,
/// `Properties=species:I:1:pos:R:3:radius:R:1:body:I:1:coordination:I:1`, `pbc`
/// and `dim`, then one line per particle.
fn write_xyz<const D: usize>(w: &mut dyn Write, x: &Export<D>) -> std::io::Result<()> {
    let Export {
        bed,
        coordination,
        box3: b,
    } = *x;
    let p = bed.container.periodic;
    let tf = |x: bool| if x { "T" } else { "F" };
    let (pbc, oz) = if D == 2 {
        (format!("{} F T", tf(p)), -b[2] / 2.0)
    } else {
        (format!("{} {} F", tf(p), tf(p)), 0.0)
    };
    writeln!(w, "{}", bed.len())?;
    writeln!(
        w,
        r#"Lattice="{} 0 0 0 {} 0 0 0 {}" Origin="0 0 {}" Properties=species:I:1:pos:R:3:radius:R:1:body:I:1:coordination:I:1 pbc="{pbc}" dim={D}"#,
        Num(b[0]),
        Num(b[1]),
        Num(b[2]),
        Num(oz)
    )?;
    for i in 0..bed.len() {
        let q = xyz(bed, i);
        writeln!(
            w,
            "{} {} {} {} {} {} {}",
            bed.species[i],
            Num(q[0]),
            Num(q[1]),
            Num(q[2]),
            Num(bed.radii[i]),
            bed.bodies[i],
            coordination[i]
        )?;
    }
    Ok(())
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

    #[test]
    fn flags() {
        assert_eq!(boundary_flags::<3>(true), ["pp", "pp", "ff"]);
        assert_eq!(boundary_flags::<3>(false), ["ff", "ff", "ff"]);
        assert_eq!(boundary_flags::<2>(true), ["pp", "ff", "pp"]);
        assert_eq!(boundary_flags::<2>(false), ["ff", "ff", "pp"]);
    }
}
