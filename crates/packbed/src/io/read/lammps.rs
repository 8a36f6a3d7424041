//! LAMMPS dumps (the first snapshot).

use super::raw::{Raw, Reader};
use super::report::MAX_PARTICLES;
use crate::error::Result;
use crate::math::Real;

/// One atom of a LAMMPS dump: id, position, radius, type, molecule, line.
type DumpRow = (u64, [Real; 3], Real, u32, Option<u32>, usize);

impl Reader<'_> {
    /// LAMMPS dump (first snapshot): box bounds with boundary flags, and columns
    /// by name (`x y z` or scaled `xs ys zs`, `radius` or `diameter`, `type`, `mol`).
    pub(super) fn dump(&self, text: &str) -> Result<Raw> {
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
        raw.first_species_id = 1;
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
}
