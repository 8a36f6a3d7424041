//! Readers of bed files: packbed's `particles.csv` (box from the `summary.json`
//! beside it), plain CSV or whitespace `x y [z] r` tables with or without a
//! header, LAMMPS dumps, extended XYZ and packbed's own `bed.vtu`.
//!
//! One entry point, [`read_bed`]: the format is recognised from the content
//! (and the extension for VTK), the dimension from the columns or box. The box
//! comes from the file where it has one, else from the caller's [`BoxHint`].
//! Every problem is an [`Error::Data`] naming the file and the 1-based line.

// `!(x > 0.0)` is how NaN is refused along with the non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::bed::{AnyBed, Bed};

/// One atom of a LAMMPS dump: id, position, radius, type, molecule, line.
type DumpRow = (u64, [Real; 3], Real, u32, Option<u32>, usize);
use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use crate::species::{Shape, SizeDist, Species};
use std::path::Path;

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
}

impl BoxSource {
    /// How `summary.json` and the screen name it.
    pub fn name(&self) -> &'static str {
        match self {
            BoxSource::Given => "options",
            BoxSource::File => "file",
            BoxSource::SummaryBeside => "summary.json",
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

/// Reads a bed file. `box_hint` is used when the file carries no box (plain
/// tables; `particles.csv` without a `summary.json` beside it).
pub fn read_bed(path: &Path, box_hint: Option<&BoxHint>) -> Result<AnyBed> {
    read_bed_report(path, box_hint).map(|(bed, _)| bed)
}

/// [`read_bed`], also telling where the box came from. A given `box_hint` wins
/// over a box in the file (or in the `summary.json` beside it).
pub fn read_bed_report(path: &Path, box_hint: Option<&BoxHint>) -> Result<(AnyBed, ReadReport)> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    let r = Reader { path };
    let first = text
        .lines()
        .enumerate()
        .find(|(_, l)| !l.trim().is_empty())
        .map(|(k, l)| (k, l.trim().to_string()));
    let Some((first_line, first)) = first else {
        return Err(r.err(1, "the file is empty"));
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let raw = if first.starts_with("ITEM:") {
        r.dump(&text)?
    } else if first.starts_with("<?xml") || first.starts_with("<VTKFile") || ext == "vtu" {
        r.vtu(&text)?
    } else if first.parse::<u64>().is_ok()
        && text
            .lines()
            .nth(first_line + 1)
            .is_some_and(|l| l.contains('='))
    {
        r.xyz(&text, first_line)?
    } else {
        r.table(&text, box_hint)?
    };
    r.finish(raw, box_hint)
}

/// Particles as read, before the dimension is fixed.
struct Raw {
    dim: usize,
    /// Positions with three components (z unused in 2D).
    pos: Vec<[Real; 3]>,
    radii: Vec<Real>,
    species: Vec<u32>,
    bodies: Vec<u32>,
    /// Line of each particle, for error messages.
    lines: Vec<usize>,
    /// Box extents (`dim` of them) and periodic flag, if the file has them.
    size: Option<(Vec<Real>, bool)>,
    /// Box origin, subtracted from the positions (packbed's box starts at 0).
    origin: [Real; 3],
    /// Where `size` came from, when set.
    box_source: BoxSource,
    species_info: Vec<Species>,
}

impl Raw {
    fn new(dim: usize) -> Raw {
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

struct Reader<'a> {
    path: &'a Path,
}

impl Reader<'_> {
    fn err(&self, line: usize, message: impl Into<String>) -> Error {
        Error::Data {
            path: self.path.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    fn num(&self, line: usize, what: &str, s: &str) -> Result<Real> {
        let v: Real = s
            .parse()
            .map_err(|_| self.err(line, format!("{what}: \"{s}\" is not a number")))?;
        if !v.is_finite() {
            return Err(self.err(line, format!("{what} is {s}, not a finite number")));
        }
        Ok(v)
    }

    fn int(&self, line: usize, what: &str, s: &str) -> Result<u32> {
        s.parse().map_err(|_| {
            self.err(
                line,
                format!("{what}: \"{s}\" is not a whole number >= 0 (up to 4294967295)"),
            )
        })
    }

    /// The common checks, then the bed in its dimension.
    fn finish(&self, mut raw: Raw, hint: Option<&BoxHint>) -> Result<(AnyBed, ReadReport)> {
        if raw.pos.is_empty() {
            return Err(self.err(1, "no particles in the file"));
        }
        for (k, &r) in raw.radii.iter().enumerate() {
            if !(r > 0.0) {
                return Err(self.err(raw.lines[k], format!("radius {r} must be > 0")));
            }
        }
        let file_box = raw.size.take();
        let (size, periodic, box_source) = match (hint, file_box) {
            (Some(h), _) => {
                if h.size.len() != raw.dim {
                    return Err(self.err(
                        1,
                        format!(
                            "the particles are {}D but the box given has {} extents",
                            raw.dim,
                            h.size.len()
                        ),
                    ));
                }
                (h.size.clone(), h.periodic, BoxSource::Given)
            }
            (None, Some((s, p))) => (s, p, raw.box_source),
            (None, None) => {
                return Err(self.err(
                    1,
                    format!(
                        "the file has no box; give one ({})",
                        if raw.dim == 2 {
                            "--box W,H"
                        } else {
                            "--box W,D,H"
                        }
                    ),
                ))
            }
        };
        if size.iter().any(|&s| !(s > 0.0 && s.is_finite())) {
            return Err(self.err(1, format!("box extents {size:?} must be finite and > 0")));
        }
        let r_min = raw.radii.iter().copied().fold(Real::INFINITY, Real::min);
        let longest = (raw.radii.iter().chain(&size))
            .chain(raw.pos.iter().flatten())
            .fold(0.0, |m: Real, x| m.max(x.abs()));
        if let Some(why) = crate::config::length_scale_problem(r_min, longest) {
            return Err(self.err(1, format!("radii, box and positions: {why}")));
        }
        // As `run` refuses a box narrower than its largest particle: such a bed
        // has no packing fraction (a radius of 1e300 overflowed every volume).
        let narrowest = size.iter().copied().fold(Real::INFINITY, Real::min);
        if let Some(k) = (0..raw.radii.len()).find(|&k| 2.0 * raw.radii[k] > narrowest) {
            return Err(self.err(
                raw.lines[k],
                format!(
                    "radius {:?} is larger than the box: its diameter exceeds the box extent \
                     {narrowest:?}",
                    raw.radii[k]
                ),
            ));
        }
        for p in raw.pos.iter_mut() {
            for k in 0..3 {
                p[k] -= raw.origin[k];
            }
        }
        let wrapped = self.check_inside(&mut raw, &size, periodic, box_source)?;
        self.check_crowding(&raw)?;
        let bed = match raw.dim {
            2 => AnyBed::D2(build::<2>(&raw, &size, periodic)),
            _ => AnyBed::D3(build::<3>(&raw, &size, periodic)),
        };
        Ok((
            bed,
            ReadReport {
                box_source,
                wrapped,
            },
        ))
    }

    /// Refuses particles sticking out of the box by more than [`OUTSIDE_TOL`] of
    /// their radius, through the floor, a side wall or (for a walled box given
    /// by the caller) the roof; wraps centres into `[0, W)` along periodic axes
    /// and returns how many it moved.
    ///
    /// The height of a box read from a file is not taken as a roof: packbed's
    /// own beds filled by count rise above their roof (the roof is ignored
    /// there, and the analysis takes the box up to the highest top), and so do
    /// their exports. A box the user gives is a statement about the bed.
    fn check_inside(
        &self,
        raw: &mut Raw,
        size: &[Real],
        periodic: bool,
        source: BoxSource,
    ) -> Result<u64> {
        let d = raw.dim;
        let v = d - 1;
        let roof = !periodic && source == BoxSource::Given;
        let mut wrapped = 0u64;
        let mut outside = 0u64;
        let mut first: Option<(usize, String)> = None;
        const AXES: [&str; 3] = ["x", "y", "z"];
        for k in 0..raw.pos.len() {
            let r = raw.radii[k];
            let tol = OUTSIDE_TOL * r;
            let p = &mut raw.pos[k];
            let mut out: Option<(&str, Real)> = None;
            for a in 0..v {
                let w = size[a];
                if periodic {
                    if !(0.0..w).contains(&p[a]) {
                        let mut x = p[a].rem_euclid(w);
                        // A tiny negative centre rounds to w itself.
                        if x >= w {
                            x = 0.0;
                        }
                        p[a] = x;
                        wrapped += 1;
                    }
                } else if p[a] - r < -tol {
                    out = out.or(Some((["wall x0", "wall y0"][a], r - p[a])));
                } else if p[a] + r > w + tol {
                    out = out.or(Some((["wall x1", "wall y1"][a], p[a] + r - w)));
                }
            }
            if p[v] - r < -tol {
                out = out.or(Some(("floor", r - p[v])));
            } else if roof && p[v] + r > size[v] + tol {
                out = out.or(Some(("roof", p[v] + r - size[v])));
            }
            if let Some((wall, by)) = out {
                outside += 1;
                if first.is_none() {
                    let at: Vec<String> = (0..d).map(|a| format!("{} {}", AXES[a], p[a])).collect();
                    first = Some((
                        raw.lines[k],
                        format!(
                            "the first ({}, r {r}) through the {wall} by {:.3} of its radius",
                            at.join(", "),
                            by / r
                        ),
                    ));
                }
            }
        }
        if let Some((line, what)) = first {
            let extents: Vec<String> = size.iter().map(|x| x.to_string()).collect();
            return Err(self.err(
                line,
                format!(
                    "{outside} particle{} stick{} out of the {} box {} (from the {}) by more \
                     than {} % of the radius; {what}",
                    if outside == 1 { "" } else { "s" },
                    if outside == 1 { "s" } else { "" },
                    if periodic { "periodic" } else { "walled" },
                    extents.join(" x "),
                    source.name(),
                    OUTSIDE_TOL * 100.0,
                ),
            ));
        }
        Ok(wrapped)
    }

    /// Refuses a file whose particles sit far more densely than any packing can:
    /// thousands of copies of one particle, say, from a broken export. Each
    /// contact would be listed and every measure would crawl through a graph of
    /// n² links (20,000 copies took minutes and gigabytes before being
    /// stopped). Balls of radius at least `r_min` whose centres lie in a cube of
    /// side `w` fit in the cube grown by `r_min` on every side, so at most
    /// `(w + 2 r_min)^d / V(r_min)` of them fit without overlapping; a cube
    /// holding `CROWDING` times that many is refused. That leaves room for soft
    /// particles overlapping a lot and for the overlapping beads of rods.
    fn check_crowding(&self, raw: &Raw) -> Result<()> {
        const CROWDING: Real = 64.0;
        let d = raw.dim;
        let r_min = raw.radii.iter().copied().fold(Real::INFINITY, Real::min);
        let r_max = raw.radii.iter().copied().fold(0.0, Real::max);
        let w = 2.0 * r_max;
        let ball = if d == 2 {
            crate::math::ball_volume::<2>(r_min)
        } else {
            crate::math::ball_volume::<3>(r_min)
        };
        let fit = (w + 2.0 * r_min).powi(d as i32) / ball;
        let cap = (CROWDING * fit).ceil();
        if !(cap.is_finite() && (raw.pos.len() as Real) > cap) {
            return Ok(());
        }
        // Bodies per cell of side `w`, counted by sorting. Bodies, not beads:
        // the beads of one rod overlap by design (spacing below 2 radii), but
        // each body holds a ball of radius `r_min` of its own.
        let mut cells: Vec<([i64; 3], u32, usize)> = raw
            .pos
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let cell = std::array::from_fn(|a| (p[a] / w).floor() as i64);
                (cell, raw.bodies[k], k)
            })
            .collect();
        cells.sort_unstable();
        for run in cells.chunk_by(|a, b| a.0 == b.0) {
            let bodies = 1 + run.windows(2).filter(|p| p[0].1 != p[1].1).count();
            if bodies as Real > cap {
                let first = run.iter().map(|c| c.2).min().unwrap_or(0);
                return Err(self.err(
                    raw.lines[first],
                    format!(
                        "{bodies} particles (bodies) have their centres within one cube of side \
                         {w} (twice the largest radius), far more than fit there without \
                         overlapping (about {:.0}): duplicated or mis-scaled particles? This is \
                         not a packed bed",
                        fit
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Plain CSV or whitespace table, or packbed's `particles.csv`.
    fn table(&self, text: &str, hint: Option<&BoxHint>) -> Result<Raw> {
        let mut rows = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let split = |l: &str| -> Vec<String> {
            if l.contains(',') {
                l.split(',').map(|s| s.trim().to_string()).collect()
            } else {
                l.split_whitespace().map(str::to_string).collect()
            }
        };
        let Some((first_no, first)) = rows.next() else {
            return Err(self.err(1, "the file has no data (only comments or blank lines)"));
        };
        let first_cells = split(first);
        let has_header = first_cells.iter().any(|c| c.parse::<f64>().is_err());
        let columns: Vec<String> = if has_header {
            first_cells
                .iter()
                .map(|c| c.trim_matches('"').to_ascii_lowercase())
                .collect()
        } else {
            match (first_cells.len(), hint.map(|h| h.size.len())) {
                (3, _) => ["x", "y", "r"].map(String::from).to_vec(),
                (4, _) => ["x", "y", "z", "r"].map(String::from).to_vec(),
                (n, _) => {
                    return Err(self.err(
                        first_no,
                        format!(
                            "{n} columns without a header: expected x y r (2D) or x y z r (3D)"
                        ),
                    ))
                }
            }
        };
        let find = |names: &[&str]| columns.iter().position(|c| names.contains(&c.as_str()));
        let (Some(ix), Some(iy)) = (find(&["x"]), find(&["y"])) else {
            return Err(self.err(first_no, "the header needs columns x and y"));
        };
        let iz = find(&["z"]);
        let Some(ir) = find(&["r", "radius"]) else {
            return Err(self.err(first_no, "the header needs a radius column (r or radius)"));
        };
        let isp = find(&["species", "type"]);
        let ibody = find(&["body", "mol"]);
        let packbed_csv = has_header
            && columns.first().map(String::as_str) == Some("id")
            && isp.is_some()
            && ibody.is_some();
        let dim = if iz.is_some() { 3 } else { 2 };
        let mut raw = Raw::new(dim);
        let data: Box<dyn Iterator<Item = (usize, &str)>> = if has_header {
            Box::new(rows)
        } else {
            Box::new(std::iter::once((first_no, first)).chain(rows))
        };
        for (line, l) in data {
            let cells = split(l);
            if cells.len() != columns.len() {
                return Err(self.err(
                    line,
                    format!(
                        "{} columns, expected {} ({})",
                        cells.len(),
                        columns.len(),
                        columns.join(",")
                    ),
                ));
            }
            let z = match iz {
                Some(i) => self.num(line, "z", &cells[i])?,
                None => 0.0,
            };
            raw.pos.push([
                self.num(line, "x", &cells[ix])?,
                self.num(line, "y", &cells[iy])?,
                z,
            ]);
            raw.radii.push(self.num(line, &columns[ir], &cells[ir])?);
            raw.species.push(match isp {
                Some(i) => self.int(line, &columns[i], &cells[i])?,
                None => 0,
            });
            let n = raw.bodies.len() as u32;
            raw.bodies.push(match ibody {
                Some(i) => self.int(line, &columns[i], &cells[i])?,
                None => n,
            });
            raw.lines.push(line);
        }
        if packbed_csv {
            self.summary_beside(&mut raw)?;
        }
        Ok(raw)
    }

    /// Box and species names from the `summary.json` beside a `particles.csv`.
    fn summary_beside(&self, raw: &mut Raw) -> Result<()> {
        let Some(path) = self.path.parent().map(|d| d.join("summary.json")) else {
            return Ok(());
        };
        let Ok(text) = std::fs::read_to_string(&path) else {
            return Ok(());
        };
        let bad = |m: String| Error::Data {
            path: path.clone(),
            line: 1,
            message: m,
        };
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| bad(format!("not valid JSON: {e}")))?;
        let get = |k: &str| v.get("box").and_then(|b| b.get(k)).and_then(|x| x.as_f64());
        let (Some(w), Some(h)) = (get("width"), get("height")) else {
            return Err(bad("box.width and box.height are missing".into()));
        };
        let periodic = v
            .get("box")
            .and_then(|b| b.get("periodic"))
            .and_then(|p| p.as_bool())
            .unwrap_or(false);
        let size = if raw.dim == 3 {
            let d = get("depth").ok_or_else(|| bad("box.depth is missing for a 3D bed".into()))?;
            vec![w, d, h]
        } else {
            vec![w, h]
        };
        raw.size = Some((size, periodic));
        raw.box_source = BoxSource::SummaryBeside;
        if let Some(list) = v.get("species").and_then(|s| s.as_array()) {
            for (k, s) in list.iter().enumerate() {
                let name = s
                    .get("name")
                    .and_then(|n| n.as_str())
                    .unwrap_or("")
                    .to_string();
                let shape_text = s.get("shape").and_then(|n| n.as_str()).unwrap_or("");
                let shape = parse_chain(shape_text).unwrap_or(Shape::Sphere);
                let r = mean_radius(raw, k as u32);
                raw.species_info.push(Species {
                    name,
                    shape,
                    size: SizeDist::Fixed(r),
                    ratio: s.get("ratio").and_then(|x| x.as_f64()).unwrap_or(1.0),
                });
            }
        }
        Ok(())
    }

    /// LAMMPS dump (first snapshot): box bounds with boundary flags, and columns
    /// by name (`x y z` or scaled `xs ys zs`, `radius` or `diameter`, `type`, `mol`).
    fn dump(&self, text: &str) -> Result<Raw> {
        let lines: Vec<&str> = text.lines().collect();
        let mut k = 0;
        let mut count: Option<u64> = None;
        let mut bounds: Vec<(Real, Real)> = Vec::new();
        let mut flags: Vec<String> = Vec::new();
        while k < lines.len() {
            let l = lines[k].trim();
            let no = k + 1;
            if let Some(rest) = l.strip_prefix("ITEM: NUMBER OF ATOMS") {
                let _ = rest;
                let s = lines.get(k + 1).map(|s| s.trim()).unwrap_or("");
                let n: u64 = s.parse().map_err(|_| {
                    self.err(
                        no + 1,
                        format!("number of atoms \"{s}\" is not a whole number"),
                    )
                })?;
                if n > MAX_PARTICLES {
                    return Err(self.err(
                        no + 1,
                        format!("{n} atoms is more than packbed reads ({MAX_PARTICLES})"),
                    ));
                }
                count = Some(n);
                k += 2;
            } else if let Some(rest) = l.strip_prefix("ITEM: BOX BOUNDS") {
                flags = rest.split_whitespace().map(str::to_string).collect();
                if flags
                    .iter()
                    .any(|f| ["xy", "xz", "yz"].contains(&f.as_str()))
                {
                    return Err(self.err(
                        no,
                        "triclinic boxes are not supported (packbed boxes are rectangular)",
                    ));
                }
                for j in 1..=3 {
                    let s = lines.get(k + j).copied().unwrap_or("");
                    let v: Vec<&str> = s.split_whitespace().collect();
                    if v.len() < 2 {
                        return Err(self.err(no + j, "box bounds need two numbers: lo hi"));
                    }
                    bounds.push((
                        self.num(no + j, "box lo", v[0])?,
                        self.num(no + j, "box hi", v[1])?,
                    ));
                }
                k += 4;
            } else if let Some(rest) = l.strip_prefix("ITEM: ATOMS") {
                let cols: Vec<&str> = rest.split_whitespace().collect();
                let Some(n) = count else {
                    return Err(self.err(no, "ITEM: ATOMS before ITEM: NUMBER OF ATOMS"));
                };
                if bounds.len() != 3 {
                    return Err(self.err(no, "ITEM: ATOMS before ITEM: BOX BOUNDS"));
                }
                return self.dump_atoms(&lines, k + 1, &cols, n as usize, &bounds, &flags);
            } else {
                k += 1;
            }
        }
        Err(self.err(lines.len().max(1), "no ITEM: ATOMS section"))
    }

    fn dump_atoms(
        &self,
        lines: &[&str],
        start: usize,
        cols: &[&str],
        n: usize,
        bounds: &[(Real, Real)],
        flags: &[String],
    ) -> Result<Raw> {
        let header = start;
        let find = |names: &[&str]| cols.iter().position(|c| names.contains(c));
        let scaled = find(&["x"]).is_none() && find(&["xs"]).is_some();
        let (ix, iy, iz) = if scaled {
            (find(&["xs"]), find(&["ys"]), find(&["zs"]))
        } else {
            (find(&["x", "xu"]), find(&["y", "yu"]), find(&["z", "zu"]))
        };
        let (Some(ix), Some(iy), Some(iz)) = (ix, iy, iz) else {
            return Err(self.err(header, "ITEM: ATOMS needs columns x y z (or xs ys zs)"));
        };
        let ir = find(&["radius"]);
        let id = find(&["diameter"]);
        if ir.is_none() && id.is_none() {
            return Err(self.err(header, "ITEM: ATOMS needs a radius (or diameter) column"));
        }
        let itype = find(&["type"]);
        let imol = find(&["mol"]);
        let iid = find(&["id"]);
        let mut rows: Vec<DumpRow> = Vec::with_capacity(n.min(1 << 24));
        for j in 0..n {
            let no = start + j + 1;
            let Some(l) = lines.get(start + j) else {
                return Err(self.err(no, format!("the file ends after {j} of {n} atoms")));
            };
            if l.starts_with("ITEM:") {
                return Err(self.err(no, format!("only {j} atom lines, the header says {n}")));
            }
            let v: Vec<&str> = l.split_whitespace().collect();
            if v.len() != cols.len() {
                return Err(self.err(no, format!("{} columns, expected {}", v.len(), cols.len())));
            }
            let mut p = [
                self.num(no, cols[ix], v[ix])?,
                self.num(no, cols[iy], v[iy])?,
                self.num(no, cols[iz], v[iz])?,
            ];
            if scaled {
                for a in 0..3 {
                    p[a] = bounds[a].0 + p[a] * (bounds[a].1 - bounds[a].0);
                }
            }
            let r = match (ir, id) {
                (Some(i), _) => self.num(no, "radius", v[i])?,
                (None, Some(i)) => self.num(no, "diameter", v[i])? / 2.0,
                _ => unreachable!("checked above"),
            };
            let ty = match itype {
                Some(i) => self.int(no, "type", v[i])?.saturating_sub(1),
                None => 0,
            };
            let mol = match imol {
                Some(i) => Some(self.int(no, "mol", v[i])?.saturating_sub(1)),
                None => None,
            };
            let key = match iid {
                Some(i) => self.int(no, "id", v[i])? as u64,
                None => j as u64,
            };
            rows.push((key, p, r, ty, mol, no));
        }
        // A count below the rows would silently cut the bed short: the snapshot
        // ends at the next ITEM (a new snapshot) or at the end of the file.
        let extra = lines[(start + n).min(lines.len())..]
            .iter()
            .take_while(|l| !l.trim_start().starts_with("ITEM:"))
            .filter(|l| !l.trim().is_empty())
            .count();
        if extra > 0 {
            return Err(self.err(
                start + n + 1,
                format!(
                    "{} atom lines, but ITEM: NUMBER OF ATOMS says {n}",
                    n + extra
                ),
            ));
        }
        // Dumps are often written in id-scrambled order: restore id order.
        rows.sort_by_key(|r| r.0);
        let flag = |a: usize| flags.get(a).map(String::as_str).unwrap_or("ff");
        let thin2d = flag(2) == "pp" && rows.iter().all(|r| r.1[2] == 0.0);
        let dim = if thin2d { 2 } else { 3 };
        let mut raw = Raw::new(dim);
        for (j, (_, p, r, ty, mol, no)) in rows.into_iter().enumerate() {
            raw.pos.push(p);
            raw.radii.push(r);
            raw.species.push(ty);
            raw.bodies.push(mol.unwrap_or(j as u32));
            raw.lines.push(no);
        }
        let periodic = flag(0).starts_with('p');
        raw.origin = [
            bounds[0].0,
            bounds[1].0,
            if dim == 2 { 0.0 } else { bounds[2].0 },
        ];
        let ext: Vec<Real> = (0..dim).map(|a| bounds[a].1 - bounds[a].0).collect();
        raw.size = Some((ext, periodic));
        Ok(raw)
    }

    /// Extended XYZ (first frame): `Lattice` (orthogonal), `Origin`, `pbc`,
    /// `Properties` with `pos:R:3` and `radius:R:1` (species and body optional).
    fn xyz(&self, text: &str, first: usize) -> Result<Raw> {
        let lines: Vec<&str> = text.lines().collect();
        let count_line = first + 1;
        let n: u64 = lines[first]
            .trim()
            .parse()
            .map_err(|_| self.err(count_line, "the first line must be the number of particles"))?;
        if n > MAX_PARTICLES {
            return Err(self.err(
                count_line,
                format!("{n} particles is more than packbed reads ({MAX_PARTICLES})"),
            ));
        }
        let comment_no = first + 2;
        let kv = parse_key_values(lines[first + 1]);
        let get = |k: &str| {
            kv.iter()
                .find(|(a, _)| a.eq_ignore_ascii_case(k))
                .map(|(_, b)| b.as_str())
        };
        let props = get("Properties").unwrap_or("species:S:1:pos:R:3");
        // Columns: (name, kind, width).
        let parts: Vec<&str> = props.split(':').collect();
        if !parts.len().is_multiple_of(3) {
            return Err(self.err(
                comment_no,
                format!("Properties=\"{props}\" is not name:type:count triples"),
            ));
        }
        let mut cols = Vec::new();
        let mut at = 0usize;
        for t in parts.chunks(3) {
            let w: usize = t[2]
                .parse()
                .map_err(|_| self.err(comment_no, format!("Properties: bad count \"{}\"", t[2])))?;
            cols.push((t[0].to_ascii_lowercase(), t[1].to_ascii_uppercase(), at, w));
            at += w;
        }
        let col = |name: &[&str]| cols.iter().find(|c| name.contains(&c.0.as_str())).cloned();
        let Some(pos) = col(&["pos"]) else {
            return Err(self.err(comment_no, "Properties has no pos column"));
        };
        let Some(rad) = col(&["radius", "radii"]) else {
            return Err(self.err(comment_no, "Properties has no radius column"));
        };
        let sp = col(&["species", "type"]);
        let body = col(&["body", "mol", "molecule"]);
        let dim_key = get("dim").and_then(|d| d.parse::<usize>().ok());
        let dim = match (dim_key, pos.3) {
            (Some(2), _) | (None, 2) => 2,
            _ => 3,
        };
        let mut raw = Raw::new(dim);
        let mut names: Vec<String> = Vec::new();
        for j in 0..n as usize {
            let no = first + 3 + j;
            let Some(l) = lines.get(first + 2 + j) else {
                return Err(self.err(no, format!("the file ends after {j} of {n} particles")));
            };
            let v: Vec<&str> = l.split_whitespace().collect();
            if v.len() != at {
                return Err(self.err(no, format!("{} columns, Properties says {at}", v.len())));
            }
            let mut p = [0.0; 3];
            for a in 0..pos.3.min(3) {
                p[a] = self.num(no, ["x", "y", "z"][a], v[pos.2 + a])?;
            }
            raw.pos.push(p);
            raw.radii.push(self.num(no, "radius", v[rad.2])?);
            raw.species.push(match &sp {
                Some(c) if c.1 == "I" => self.int(no, &c.0, v[c.2])?,
                Some(c) => {
                    // Named species: numbered in order of first appearance.
                    let s = v[c.2];
                    match names.iter().position(|x| x == s) {
                        Some(k) => k as u32,
                        None => {
                            names.push(s.to_string());
                            (names.len() - 1) as u32
                        }
                    }
                }
                None => 0,
            });
            raw.bodies.push(match &body {
                Some(c) => self.int(no, &c.0, v[c.2])?,
                None => j as u32,
            });
            raw.lines.push(no);
        }
        // A count below the rows would silently cut the bed short: after the
        // frame comes the end of the file or the count line of the next frame.
        let extra = lines[(first + 2 + n as usize).min(lines.len())..]
            .iter()
            .take_while(|l| l.trim().parse::<u64>().is_err())
            .filter(|l| !l.trim().is_empty())
            .count();
        if extra > 0 {
            return Err(self.err(
                first + 3 + n as usize,
                format!(
                    "{} particle lines, but the count line says {n}",
                    n as usize + extra
                ),
            ));
        }
        for s in &names {
            raw.species_info.push(Species {
                name: s.clone(),
                shape: Shape::Sphere,
                size: SizeDist::Fixed(1.0),
                ratio: 1.0,
            });
        }
        if let Some(lat) = get("Lattice") {
            let v: Vec<Real> = lat
                .split_whitespace()
                .map(|s| self.num(comment_no, "Lattice", s))
                .collect::<Result<_>>()?;
            if v.len() != 9 {
                return Err(self.err(comment_no, "Lattice needs 9 numbers"));
            }
            let off = [v[1], v[2], v[3], v[5], v[6], v[7]];
            if off.iter().any(|&x| x != 0.0) {
                return Err(self.err(
                    comment_no,
                    "Lattice is not orthogonal (packbed boxes are rectangular)",
                ));
            }
            let pbc: Vec<bool> = get("pbc")
                .map(|s| {
                    s.split_whitespace()
                        .map(|t| t.eq_ignore_ascii_case("t") || t == "1")
                        .collect()
                })
                .unwrap_or_default();
            let ext: Vec<Real> = [v[0], v[4], v[8]][..dim].to_vec();
            raw.size = Some((ext, pbc.first().copied().unwrap_or(false)));
            if let Some(o) = get("Origin") {
                let o: Vec<Real> = o
                    .split_whitespace()
                    .map(|s| self.num(comment_no, "Origin", s))
                    .collect::<Result<_>>()?;
                if o.len() == 3 {
                    raw.origin = [o[0], o[1], if dim == 2 { 0.0 } else { o[2] }];
                }
            }
        }
        for (k, s) in raw.species_info.iter_mut().enumerate() {
            let r = raw
                .radii
                .iter()
                .zip(&raw.species)
                .find(|(_, &q)| q as usize == k)
                .map_or(1.0, |(r, _)| *r);
            s.size = SizeDist::Fixed(r);
        }
        Ok(raw)
    }

    /// packbed's own `bed.vtu` (ASCII): points, `radius`, `species`, `body`, and
    /// the `box`, `periodic`, `dim` field data.
    fn vtu(&self, text: &str) -> Result<Raw> {
        let array = |name: Option<&str>| -> Option<(usize, Vec<&str>)> {
            let mut from = 0;
            while let Some(i) = text[from..].find("<DataArray") {
                let s = from + i;
                let open_end = s + text[s..].find('>')?;
                let tag = &text[s..open_end];
                let close = open_end + text[open_end..].find("</DataArray>")?;
                let matches = match name {
                    Some(n) => tag.contains(&format!("Name=\"{n}\"")),
                    None => !tag.contains("Name=") && tag.contains("NumberOfComponents=\"3\""),
                };
                if matches {
                    let line = text[..open_end].matches('\n').count() + 1;
                    return Some((line, text[open_end + 1..close].split_whitespace().collect()));
                }
                from = close;
            }
            None
        };
        let need = |name: Option<&str>| {
            array(name)
                .ok_or_else(|| self.err(1, format!("no DataArray {}", name.unwrap_or("of points"))))
        };
        let (pl, pts) = need(None)?;
        let (rl, rad) = need(Some("radius"))?;
        if pts.len() % 3 != 0 || pts.len() / 3 != rad.len() {
            return Err(self.err(pl, "the points and radii do not match in number"));
        }
        let dim = array(Some("dim"))
            .and_then(|(_, v)| v.first().and_then(|d| d.parse::<usize>().ok()))
            .unwrap_or(3);
        let mut raw = Raw::new(if dim == 2 { 2 } else { 3 });
        let ints = |name: &str| -> Result<Option<Vec<u32>>> {
            match array(Some(name)) {
                Some((l, v)) => {
                    if v.len() != rad.len() {
                        return Err(self.err(
                            l,
                            format!("{name} has {} values for {} points", v.len(), rad.len()),
                        ));
                    }
                    v.iter()
                        .map(|s| self.int(l, name, s))
                        .collect::<Result<Vec<_>>>()
                        .map(Some)
                }
                None => Ok(None),
            }
        };
        let species = ints("species")?;
        let bodies = ints("body")?;
        for j in 0..rad.len() {
            raw.pos.push([
                self.num(pl, "x", pts[3 * j])?,
                self.num(pl, "y", pts[3 * j + 1])?,
                self.num(pl, "z", pts[3 * j + 2])?,
            ]);
            raw.radii.push(self.num(rl, "radius", rad[j])?);
            raw.species.push(species.as_ref().map_or(0, |s| s[j]));
            raw.bodies.push(bodies.as_ref().map_or(j as u32, |b| b[j]));
            raw.lines.push(rl);
        }
        if let Some((l, b)) = array(Some("box")) {
            let v: Vec<Real> = b
                .iter()
                .map(|s| self.num(l, "box", s))
                .collect::<Result<_>>()?;
            if v.len() == 3 {
                let periodic =
                    array(Some("periodic")).is_some_and(|(_, p)| p.first() == Some(&"1"));
                raw.size = Some((v[..raw.dim].to_vec(), periodic));
            }
        }
        Ok(raw)
    }
}

/// `key=value` and `key="quoted value"` pairs of an extended XYZ comment line.
fn parse_key_values(line: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut chars = line.trim().chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        let mut key = String::new();
        while let Some(&c) = chars.peek() {
            if c == '=' || c.is_whitespace() {
                break;
            }
            key.push(c);
            chars.next();
        }
        if key.is_empty() {
            break;
        }
        let mut value = String::new();
        if chars.peek() == Some(&'=') {
            chars.next();
            if chars.peek() == Some(&'"') {
                chars.next();
                for c in chars.by_ref() {
                    if c == '"' {
                        break;
                    }
                    value.push(c);
                }
            } else {
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() {
                        break;
                    }
                    value.push(c);
                    chars.next();
                }
            }
        }
        out.push((key, value));
    }
    out
}

/// "chain of 5 beads, spacing 1" → the chain shape.
fn parse_chain(s: &str) -> Option<Shape> {
    let rest = s.strip_prefix("chain of ")?;
    let beads: u32 = rest.split_whitespace().next()?.parse().ok()?;
    let spacing: Real = rest.rsplit(' ').next()?.parse().ok()?;
    // A bed file records the shape, not how chains entered the box.
    Some(Shape::Chain {
        beads,
        spacing,
        orientation: crate::species::Orientation::default(),
    })
}

fn mean_radius(raw: &Raw, s: u32) -> Real {
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

fn build<const D: usize>(raw: &Raw, size: &[Real], periodic: bool) -> Bed<D> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_values() {
        let kv = parse_key_values(
            r#"Lattice="1 0 0 0 2 0 0 0 3" Properties=pos:R:3 pbc="T T F" dim=3 flag"#,
        );
        assert_eq!(kv[0], ("Lattice".into(), "1 0 0 0 2 0 0 0 3".into()));
        assert_eq!(kv[1], ("Properties".into(), "pos:R:3".into()));
        assert_eq!(kv[2], ("pbc".into(), "T T F".into()));
        assert_eq!(kv[3], ("dim".into(), "3".into()));
        assert_eq!(kv[4], ("flag".into(), "".into()));
    }

    #[test]
    fn chain_shapes() {
        assert_eq!(
            parse_chain("chain of 5 beads, spacing 1"),
            Some(Shape::Chain {
                beads: 5,
                spacing: 1.0,
                orientation: crate::species::Orientation::default(),
            })
        );
        assert_eq!(parse_chain("sphere"), None);
    }
}
