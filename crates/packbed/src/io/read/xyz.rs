//! Extended XYZ (the first frame).

use super::raw::{Raw, Reader};
use super::report::MAX_PARTICLES;
use crate::error::Result;
use crate::math::Real;
use crate::species::{Shape, SizeDist, Species};

impl Reader<'_> {
    /// Extended XYZ (first frame): `Lattice` (orthogonal), `Origin`, `pbc`,
    /// `Properties` with `pos:R:3` and `radius:R:1` (species and body optional).
    pub(super) fn xyz(&self, text: &str, first: usize) -> Result<Raw> {
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
                feed: None,
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
}
