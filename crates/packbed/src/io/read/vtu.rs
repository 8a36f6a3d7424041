//! packbed's own `bed.vtu` (ASCII VTK).

use super::raw::{Raw, Reader};
use crate::error::Result;
use crate::math::Real;

impl Reader<'_> {
    /// packbed's own `bed.vtu` (ASCII): points, `radius`, `species`, `body`, and
    /// the `box`, `periodic`, `dim` field data.
    pub(super) fn vtu(&self, text: &str) -> Result<Raw> {
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
