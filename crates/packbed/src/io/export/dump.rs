//! LAMMPS dump, `bed.dump` (OVITO, LAMMPS `read_dump`; read back by `io::read::lammps`).

use super::{position, Export};
use crate::io::tables::{push_int, write_rows, Num};
use std::io::Write;

/// The LAMMPS boundary flags: `pp` for periodic axes, `ff` for walls. 2D beds are
/// periodic in the thin z direction, as LAMMPS requires of 2D boxes.
pub fn boundary_flags<const D: usize>(periodic: bool) -> [&'static str; 3] {
    let side = if periodic { "pp" } else { "ff" };
    if D == 2 {
        [side, "ff", "pp"]
    } else {
        [side, side, "ff"]
    }
}

/// LAMMPS dump: `ITEM: ATOMS id type x y z radius mol c_coord`, ids and types
/// 1-based as LAMMPS numbers them (`id = row + 1`, `type = species + 1`,
/// `mol = body + 1`).
pub(super) fn write<const D: usize>(w: &mut dyn Write, x: &Export<D>) -> std::io::Result<()> {
    let (bed, coordination, b) = (x.bed, x.coordination, x.box3);
    let flags = boundary_flags::<D>(bed.container.periodic);
    writeln!(w, "ITEM: TIMESTEP\n0")?;
    writeln!(w, "ITEM: NUMBER OF ATOMS\n{}", bed.len())?;
    writeln!(w, "ITEM: BOX BOUNDS {} {} {}", flags[0], flags[1], flags[2])?;
    writeln!(w, "0 {}", Num(b[0]))?;
    writeln!(w, "0 {}", Num(b[1]))?;
    if D == 2 {
        writeln!(w, "{} {}", Num(-b[2] / 2.0), Num(b[2] / 2.0))?;
    } else {
        writeln!(w, "0 {}", Num(b[2]))?;
    }
    writeln!(w, "ITEM: ATOMS id type x y z radius mol c_coord")?;
    write_rows(w, bed.len(), |w, i| {
        let p = position(bed, i);
        push_int(w, i + 1);
        w.push(b' ');
        push_int(w, bed.species[i] + 1);
        for v in [p[0], p[1], p[2], bed.radii[i]] {
            w.push(b' ');
            Num(v).push_to(w);
        }
        w.push(b' ');
        push_int(w, bed.bodies[i] + 1);
        w.push(b' ');
        push_int(w, coordination[i]);
        w.push(b'\n');
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags() {
        assert_eq!(boundary_flags::<3>(true), ["pp", "pp", "ff"]);
        assert_eq!(boundary_flags::<3>(false), ["ff", "ff", "ff"]);
        assert_eq!(boundary_flags::<2>(true), ["pp", "ff", "pp"]);
        assert_eq!(boundary_flags::<2>(false), ["ff", "ff", "pp"]);
    }
}
