//! Plain CSV or whitespace `x y [z] r` tables, with or without a header, and
//! packbed's own `particles.csv` (box and species from the `summary.json`
//! beside it).

use super::raw::{mean_radius, Raw, Reader};
use super::report::{BoxHint, BoxSource};
use crate::error::{echo, Error, Result};
use crate::math::Real;
use crate::species::{Shape, SizeDist, Species};

impl Reader<'_> {
    /// Plain CSV or whitespace table, or packbed's `particles.csv`.
    pub(super) fn table(&self, text: &str, hint: Option<&BoxHint>) -> Result<Raw> {
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
        // A column named twice (`x,x,y,r`), or by two of its names (`r` and
        // `radius`), would leave which one is used to the reader's order.
        for names in [
            &["x"][..],
            &["y"],
            &["z"],
            &["r", "radius"],
            &["species", "type"],
            &["body", "mol"],
            &["id"],
        ] {
            let named: Vec<usize> = (0..columns.len())
                .filter(|&k| names.contains(&columns[k].as_str()))
                .collect();
            if let [a, b, ..] = named[..] {
                return Err(self.err(
                    first_no,
                    format!(
                        "the header names column `{}` twice (columns {} and {}): which one to use?",
                        echo(&columns[b]),
                        a + 1,
                        b + 1
                    ),
                ));
            }
        }
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
                        echo(&columns.join(","))
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
        // A summary of another bed (3D beside a 2D table, say) would give it a
        // wrong box and species.
        if let Some(dim) = v.get("dim").and_then(|d| d.as_u64()) {
            if dim != raw.dim as u64 {
                return Err(bad(format!(
                    "says dim {dim}, but {} beside it is a {}D bed ({}): is it the summary \
                     of another bed? Move it away (and give the box) or put this bed's summary there",
                    self.path.display(),
                    raw.dim,
                    if raw.dim == 2 { "no z column" } else { "a z column" }
                )));
            }
        }
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
                    feed: None,
                });
            }
        }
        Ok(())
    }
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
        orientation: crate::species::EntryOrientation::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_shapes() {
        assert_eq!(
            parse_chain("chain of 5 beads, spacing 1"),
            Some(Shape::Chain {
                beads: 5,
                spacing: 1.0,
                orientation: crate::species::EntryOrientation::default(),
            })
        );
        assert_eq!(parse_chain("sphere"), None);
    }
}
