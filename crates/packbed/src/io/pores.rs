//! The pore network's files: `pores.csv`, `throats.csv` and `network.vtp`
//! (VTK polydata for ParaView: pores as points with their pressure, throats as
//! lines with their flux). Numbers as in [`super::tables`]: the shortest text
//! that reads back to the same bits.

use super::tables::{push_int, write_rows, Num};
use crate::analysis::pores::{Column, PoreTables};
use std::io::Write;

/// The network's file names, in writing order.
pub const PORE_FILES: [&str; 3] = ["pores.csv", "throats.csv", "network.vtp"];

/// [`super::tables`]'s check of a number, as the text to write.
fn finite(v: f64, what: &str, id: usize) -> std::io::Result<Num> {
    super::tables::finite(v, what, id).map(Num)
}

/// Writes columns as CSV.
fn write_columns(w: &mut dyn Write, columns: &[(String, Column)]) -> std::io::Result<()> {
    let names: Vec<&str> = columns.iter().map(|c| c.0.as_str()).collect();
    writeln!(w, "{}", names.join(","))?;
    let rows = columns.first().map_or(0, |c| c.1.len());
    write_rows(w, rows, |w, row| {
        for (k, (name, column)) in columns.iter().enumerate() {
            if k > 0 {
                w.push(b',');
            }
            match column {
                Column::Int(v) => push_int(w, v[row]),
                Column::Float(v) => finite(v[row], name, row)?.push_to(w),
            }
        }
        w.push(b'\n');
        Ok(())
    })
}

/// Writes `pores.csv`: `id`, the vertices' particle ids `v0…`, on periodic
/// beds their image shifts (`v0_sx`, `v0_sy`: periods along x and y), the
/// power centre, volume, void volume, body radius, `in_slab` (1 for the pores
/// of the flow region) and the pressure under each solved axis' unit gradient.
pub fn write_pores(w: &mut dyn Write, t: &PoreTables) -> std::io::Result<()> {
    write_columns(w, &t.pore_columns())
}

/// Writes `throats.csv`: `id,pore_a,pore_b`, on periodic beds the periods
/// pore b's image lies across (`sx`, `sy`), the constriction radius, the
/// conductance and the flux from a to b under each solved axis.
pub fn write_throats(w: &mut dyn Write, t: &PoreTables) -> std::io::Result<()> {
    write_columns(w, &t.throat_columns())
}

/// Writes `network.vtp`: VTK XML polydata (ASCII). Pores are points (`z = 0`
/// in 2D) with body radius, void volume and pressures; throats are lines with
/// constriction radius, conductance and fluxes. A throat to a periodic image
/// would cross the box: it ends at a copy of the pore at the image's place.
pub fn write_network_vtp(w: &mut dyn Write, t: &PoreTables, size: &[f64]) -> std::io::Result<()> {
    // Copies of pores for the throats that cross a periodic side.
    let mut extra: Vec<(usize, [f64; 3])> = Vec::new();
    let mut ends: Vec<(usize, usize)> = Vec::with_capacity(t.throats.len());
    let at = |p: usize| -> [f64; 3] {
        let c = &t.pores[p].centre;
        [c[0], c[1], if t.dim == 3 { c[2] } else { 0.0 }]
    };
    for th in &t.throats {
        let (a, b) = (th.pores[0] as usize, th.pores[1] as usize);
        if th.shift == [0, 0] {
            ends.push((a, b));
        } else {
            let mut p = at(b);
            for k in 0..t.dim - 1 {
                p[k] += f64::from(th.shift[k]) * size[k];
            }
            extra.push((b, p));
            ends.push((a, t.pores.len() + extra.len() - 1));
        }
    }
    let n_points = t.pores.len() + extra.len();
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "<PolyData>")?;
    writeln!(
        w,
        "<Piece NumberOfPoints=\"{n_points}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
        ends.len()
    )?;
    writeln!(w, "<Points>")?;
    writeln!(
        w,
        "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    )?;
    write_rows(w, n_points, |w, i| {
        let (p, c) = if i < t.pores.len() {
            (i, at(i))
        } else {
            extra[i - t.pores.len()]
        };
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            if k > 0 {
                w.push(b' ');
            }
            finite(c[k], axis, p)?.push_to(w);
        }
        w.push(b'\n');
        Ok(())
    })?;
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Points>")?;
    // Point data: a copy carries its pore's values.
    let pore_of = |i: usize| {
        if i < t.pores.len() {
            i
        } else {
            extra[i - t.pores.len()].0
        }
    };
    writeln!(w, "<PointData>")?;
    let point_array =
        |w: &mut dyn Write, name: &str, f: &(dyn Fn(usize) -> f64 + Sync)| -> std::io::Result<()> {
            writeln!(
                w,
                "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
            )?;
            write_rows(w, n_points, |w, i| {
                finite(f(pore_of(i)), name, i)?.push_to(w);
                w.push(b'\n');
                Ok(())
            })?;
            writeln!(w, "</DataArray>")
        };
    point_array(w, "body_radius", &|p| t.pores[p].body_radius)?;
    point_array(w, "void_volume", &|p| t.pores[p].void_volume)?;
    point_array(w, "in_slab", &|p| f64::from(u8::from(t.pores[p].in_slab)))?;
    for (k, axis) in t.axes.iter().enumerate() {
        point_array(w, &format!("pressure_{axis}"), &|p| t.pores[p].pressure[k])?;
    }
    if let Some(liquid) = &t.liquid {
        // The drainage's state: 0 off the slab, 1 drained, 2 filled, 3 trapped.
        point_array(w, "liquid_state", &|p| match liquid[p].0 {
            crate::analysis::pores::drainage::PoreState::Outside => 0.0,
            crate::analysis::pores::drainage::PoreState::Drained => 1.0,
            crate::analysis::pores::drainage::PoreState::Filled => 2.0,
            crate::analysis::pores::drainage::PoreState::Trapped => 3.0,
        })?;
        point_array(w, "cluster", &|p| liquid[p].1 as f64)?;
        point_array(w, "liquid", &|p| liquid[p].2)?;
    }
    writeln!(w, "</PointData>")?;
    writeln!(w, "<CellData>")?;
    let line_array =
        |w: &mut dyn Write, name: &str, f: &(dyn Fn(usize) -> f64 + Sync)| -> std::io::Result<()> {
            writeln!(
                w,
                "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
            )?;
            write_rows(w, t.throats.len(), |w, i| {
                finite(f(i), name, i)?.push_to(w);
                w.push(b'\n');
                Ok(())
            })?;
            writeln!(w, "</DataArray>")
        };
    line_array(w, "constriction_radius", &|i| {
        t.throats[i].constriction_radius
    })?;
    line_array(w, "conductance", &|i| t.throats[i].conductance)?;
    for (k, axis) in t.axes.iter().enumerate() {
        line_array(w, &format!("flux_{axis}"), &|i| t.throats[i].flux[k])?;
    }
    writeln!(w, "</CellData>")?;
    writeln!(w, "<Lines>")?;
    writeln!(
        w,
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    )?;
    write_rows(w, ends.len(), |w, i| {
        push_int(w, ends[i].0);
        w.push(b' ');
        push_int(w, ends[i].1);
        w.push(b'\n');
        Ok(())
    })?;
    writeln!(w, "</DataArray>")?;
    writeln!(
        w,
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    )?;
    write_rows(w, ends.len(), |w, i| {
        push_int(w, 2 * (i + 1));
        w.push(b'\n');
        Ok(())
    })?;
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Lines>")?;
    writeln!(w, "</Piece>")?;
    writeln!(w, "</PolyData>")?;
    writeln!(w, "</VTKFile>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::pores::{PoreRow, ThroatRow};

    fn tables() -> PoreTables {
        let pore = |x: f64| PoreRow {
            particles: [0, 1, 2, 3],
            images: [[0, 0], [1, 0], [0, 0], [0, -1]],
            centre: [x, 1.0, 2.0],
            volume: 1.5,
            void_volume: 0.5,
            body_radius: 0.25,
            in_slab: true,
            pressure: [-x, 0.0, 0.0],
        };
        PoreTables {
            dim: 3,
            periodic: true,
            axes: vec!["x"],
            pores: vec![pore(1.0), pore(9.0)],
            throats: vec![
                ThroatRow {
                    pores: [0, 1],
                    shift: [0, 0],
                    constriction_radius: 0.1,
                    conductance: 2.0,
                    flux: [3.0, 0.0, 0.0],
                },
                ThroatRow {
                    pores: [0, 1],
                    shift: [-1, 0],
                    constriction_radius: 0.2,
                    conductance: 1.0,
                    flux: [-0.5, 0.0, 0.0],
                },
            ],
            liquid: None,
        }
    }

    fn text(f: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> String {
        let mut buf = Vec::new();
        f(&mut buf).unwrap();
        String::from_utf8(buf).unwrap()
    }

    #[test]
    fn tables_have_their_columns() {
        let t = tables();
        let pores = text(|w| write_pores(w, &t));
        let mut lines = pores.lines();
        assert_eq!(
            lines.next().unwrap(),
            "id,v0,v1,v2,v3,v0_sx,v0_sy,v1_sx,v1_sy,v2_sx,v2_sy,v3_sx,v3_sy,x,y,z,volume,void_volume,body_radius,in_slab,pressure_x"
        );
        assert_eq!(
            lines.next().unwrap(),
            "0,0,1,2,3,0,0,1,0,0,0,0,-1,1,1,2,1.5,0.5,0.25,1,-1"
        );
        let throats = text(|w| write_throats(w, &t));
        let mut lines = throats.lines();
        assert_eq!(
            lines.next().unwrap(),
            "id,pore_a,pore_b,sx,sy,constriction_radius,conductance,flux_x"
        );
        assert_eq!(lines.nth(1).unwrap(), "1,0,1,-1,0,0.2,1,-0.5");
    }

    #[test]
    fn a_throat_across_the_side_ends_at_a_copy() {
        let t = tables();
        let vtp = text(|w| write_network_vtp(w, &t, &[10.0, 10.0, 20.0]));
        assert!(vtp.contains("NumberOfPoints=\"3\""));
        // The copy of pore 1 one period to the left.
        assert!(vtp.contains("\n-1 1 2\n"));
        assert!(vtp.contains("\n0 2\n"));
        assert!(vtp.contains("Name=\"pressure_x\""));
        // Well-formed enough for an XML reader: every DataArray closed.
        assert_eq!(
            vtp.matches("<DataArray").count(),
            vtp.matches("</DataArray>").count()
        );
    }

    #[test]
    fn nan_is_refused() {
        let mut t = tables();
        t.pores[1].void_volume = f64::NAN;
        let mut buf = Vec::new();
        let e = write_pores(&mut buf, &t).unwrap_err();
        assert!(e.to_string().contains("void_volume of row 1"), "{e}");
    }
}
