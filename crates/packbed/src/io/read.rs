//! Readers of bed files.
//!
//! STUB on branch `measures` only: the real readers (packbed particles.csv, plain
//! `x y [z] r`, LAMMPS dump, extended XYZ) come from branch `render`; this minimal
//! version reads packbed's own `particles.csv` and plain `x y [z] r` CSV so that
//! `packbed analyze` can be written and tested against the agreed signature.

use crate::bed::{AnyBed, Bed};
use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use std::path::Path;

/// The box when the file has none: sizes (`W,H` or `W,D,H`) and periodic sides.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BoxHint {
    /// Extents, last one the height; empty: from the file or its `summary.json`.
    pub size: Vec<Real>,
    /// Periodic side boundaries.
    pub periodic: bool,
}

/// Reads a bed file; the box comes from `box_hint`, else from a `summary.json`
/// next to the file (packbed's own output).
pub fn read_bed(path: &Path, box_hint: &BoxHint) -> Result<AnyBed> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let bad = |line: usize, message: String| Error::Data {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut rows: Vec<Vec<Real>> = Vec::new();
    let mut packbed_layout = false;
    let mut width = None;
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        if rows.is_empty() && width.is_none() && fields[0].parse::<Real>().is_err() {
            packbed_layout = fields.first() == Some(&"id");
            width = Some(fields.len());
            continue;
        }
        let mut row = Vec::with_capacity(fields.len());
        for f in &fields {
            let v: Real = f
                .parse()
                .map_err(|_| bad(k + 1, format!("`{f}` is not a number")))?;
            if !v.is_finite() {
                return Err(bad(k + 1, format!("`{f}` is not a finite number")));
            }
            row.push(v);
        }
        if width.is_some_and(|w| w != row.len())
            || rows.first().is_some_and(|r| r.len() != row.len())
        {
            return Err(bad(
                k + 1,
                format!(
                    "{} columns, expected {}",
                    row.len(),
                    width.unwrap_or(rows[0].len())
                ),
            ));
        }
        rows.push(row);
    }
    let cols = rows.first().map_or(width.unwrap_or(0), Vec::len);
    let dim = if packbed_layout { cols - 4 } else { cols - 1 };
    if !(2..=3).contains(&dim) {
        return Err(bad(1, format!("expected x,y[,z],r columns, found {cols}")));
    }
    let (size, periodic) = if box_hint.size.is_empty() {
        summary_box(path, dim)?
    } else {
        (box_hint.size.clone(), box_hint.periodic)
    };
    if size.len() != dim || size.iter().any(|&s| !(s > 0.0 && s.is_finite())) {
        return Err(Error::Impossible(format!(
            "--box needs {dim} positive sizes for this {dim}D bed"
        )));
    }
    Ok(match dim {
        2 => AnyBed::D2(fill::<2>(&rows, packbed_layout, &size, periodic, path)?),
        _ => AnyBed::D3(fill::<3>(&rows, packbed_layout, &size, periodic, path)?),
    })
}

fn fill<const D: usize>(
    rows: &[Vec<Real>],
    packbed_layout: bool,
    size: &[Real],
    periodic: bool,
    path: &Path,
) -> Result<Bed<D>> {
    let mut s = Vector::zero();
    for k in 0..D {
        s[k] = size[k];
    }
    let mut bed = Bed::new(Container { size: s, periodic }, Vec::new());
    for (k, row) in rows.iter().enumerate() {
        let (species, body, xs) = if packbed_layout {
            (row[1] as u32, row[2] as u32, &row[3..])
        } else {
            (0, k as u32, &row[..])
        };
        let mut c = Vector::zero();
        for a in 0..D {
            c[a] = xs[a];
        }
        let r = xs[D];
        if r.is_nan() || r <= 0.0 {
            return Err(Error::Data {
                path: path.to_path_buf(),
                line: k + 2,
                message: format!("radius {r} is not positive"),
            });
        }
        bed.push_bead(c, r, species, body);
    }
    Ok(bed)
}

/// The box recorded in the `summary.json` beside a packbed `particles.csv`.
fn summary_box(path: &Path, dim: usize) -> Result<(Vec<Real>, bool)> {
    let json = path.with_file_name("summary.json");
    let none = || {
        Error::Impossible(format!(
            "{}: the file has no box; give --box (W,H or W,D,H)",
            path.display()
        ))
    };
    let text = std::fs::read_to_string(&json).map_err(|_| none())?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|_| none())?;
    let b = &v["box"];
    let mut size = vec![b["width"].as_f64().ok_or_else(none)?];
    if dim == 3 {
        size.push(b["depth"].as_f64().ok_or_else(none)?);
    }
    size.push(b["height"].as_f64().ok_or_else(none)?);
    Ok((size, b["periodic"].as_bool().unwrap_or(false)))
}
