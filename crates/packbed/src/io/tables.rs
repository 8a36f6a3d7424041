//! The CSV files of a run: `particles.csv`, `contacts.csv`, `wall_contacts.csv`.
//!
//! Numbers are written as the shortest text that reads back to the same bits
//! (Rust's `Display`/`LowerExp` for `f64`), so the files round-trip exactly. The
//! columns are numeric (wall names aside) and never quoted, so a plain writer is
//! enough.

use crate::analysis::Contacts;
use crate::bed::Bed;
use std::fmt;
use std::io::{Error, Write};

/// An `f64` in the shortest exact form: plain decimals for ordinary magnitudes,
/// exponent notation for tiny or huge ones (a contact gap of 3.6e-15 would
/// otherwise take 30 characters of zeros).
#[derive(Clone, Copy, Debug)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// A non-finite number would make the file unreadable for numpy and hide a bug;
/// refuse it with the row it is in.
pub(crate) fn finite(v: f64, what: &str, id: usize) -> std::io::Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{what} of row {id} is {v}, not a finite number; refusing to write it"),
        ))
    }
}

/// Column names of `particles.csv` for dimension `D`.
pub fn particles_header<const D: usize>() -> &'static str {
    if D == 2 {
        "id,species,body,x,y,r"
    } else {
        "id,species,body,x,y,z,r"
    }
}

/// Writes `particles.csv`: one row per sphere or bead, in deposition order.
pub fn write_particles<const D: usize>(w: &mut dyn Write, bed: &Bed<D>) -> std::io::Result<()> {
    const AXES: [&str; 3] = ["x", "y", "z"];
    writeln!(w, "{}", particles_header::<D>())?;
    for id in 0..bed.len() {
        write!(w, "{id},{},{}", bed.species[id], bed.bodies[id])?;
        for (k, axis) in AXES.iter().enumerate().take(D) {
            write!(w, ",{}", Num(finite(bed.centres[id][k], axis, id)?))?;
        }
        writeln!(w, ",{}", Num(finite(bed.radii[id], "r", id)?))?;
    }
    Ok(())
}

/// Writes `contacts.csv`: `i,j,gap` for every touching pair.
pub fn write_contacts(w: &mut dyn Write, contacts: &Contacts) -> std::io::Result<()> {
    writeln!(w, "i,j,gap")?;
    for c in &contacts.pairs {
        let gap = Num(finite(c.gap, "gap", c.i as usize)?);
        writeln!(w, "{},{},{gap}", c.i, c.j)?;
    }
    Ok(())
}

/// Writes `wall_contacts.csv`: `i,wall,gap` with wall names `floor, x0, x1, y0, y1`.
pub fn write_wall_contacts(w: &mut dyn Write, contacts: &Contacts) -> std::io::Result<()> {
    writeln!(w, "i,wall,gap")?;
    for c in &contacts.walls {
        let gap = Num(finite(c.gap, "gap", c.i as usize)?);
        writeln!(w, "{},{},{gap}", c.i, c.wall.name())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Contact, WallContact};
    use crate::container::{Container, Wall};
    use crate::math::Vector;

    fn bed3() -> Bed<3> {
        let mut b = Bed::new(
            Container {
                size: Vector([100.0; 3]),
                periodic: false,
            },
            Vec::new(),
        );
        b.push(Vector([0.1, 1.0 / 3.0, 10.0]), 10.0, 0);
        b.push(Vector([1e-300, 2.5, 29.999999999999996]), 20.0, 1);
        b
    }

    fn text(f: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> String {
        let mut v = Vec::new();
        f(&mut v).unwrap();
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn particles_round_trip_exactly() {
        let bed = bed3();
        let s = text(|w| write_particles(w, &bed));
        let mut lines = s.lines();
        assert_eq!(lines.next(), Some("id,species,body,x,y,z,r"));
        for (id, line) in lines.enumerate() {
            let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            assert_eq!(f[0] as usize, id);
            for k in 0..3 {
                assert_eq!(f[3 + k].to_bits(), bed.centres[id][k].to_bits());
            }
            assert_eq!(f[6], bed.radii[id]);
        }
    }

    #[test]
    fn numbers_round_trip_in_every_range() {
        for v in [
            0.0,
            -0.0,
            1e-300,
            -3.552713678800501e-15,
            1e-5,
            0.1,
            1.0 / 3.0,
            12.5,
            1e16,
            1e300,
        ] {
            let t = Num(v).to_string();
            assert_eq!(t.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{t}");
            assert!(t.len() <= 24, "{t}");
        }
    }

    #[test]
    fn nan_is_refused() {
        let mut bed = bed3();
        bed.centres[1][2] = f64::NAN;
        let mut v = Vec::new();
        let e = write_particles(&mut v, &bed).unwrap_err();
        assert!(e.to_string().contains("row 1"), "{e}");
    }

    #[test]
    fn contact_files() {
        let c = Contacts {
            pairs: vec![Contact {
                i: 0,
                j: 1,
                gap: -1e-12,
            }],
            walls: vec![WallContact {
                i: 0,
                wall: Wall::High(1),
                gap: 0.0,
            }],
        };
        let pairs = text(|w| write_contacts(w, &c));
        assert_eq!(pairs.lines().nth(1), Some("0,1,-1e-12"));
        let walls = text(|w| write_wall_contacts(w, &c));
        assert_eq!(walls, "i,wall,gap\n0,y1,0\n");
    }
}
