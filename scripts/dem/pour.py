#!/usr/bin/env python3
"""Write a LAMMPS input (and its batch data files) for a DEM pour: a rain of
spheres onto a flat frictional floor, periodic in x and y.

Peer measurement for packbed's calibration table.  Standard library only.

Units (LAMMPS `units lj`): length = reference diameter d = 1, density rho = 1,
gravity g = 1.  So the reference mass is m = pi/6 and time is in sqrt(d/g).

Model (pair_style granular, same model on the floor wall):
  normal      hertz/material  E, e (restitution, via `damping tsuji`), nu
  tangential  mindlin, k_t from E and nu (NULL), tangential damping 1.0, mu
  no rolling resistance, no twisting, no cohesion
  (--cohesion jkr|dmt --bond BO: the normal model becomes LAMMPS's jkr or dmt,
  with the surface energy that gives a pull-off force of BO m_ref g between two
  d = 1 spheres; the floor gets the same model and surface energy).

Insertion: the diameters are drawn up front with a fixed seed (lognormal
included: fix pour cannot draw a lognormal), split into batches, and each batch
is a loose random non-overlapping cloud (volume fraction PHI_CLOUD) written to
its own data file.  In LAMMPS each batch is appended above the current top of
the bed (`read_data ... add append shift 0 0 ztop`), falls and lands before the
next batch comes: a rain, not a collapse.  After the last batch the bed is run
until the kinetic energy (translational + rotational) per particle is below
KE_TOL * m g d (checked by fix halt every 1000 steps) or for at most
MAX_SETTLE (--settle), then the final frame (id radius x y z vx vy vz) is written
to bed.dump and a FINAL line with the KE per particle to the log.

Usage:
  pour.py --dist equal|bidisperse|lognormal --mu 0.3 --n 4000 --out DIR [--settle 40]
          [--cohesion jkr|dmt --bond BO]
writes DIR/in.pour and DIR/batch_*.data; run with
  cd DIR && lmp -in in.pour
"""
import argparse
import math
import os
import random

# ---------------------------------------------------------------- parameters
L = 10.0            # box width and depth (periodic), in d
E = 2.0e6           # Young's modulus, in rho g d (overlaps ~1e-4..1e-3 d under the bed)
NU = 0.3            # Poisson's ratio
E_REST = 0.5        # normal restitution (nominal, Tsuji damping)
XGAMMA_T = 1.0      # tangential damping ratio (LAMMPS x_gamma,t)
RHO = 1.0           # particle density
G = 1.0             # gravity
BATCH = 400         # particles per batch
PHI_CLOUD = 0.15    # solid fraction of each falling cloud
GAP = 1.0           # gap (in d_max) between bed top and the cloud bottom
KE_TOL = 1e-8       # stop when KE per particle < KE_TOL * m_ref g d
DT_FRACTION = 1.0 / 20.0   # timestep = DT_FRACTION * Hertz collision time
MAX_SETTLE = 40.0   # cap on the final settling time (in sqrt(d/g)); the final KE is reported
M_REF = RHO * math.pi / 6.0  # mass of the reference sphere d = 1
# Pull-off force of LAMMPS's cohesive normal models (29 Sep 2021 build) per unit of
# its surface-energy coefficient gamma and of R* = R_i R_j / (R_i + R_j):
# F = 3 pi gamma R* (jkr), 4 pi gamma R* (dmt), i.e. 1.5 pi w R* and 2 pi w R* for
# the work of adhesion w = 2 gamma.  Measured with a two-sphere pull test
# (RESULTS.md, "g(r) and cohesion"), not only read from the documentation.
PULLOFF_PER_GAMMA_R = {"jkr": 3.0 * math.pi, "dmt": 4.0 * math.pi}


def diameters(dist, n, seed):
    """The n diameters of a distribution, drawn with a fixed seed, shuffled."""
    rng = random.Random(seed)
    if dist == "equal":
        ds = [1.0] * n
    elif dist == "bidisperse":          # 50/50 by number, exact counts
        ds = [1.0] * (n // 2) + [1.4] * (n - n // 2)
    elif dist == "lognormal":           # number-weighted, median 1, gsd 1.3, cut at +-3 sd
        s = math.log(1.3)
        ds = []
        while len(ds) < n:
            z = rng.gauss(0.0, 1.0)
            if abs(z) <= 3.0:
                ds.append(math.exp(s * z))
    else:
        raise SystemExit(f"unknown distribution {dist}")
    rng.shuffle(ds)
    return ds


def cloud(ds, rng):
    """Random non-overlapping positions (periodic in x, y) for one batch, in a
    slab whose height gives volume fraction PHI_CLOUD; z from the slab bottom."""
    dmax = max(ds)
    vol = sum(math.pi / 6.0 * d ** 3 for d in ds)
    h = max(vol / (L * L * PHI_CLOUD), 2.0 * dmax)
    # place the largest first (easier), simple cell list on cells of size dmax
    order = sorted(range(len(ds)), key=lambda i: -ds[i])
    nc = max(1, int(L // dmax))
    cs = L / nc
    cells = {}
    pos = [None] * len(ds)
    for i in order:
        ri = ds[i] / 2.0
        for _ in range(100000):
            x, y = rng.uniform(0, L), rng.uniform(0, L)
            z = rng.uniform(ri, h - ri) + GAP * dmax
            cx, cy, cz = int(x / cs) % nc, int(y / cs) % nc, int(z / cs)
            ok = True
            for ax in (-1, 0, 1):
                for ay in (-1, 0, 1):
                    for az in (-1, 0, 1):
                        for j in cells.get(((cx + ax) % nc, (cy + ay) % nc, cz + az), ()):
                            px, py, pz = pos[j]
                            dx = (x - px + L / 2) % L - L / 2
                            dy = (y - py + L / 2) % L - L / 2
                            dz = z - pz
                            if dx * dx + dy * dy + dz * dz < ((ri + ds[j] / 2) * 1.02) ** 2:
                                ok = False
                                break
                        if not ok:
                            break
                    if not ok:
                        break
                if not ok:
                    break
            if ok:
                pos[i] = (x, y, z)
                cells.setdefault((cx, cy, cz), []).append(i)
                break
        else:
            raise SystemExit("could not place a particle in the cloud")
    return pos, h + GAP * dmax


def hertz_tc(d1, d2, v):
    """Elastic Hertz collision time of two spheres hitting at speed v."""
    m1, m2 = RHO * math.pi / 6 * d1 ** 3, RHO * math.pi / 6 * d2 ** 3
    mstar = m1 * m2 / (m1 + m2)
    rstar = (d1 / 2) * (d2 / 2) / (d1 / 2 + d2 / 2)
    estar = E / (2.0 * (1.0 - NU ** 2))
    return 2.868 * (mstar ** 2 / (rstar * estar ** 2 * v)) ** 0.2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dist", required=True, choices=["equal", "bidisperse", "lognormal"])
    ap.add_argument("--mu", type=float, required=True)
    ap.add_argument("--n", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=12345)
    ap.add_argument("--out", required=True)
    ap.add_argument("--settle", type=float, default=MAX_SETTLE,
                    help=f"cap on the final settling time in sqrt(d/g) (default {MAX_SETTLE:g})")
    ap.add_argument("--cohesion", choices=sorted(PULLOFF_PER_GAMMA_R),
                    help="cohesive normal model instead of hertz/material (needs --bond)")
    ap.add_argument("--bond", type=float,
                    help="Bond number F_pulloff / (m_ref g) of two d = 1 spheres (R* = 1/4)")
    a = ap.parse_args()
    if (a.cohesion is None) != (a.bond is None):
        ap.error("--cohesion and --bond go together")
    os.makedirs(a.out, exist_ok=True)

    ds = diameters(a.dist, a.n, a.seed)
    rng = random.Random(a.seed + 1)
    batches = [ds[i:i + BATCH] for i in range(0, len(ds), BATCH)]
    dmin, dmax = min(ds), max(ds)
    hmax = 0.0
    for k, b in enumerate(batches):
        pos, h = cloud(b, rng)
        hmax = max(hmax, h)
        with open(os.path.join(a.out, f"batch_{k:02d}.data"), "w") as f:
            f.write(f"batch {k} of the {a.dist} pour (seed {a.seed})\n\n{len(b)} atoms\n1 atom types\n\n")
            f.write(f"0 {L} xlo xhi\n0 {L} ylo yhi\n0 {h} zlo zhi\n\nAtoms # sphere\n\n")
            for i, (d, (x, y, z)) in enumerate(zip(b, pos)):
                f.write(f"{i + 1} 1 {d:.12g} {RHO} {x:.12g} {y:.12g} {z:.12g}\n")

    # timestep: fastest impact is a fall from the cloud top; smallest pair
    vmax = math.sqrt(2 * G * hmax) + 0.5
    tc = hertz_tc(dmin, dmin, vmax)
    dt = DT_FRACTION * tc
    t_batch = math.sqrt(2 * hmax / G) + 2.0          # fall time of a batch + landing
    steps_batch = int(math.ceil(t_batch / dt))
    vol = sum(math.pi / 6 * d ** 3 for d in ds)
    zhi = vol / (L * L * 0.5) + hmax + 5 * dmax      # bed at phi >= 0.5 + one cloud + margin
    settle_steps = int(a.settle / dt)
    skin = 0.3 * dmax
    normal = f"hertz/material {E:g} {E_REST} {NU}"
    cohesion_note = ""
    if a.cohesion:
        # gamma such that F_pulloff(d = 1 pair, R* = 1/4) = bond * m_ref * g
        gamma = a.bond * M_REF * G / (PULLOFF_PER_GAMMA_R[a.cohesion] * 0.25)
        normal = f"{a.cohesion} {E:g} {E_REST} {NU} {gamma:.10g}"
        cohesion_note = (f"# cohesion: {a.cohesion}, gamma = {gamma:.10g}: pull-off of a d = 1 pair "
                         f"= {a.bond:g} m_ref g (Bond number); floor: same gamma\n")

    lines = f"""# DEM pour written by pour.py: {a.dist}, mu = {a.mu}, N = {a.n}, seed {a.seed}
# units lj: d = 1, rho = {RHO}, g = {G}; m_ref = pi/6
# E = {E:g}, nu = {NU}, e = {E_REST} (tsuji), x_gamma_t = {XGAMMA_T}, mu = {a.mu}
{cohesion_note}# Hertz collision time (d_min = {dmin:.4f}, v = {vmax:.3f}) = {tc:.4e}; dt = {dt:.4e}
# {len(batches)} batches of <= {BATCH}; cloud phi {PHI_CLOUD}; batch run {t_batch:.3f} ({steps_batch} steps)
units           lj
atom_style      sphere
dimension       3
boundary        p p f
newton          off
comm_modify     vel yes
region          box block 0 {L} 0 {L} 0 {zhi:.6g}
create_box      1 box
pair_style      granular
pair_coeff      * * {normal} tangential mindlin NULL {XGAMMA_T} {a.mu} damping tsuji
neighbor        {skin:.4g} bin
neigh_modify    delay 0 every 1 check yes
timestep        {dt:.6e}
fix             integ all nve/sphere
fix             grav all gravity {G} vector 0 0 -1
fix             floor all wall/gran granular {normal} tangential mindlin NULL {XGAMMA_T} {a.mu} damping tsuji zplane 0.0 NULL
compute         prop all property/atom omegax omegay omegaz radius mass
variable        erot atom 0.2*c_prop[5]*c_prop[4]^2*(c_prop[1]^2+c_prop[2]^2+c_prop[3]^2)
compute         rke all reduce sum v_erot
compute         tke all ke
variable        kep equal (c_tke+c_rke)/atoms/{M_REF:.10g}
variable        ztop equal bound(all,zmax)
variable        speed atom sqrt(vx^2+vy^2+vz^2)
compute         vmax all reduce max v_speed
thermo_style    custom step time atoms c_tke c_rke v_kep c_vmax v_ztop cpu
thermo_modify   lost error norm no flush yes
thermo          5000
"""
    for k in range(len(batches)):
        shift = "0.0" if k == 0 else "${ztop}"
        lines += f"read_data       batch_{k:02d}.data add append shift 0.0 0.0 {shift}\n"
        lines += f"run             {steps_batch}\n"
    lines += f"""# settle: stop when KE per particle < {KE_TOL:g} m_ref g d (checked every 1000 steps)
fix             halt all halt 1000 v_kep < {KE_TOL:g} error continue
run             {settle_steps}
unfix           halt
run             0 post no
print           "FINAL kep ${{kep}} vmax $(c_vmax) time $(time) step $(step)"
write_dump      all custom bed.dump id radius x y z vx vy vz modify sort id
"""
    with open(os.path.join(a.out, "in.pour"), "w") as f:
        f.write(lines)
    print(f"{a.out}: {len(batches)} batches, dt {dt:.3e} (t_c {tc:.3e}), box height {zhi:.1f}")


if __name__ == "__main__":
    main()
