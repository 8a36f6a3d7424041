#!/usr/bin/env python3
"""Measure a bed of rigid rods (straight chains of equal beads) on a floor at
z = 0, periodic in x and y: a LAMMPS dump of pour_rods.py (columns id mol
radius x y z) or a packbed particles.csv (id species body x y z r; give the
period with --box).  Prints JSON, and writes it with --json FILE.

Definitions (d = the bead diameter; measure.py's slab and contact tolerance):
  phi   = the beads' exact volume between z = 2 d and z = top - 3 d (top as
          measure.py) over the slab's volume (the beads of one rod touch and
          do not overlap, so their volumes add);
  rods in the slab = rods whose centre (mean of their beads) is in it;
  Z_rod = contacts of a rod with other rods and the floor: bead pairs of
          different rods at a gap <= 1e-6 r (every DEM overlap counts), plus
          beads on the floor; averaged over the rods in the slab;
  neighbours = distinct other rods a rod touches (the floor not counted);
  S     = <(3 cos^2 theta - 1) / 2> of the rods' axes (first bead to last)
          to the vertical, over the rods in the slab (-0.5: all flat), and
          theta's mean in degrees.
"""
import numpy as np
from scipy.spatial import cKDTree

from measure import cli, read_columns, slab_volume


def read_rods(path, box):
    """(x, y, z, r, rod index per bead in bead order, Lx, Ly): a LAMMPS dump's
    molecules or a packbed CSV's bodies are the rods."""
    c, Lx, Ly = read_columns(path, box)
    rod = c["mol"] if "mol" in c else c["body"]
    order = np.lexsort((c["id"], rod))
    return c["x"][order], c["y"][order], c["z"][order], c["r"][order], rod[order].astype(int), Lx, Ly


def measure(x, y, z, r, rod, Lx, Ly, tol=1e-6):
    n = len(r)
    d = 2 * float(r.max())
    k = max(1, int(round(0.1 * n)))
    top = float(np.percentile(np.sort(z + r)[-k:], 90))
    a, b = 2 * d, top - 3 * d
    out = {"beads": int(n), "Lx": Lx, "Ly": Ly, "d": d, "top": top, "slab": [a, b]}
    if b <= a:
        out["error"] = "bed too thin for a slab"
        return out
    out["phi_bulk"] = float(slab_volume(z, r, a, b).sum() / (Lx * Ly * (b - a)))
    ids, first, per = np.unique(rod, return_index=True, return_counts=True)
    nr = len(ids)
    index = np.searchsorted(ids, rod)                  # 0..nr-1 per bead
    out["rods"] = int(nr)
    out["beads_per_rod"] = sorted(set(int(v) for v in per))
    last = first + per - 1
    # rod axes: unwrap the last bead to the first by the minimum image
    ax = np.column_stack([x[last] - x[first], y[last] - y[first], z[last] - z[first]])
    ax[:, 0] -= Lx * np.round(ax[:, 0] / Lx)
    ax[:, 1] -= Ly * np.round(ax[:, 1] / Ly)
    cos = ax[:, 2] / np.linalg.norm(ax, axis=1)
    centre_z = np.bincount(index, weights=z) / per
    inslab = (centre_z >= a) & (centre_z <= b)
    out["rods_in_slab"] = int(inslab.sum())
    out["S"] = float((0.5 * (3 * cos[inslab] ** 2 - 1)).mean())
    out["theta_deg"] = float(np.degrees(np.arccos(np.abs(cos[inslab]))).mean())
    out["S_all"] = float((0.5 * (3 * cos ** 2 - 1)).mean())
    # contacts between beads of different rods (periodic x, y)
    zs = z - z.min()
    Lz = 4 * (zs.max() + 10 * d)
    P = np.column_stack([np.mod(x, Lx), np.mod(y, Ly), zs])
    P[:, 0][P[:, 0] >= Lx] = 0.0
    P[:, 1][P[:, 1] >= Ly] = 0.0
    pairs = cKDTree(P, boxsize=[Lx, Ly, Lz]).query_pairs(d * (1 + 1e-3), output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    dv = P[i] - P[j]
    dv[:, 0] -= Lx * np.round(dv[:, 0] / Lx)
    dv[:, 1] -= Ly * np.round(dv[:, 1] / Ly)
    gap = np.sqrt((dv ** 2).sum(1)) - r[i] - r[j]
    touch = (gap <= tol * np.minimum(r[i], r[j])) & (index[i] != index[j])
    ri, rj = index[i[touch]], index[j[touch]]
    floor = (z - r) <= tol * r
    zc = np.bincount(ri, minlength=nr) + np.bincount(rj, minlength=nr) + np.bincount(index[floor], minlength=nr)
    out["Z_rod"] = float(zc[inslab].mean())
    nb = np.zeros(nr, dtype=int)
    for p, q in {(min(u, v), max(u, v)) for u, v in zip(ri.tolist(), rj.tolist())}:
        nb[p] += 1
        nb[q] += 1
    out["neighbours"] = float(nb[inslab].mean())
    out["rods_on_fewer_than_3_contacts"] = float((zc[inslab] < 3).mean())
    if (gap[index[i] != index[j]] < 0).any():
        g = gap[(index[i] != index[j]) & (gap < 0)]
        out["overlap_over_d_mean"] = float((-g / d).mean())
    return out


def main():
    cli(__doc__, read_rods, measure)


if __name__ == "__main__":
    main()
