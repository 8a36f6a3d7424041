//! Readers of bed files: packbed particles.csv, plain `x y [z] r`, LAMMPS dump, extended XYZ.
