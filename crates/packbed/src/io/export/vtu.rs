//! VTK XML unstructured grid, `bed.vtu` (ParaView; read back by `io::read::vtu`).

use super::{position, Export};
use crate::io::tables::{push_int, write_rows, Num};
use std::io::Write;

/// VTK XML unstructured grid: one vertex cell per particle, point data `radius`,
/// `species`, `body`, `coordination`, `id`; field data `box`, `periodic`, `dim`.
pub(super) fn write<const D: usize>(w: &mut dyn Write, x: &Export<D>) -> std::io::Result<()> {
    let (bed, coordination, b) = (x.bed, x.coordination, x.box3);
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
                 f: &(dyn Fn(&mut Vec<u8>, usize) + Sync)|
     -> std::io::Result<()> {
        writeln!(w, r#"<DataArray type="{ty}" Name="{name}" format="ascii">"#)?;
        write_rows(w, n, |w, i| {
            f(w, i);
            w.push(b'\n');
            Ok(())
        })?;
        writeln!(w, "</DataArray>")
    };
    array(w, "Float64", "radius", &|w, i| Num(bed.radii[i]).push_to(w))?;
    array(w, "Int32", "species", &|w, i| push_int(w, bed.species[i]))?;
    array(w, "Int32", "body", &|w, i| push_int(w, bed.bodies[i]))?;
    array(w, "Int32", "coordination", &|w, i| {
        push_int(w, coordination[i])
    })?;
    array(w, "Int64", "id", &|w, i| push_int(w, i))?;
    writeln!(w, "</PointData>")?;
    writeln!(w, "<Points>")?;
    writeln!(
        w,
        r#"<DataArray type="Float64" NumberOfComponents="3" format="ascii">"#
    )?;
    write_rows(w, n, |w, i| {
        let p = position(bed, i);
        for (k, v) in p.into_iter().enumerate() {
            if k > 0 {
                w.push(b' ');
            }
            Num(v).push_to(w);
        }
        w.push(b'\n');
        Ok(())
    })?;
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Points>")?;
    writeln!(w, "<Cells>")?;
    array(w, "Int64", "connectivity", &|w, i| push_int(w, i))?;
    array(w, "Int64", "offsets", &|w, i| push_int(w, i + 1))?;
    // VTK_VERTEX.
    array(w, "UInt8", "types", &|w, _| w.push(b'1'))?;
    writeln!(w, "</Cells>")?;
    writeln!(w, "</Piece>")?;
    writeln!(w, "</UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}
