//! VTK XML unstructured grid, `bed.vtu` (ParaView; read back by `io::read::vtu`).

use super::{position, Export};
use crate::io::tables::Num;
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
        let p = position(bed, i);
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
