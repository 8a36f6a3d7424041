#!/usr/bin/env python3
"""Write a LAMMPS input for a DEM pour of rigid rods: straight rods of K
touching beads of diameter d = 1 (centres one diameter apart), poured by
LAMMPS's `fix pour` as rigid bodies (`fix rigid/small`) onto a flat
frictional floor, periodic in x and y.

Peer measurement for packbed's momentum rule on chains (docs/settling.md,
"Momentum for rigid chains").  Standard library only; the contact model,
units, box and stopping rule are pour.py's (imported), so the rod pours and
the sphere pours differ only in the particles and their insertion:

  - every bead interacts with every bead of another rod and with the floor
    by Hertz-Mindlin (pair_style granular, as pour.py); beads of one rod do
    not interact (neigh_modify exclude molecule/intra);
  - a rod is one rigid body (fix rigid/small molecule): its mass and inertia
    are the sum of its beads';
  - fix pour inserts the rods at random positions and orientations (LAMMPS
    rotates each inserted molecule about a random axis), at fix pour's
    volume fraction VOL_POUR, into a slab ABOVE_BED d above the final bed's top,
    RAIN d tall, each moving down at the speed of a fall from the slab's top
    (fix pour's rule; checked: the lowest of a cloud start at 4.86 sqrt(g d)
    in a slab 12 d tall): a rain of loose clouds that all fall from the slab's
    top, faster on impact than pour.py's batches, which start at rest;
  - after the pour, the bed is run until the kinetic energy per bead is below
    KE_TOL m_ref g d or for at most --settle, and the final frame is written
    to bed.dump (id mol radius x y z vx vy vz).

Usage:
  pour_rods.py --beads 3 --mu 0.3 --rods 667 --out DIR [--settle 40] [--seed S]
writes DIR/in.pour and DIR/rod.mol; run with  cd DIR && lmp -in in.pour
"""
import argparse
import math
import os

from pour import E, E_REST, G, KE_TOL, L, M_REF, MAX_SETTLE, NU, RHO, XGAMMA_T, DT_FRACTION, hertz_tc

VOL_POUR = 0.5     # fix pour's volume fraction of each cloud, of the rods' bounding spheres
                   # (diameter = the rod's length): a bead solid fraction of VOL_POUR K / K^3
ABOVE_BED = 3.0    # the insertion slab's bottom, in d above the final bed's top (phi 0.5)
RAIN = 12.0        # the insertion slab's height, in d


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--beads", type=int, default=3)
    ap.add_argument("--mu", type=float, required=True)
    ap.add_argument("--rods", type=int, default=667)
    ap.add_argument("--seed", type=int, default=4767548)
    ap.add_argument("--out", required=True)
    ap.add_argument("--settle", type=float, default=MAX_SETTLE)
    a = ap.parse_args()
    if a.beads < 2 or a.rods < 1:
        ap.error("a rod has at least 2 beads, and a pour at least one rod")
    os.makedirs(a.out, exist_ok=True)
    k = a.beads
    m_bead = RHO * math.pi / 6.0
    with open(os.path.join(a.out, "rod.mol"), "w") as f:
        f.write(f"# straight rod of {k} touching beads, d = 1\n\n{k} atoms\n\nCoords\n\n")
        for i in range(k):
            f.write(f"{i + 1} {i - (k - 1) / 2:.12g} 0 0\n")
        f.write("\nTypes\n\n" + "".join(f"{i + 1} 1\n" for i in range(k)))
        f.write("\nDiameters\n\n" + "".join(f"{i + 1} 1\n" for i in range(k)))
        f.write("\nMasses\n\n" + "".join(f"{i + 1} {m_bead:.12g}\n" for i in range(k)))

    beads = k * a.rods
    bed_top = beads * math.pi / 6.0 / (L * L * 0.5)     # a bed at phi 0.5: above any real one
    zlo = bed_top + ABOVE_BED
    zhi_ins = zlo + RAIN
    zbox = zhi_ins + k + 2.0
    vmax = math.sqrt(2 * G * zhi_ins) + 0.5
    dt = DT_FRACTION * hertz_tc(1.0, 1.0, vmax)         # one bead's mass: shorter than a rod's
    t_fall = math.sqrt(2 * zhi_ins / G)
    # fix pour inserts a cloud each time the last has fallen through the slab
    # (sqrt(2 RAIN / g)), VOL_POUR of the slab in bounding spheres each (as it
    # reports in screen.txt); run for every cloud and the last one's fall.
    per_cloud = max(1, int(VOL_POUR * L * L * RAIN / (math.pi / 6.0 * k ** 3)))
    clouds = math.ceil(a.rods / per_cloud)
    pour_time = clouds * math.sqrt(2 * RAIN / G) + t_fall + 5.0
    pour_steps = int(math.ceil(pour_time / dt))
    settle_steps = int(a.settle / dt)
    normal = f"hertz/material {E:g} {E_REST} {NU}"
    lines = f"""# DEM pour of rigid rods written by pour_rods.py: {k} beads, mu = {a.mu}, {a.rods} rods, seed {a.seed}
# units lj: d = 1, rho = {RHO}, g = {G}; m_ref = pi/6 (one bead)
# E = {E:g}, nu = {NU}, e = {E_REST} (tsuji), x_gamma_t = {XGAMMA_T}, mu = {a.mu}
# insertion slab z {zlo:.3f}..{zhi_ins:.3f}, fix pour vol {VOL_POUR}; dt = {dt:.4e}
units           lj
atom_style      sphere
atom_modify     map array
dimension       3
boundary        p p f
newton          off
comm_modify     vel yes
fix             prop all property/atom mol ghost yes
region          box block 0 {L} 0 {L} 0 {zbox:.6g}
create_box      1 box
pair_style      granular
pair_coeff      * * {normal} tangential mindlin NULL {XGAMMA_T} {a.mu} damping tsuji
neighbor        0.3 bin
neigh_modify    delay 0 every 1 check yes exclude molecule/intra all
timestep        {dt:.6e}
molecule        rod rod.mol
fix             bodies all rigid/small molecule mol rod
fix             grav all gravity {G} vector 0 0 -1
fix             floor all wall/gran granular {normal} tangential mindlin NULL {XGAMMA_T} {a.mu} damping tsuji zplane 0.0 NULL
region          slab block 0 {L} 0 {L} {zlo:.6g} {zhi_ins:.6g}
fix             ins all pour {a.rods} 0 {a.seed} vol {VOL_POUR} 1000 region slab mol rod rigid bodies
compute         tke all ke
variable        kep equal c_tke/(atoms+1e-30)/{M_REF:.10g}
variable        ztop equal bound(all,zmax)
variable        speed atom sqrt(vx^2+vy^2+vz^2)
compute         vmax all reduce max v_speed
thermo_style    custom step time atoms c_tke v_kep c_vmax v_ztop cpu
thermo_modify   lost error norm no flush yes
thermo          5000
run             {pour_steps}
variable        n equal atoms
print           "POURED $(v_n) beads of {beads}"
# settle: stop when KE per bead < {KE_TOL:g} m_ref g d (checked every 1000 steps)
fix             halt all halt 1000 v_kep < {KE_TOL:g} error continue
run             {settle_steps}
unfix           halt
run             0 post no
print           "FINAL kep ${{kep}} vmax $(c_vmax) time $(time) step $(step)"
write_dump      all custom bed.dump id mol radius x y z vx vy vz modify sort id
"""
    with open(os.path.join(a.out, "in.pour"), "w") as f:
        f.write(lines)
    print(f"{a.out}: {a.rods} rods of {k}, {clouds} clouds of about {per_cloud}, dt {dt:.3e}, "
          f"pour {pour_steps} steps, settle <= {settle_steps}")


if __name__ == "__main__":
    main()
