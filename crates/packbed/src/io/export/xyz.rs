//! Extended XYZ, `bed.xyz` (OVITO, ASE; read back by `io::read::xyz`).

use super::{position, Export};
use crate::io::tables::{push_int, write_rows, Num};
use std::io::Write;

/// Extended XYZ: a count line, a comment line with `Lattice`, `Origin`,
/// `Properties=species:I:1:pos:R:3:radius:R:1:body:I:1:coordination:I:1`, `pbc`
/// and `dim`, then one line per particle.
pub(super) fn write<const D: usize>(w: &mut dyn Write, x: &Export<D>) -> std::io::Result<()> {
    let (bed, coordination, b) = (x.bed, x.coordination, x.box3);
    let p = bed.container.periodic;
    let tf = |x: bool| if x { "T" } else { "F" };
    let (pbc, oz) = if D == 2 {
        (format!("{} F T", tf(p)), -b[2] / 2.0)
    } else {
        (format!("{} {} F", tf(p), tf(p)), 0.0)
    };
    writeln!(w, "{}", bed.len())?;
    writeln!(
        w,
        r#"Lattice="{} 0 0 0 {} 0 0 0 {}" Origin="0 0 {}" Properties=species:I:1:pos:R:3:radius:R:1:body:I:1:coordination:I:1 pbc="{pbc}" dim={D}"#,
        Num(b[0]),
        Num(b[1]),
        Num(b[2]),
        Num(oz)
    )?;
    write_rows(w, bed.len(), |w, i| {
        let q = position(bed, i);
        push_int(w, bed.species[i]);
        for v in [q[0], q[1], q[2], bed.radii[i]] {
            w.push(b' ');
            Num(v).push_to(w);
        }
        w.push(b' ');
        push_int(w, bed.bodies[i]);
        w.push(b' ');
        push_int(w, coordination[i]);
        w.push(b'\n');
        Ok(())
    })
}
