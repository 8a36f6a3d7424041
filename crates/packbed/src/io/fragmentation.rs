//! The tables of `packbed fragment`: `bonds.csv` (every bond of the intact bed
//! under load) and `breakage.csv` (the broken bonds in order), with the
//! columns of `docs/reference/fragmentation.md`, "What it writes". Numbers in
//! the shortest exact form, as in the run's tables.

use super::tables::Num;
use crate::mechanics::Fragmentation;
use std::io::{Error, ErrorKind, Write};

const AXES: [&str; 3] = ["x", "y", "z"];

fn finite(v: f64, what: &str, row: usize) -> std::io::Result<String> {
    if v.is_finite() {
        Ok(Num(v).to_string())
    } else {
        Err(Error::new(
            ErrorKind::InvalidData,
            format!("{what} of bond {row} is {v}, not a finite number; refusing to write it"),
        ))
    }
}

fn csv_err(e: csv::Error) -> Error {
    Error::other(e)
}

/// Writes `bonds.csv`: `bond,i,j,wall,px,py[,pz],nx,ny[,nz],fx,fy[,fz],normal,tangential,magnitude`.
pub fn write_bonds<const D: usize>(
    w: &mut dyn Write,
    frag: &Fragmentation<D>,
) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    let mut header = vec!["bond".to_string(), "i".into(), "j".into(), "wall".into()];
    for prefix in ["p", "n", "f"] {
        header.extend(AXES[..D].iter().map(|a| format!("{prefix}{a}")));
    }
    header.extend(["normal", "tangential", "magnitude"].map(String::from));
    out.write_record(&header).map_err(csv_err)?;
    let ids = &frag.bodies.ids;
    for (k, g) in frag.bonds.iter().enumerate() {
        let mut row = vec![
            k.to_string(),
            ids[g.i as usize].to_string(),
            g.j.map(|j| ids[j as usize].to_string()).unwrap_or_default(),
            g.wall.map(|w| w.name().to_string()).unwrap_or_default(),
        ];
        for v in [&g.point, &g.normal, &frag.forces[k]] {
            for a in 0..D {
                row.push(finite(v[a], "a coordinate", k)?);
            }
        }
        row.push(finite(frag.normal(k), "normal", k)?);
        row.push(finite(frag.tangential(k), "tangential", k)?);
        row.push(finite(frag.forces[k].norm(), "magnitude", k)?);
        out.write_record(&row).map_err(csv_err)?;
    }
    out.flush()
}

/// Writes `breakage.csv`: `step,i,j,wall,magnitude,fragments,largest_fragment`.
pub fn write_breakage<const D: usize>(
    w: &mut dyn Write,
    frag: &Fragmentation<D>,
) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    out.write_record([
        "step",
        "i",
        "j",
        "wall",
        "magnitude",
        "fragments",
        "largest_fragment",
    ])
    .map_err(csv_err)?;
    let ids = &frag.bodies.ids;
    for s in &frag.steps {
        let g = &frag.bonds[s.bond];
        out.write_record([
            s.step.to_string(),
            ids[g.i as usize].to_string(),
            g.j.map(|j| ids[j as usize].to_string()).unwrap_or_default(),
            g.wall.map(|w| w.name().to_string()).unwrap_or_default(),
            finite(s.magnitude, "magnitude", s.bond)?,
            s.fragments.to_string(),
            s.largest_fragment.to_string(),
        ])
        .map_err(csv_err)?;
    }
    out.flush()
}
