//! Exports for other tools: VTK (ParaView), LAMMPS dump (OVITO), extended XYZ.
