//! Extended XYZ, `bed.xyz` (OVITO, ASE; read back by `io::read::xyz`).

use super::{position, Export};
use crate::io::tables::Num;
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
    for i in 0..bed.len() {
        let q = position(bed, i);
        writeln!(
            w,
            "{} {} {} {} {} {} {}",
            bed.species[i],
            Num(q[0]),
            Num(q[1]),
            Num(q[2]),
            Num(bed.radii[i]),
            bed.bodies[i],
            coordination[i]
        )?;
    }
    Ok(())
}
