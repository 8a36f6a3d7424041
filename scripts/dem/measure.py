#!/usr/bin/env python3
"""Measure a packed bed of spheres on a floor at z = 0, periodic in x and y.

Reads a LAMMPS dump (`ITEM: ATOMS ... radius x y z`, the last frame is used;
the x/y period is read from ITEM: BOX BOUNDS) or a packbed particles.csv
(header with x, y, z, r; give the period with --box).  Prints JSON, and writes
it with --json FILE.

Definitions (d_max = largest diameter in the bed):
  top   = 90th percentile of the particle tops z + r among the 10 % of
          particles with the highest tops (i.e. ~ the 99th percentile of z + r);
  slab  = 2 d_max <= z <= top - 3 d_max  (horizontal, whole periodic width);
  phi   = exact solid volume in the slab (each sphere cut by the two planes,
          spherical caps/segments) / (L_x L_y slab height);
  contacts: i, j touch if gap = |x_i - x_j| - r_i - r_j <= tol * min(r_i, r_j)
          (minimum image in x, y); tol = 1e-6 (packbed's exact contacts),
          1e-3, 1e-2; and `overlap` = gap < 0 only (DEM contacts);
          the floor counts as a contact when z - r <= tol * r (none in the slab);
  Z     = mean contact number over particles whose centre is in the slab;
  rattlers = fraction of slab particles with < 4 contacts at tol 1e-3;
  g(r)  = radial distribution, r / d_ref from 0.8 to 4 in bins of 0.02, with
          d_ref = 2 * median radius; centres in the slab, neighbours anywhere,
          normalised by the slab number density (a pooled g(r) for mixtures).
"""
import argparse
import json
import sys

import numpy as np
from scipy.spatial import cKDTree

TOLS = {"1e-6": 1e-6, "1e-3": 1e-3, "1e-2": 1e-2}


def read_columns(path, box):
    """The columns of a bed by name, with x and y from 0, and its x, y
    period: the last frame of a LAMMPS dump (`radius` renamed `r`) or a
    packbed CSV (the period given as `box`)."""
    with open(path) as f:
        text = f.read()
    if text.startswith("ITEM:"):
        start = text.rfind("ITEM: TIMESTEP")
        lines = text[start:].splitlines()
        i = lines.index(next(l for l in lines if l.startswith("ITEM: BOX BOUNDS")))
        xb = [float(v) for v in lines[i + 1].split()[:2]]
        yb = [float(v) for v in lines[i + 2].split()[:2]]
        j = lines.index(next(l for l in lines if l.startswith("ITEM: ATOMS")))
        cols = ["r" if c == "radius" else c for c in lines[j].split()[2:]]
        data = np.array([l.split() for l in lines[j + 1:] if l.strip()], dtype=float)
        c = {name: data[:, k] for k, name in enumerate(cols)}
        c["x"], c["y"] = c["x"] - xb[0], c["y"] - yb[0]
        return c, xb[1] - xb[0], yb[1] - yb[0]
    header = text.splitlines()[0].split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if box is None:
        sys.exit("a CSV bed needs --box L (the x, y period)")
    return {name: data[:, k] for k, name in enumerate(header)}, box, box


def read_bed(path, box):
    """Return (x, y, z, r, Lx, Ly)."""
    c, Lx, Ly = read_columns(path, box)
    return c["x"], c["y"], c["z"], c["r"], Lx, Ly


def slab_volume(z, r, a, b):
    """Exact volume of each sphere between the planes z = a and z = b."""
    t1 = np.clip(a - z, -r, r)
    t2 = np.clip(b - z, -r, r)
    F = lambda t: r * r * t - t ** 3 / 3.0  # integral of (r^2 - t^2) dt
    return np.pi * (F(t2) - F(t1))


def measure(x, y, z, r, Lx, Ly):
    n = len(r)
    dmax = 2 * r.max()
    tops = z + r
    k = max(1, int(round(0.1 * n)))
    top = float(np.percentile(np.sort(tops)[-k:], 90))
    a, b = 2 * dmax, top - 3 * dmax
    out = {"n": int(n), "Lx": Lx, "Ly": Ly, "d_max": dmax, "d_min": 2 * float(r.min()),
           "top": top, "slab": [a, b]}
    if b <= a:
        out["error"] = "bed too thin for a slab"
        return out
    phi = slab_volume(z, r, a, b).sum() / (Lx * Ly * (b - a))
    out["phi_bulk"] = float(phi)

    # positions for a tree periodic in x, y (z period far larger than the bed)
    zshift = z - z.min()
    Lz = 4 * (zshift.max() + 10 * dmax)
    P = np.column_stack([np.mod(x, Lx), np.mod(y, Ly), zshift])
    P[:, 0][P[:, 0] >= Lx] = 0.0
    P[:, 1][P[:, 1] >= Ly] = 0.0
    tree = cKDTree(P, boxsize=[Lx, Ly, Lz])
    maxtol = max(TOLS.values())
    pairs = tree.query_pairs(dmax * (1 + maxtol), output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    d = P[i] - P[j]
    d[:, 0] -= Lx * np.round(d[:, 0] / Lx)
    d[:, 1] -= Ly * np.round(d[:, 1] / Ly)
    dist = np.sqrt((d ** 2).sum(1))
    gap = dist - r[i] - r[j]
    rmin = np.minimum(r[i], r[j])
    inslab = (z >= a) & (z <= b)
    ns = int(inslab.sum())
    out["n_slab"] = ns

    def counts(mask_pairs, floor_mask):
        c = np.bincount(i[mask_pairs], minlength=n) + np.bincount(j[mask_pairs], minlength=n)
        return c + floor_mask.astype(int)

    Z = {}
    cn = {}
    for name, tol in TOLS.items():
        c = counts(gap <= tol * rmin, (z - r) <= tol * r)
        cn[name] = c
        Z[name] = float(c[inslab].mean())
    c_ov = counts(gap < 0, (z - r) < 0)
    Z["overlap"] = float(c_ov[inslab].mean())
    out["Z"] = Z
    out["rattlers_tol1e-3"] = float((cn["1e-3"][inslab] < 4).mean())
    hist = np.bincount(cn["1e-3"][inslab], minlength=13)
    out["contact_hist_tol1e-3"] = {str(k): int(v) for k, v in enumerate(hist)}
    hist6 = np.bincount(cn["1e-6"][inslab], minlength=13)
    out["contact_hist_tol1e-6"] = {str(k): int(v) for k, v in enumerate(hist6)}
    # overlaps of touching pairs with at least one centre in the slab, relative to d = 2 r_min
    sel = (gap < 0) & (inslab[i] | inslab[j])
    if sel.any():
        ov = -gap[sel] / (2 * rmin[sel])
        out["overlap_over_d"] = {"mean": float(ov.mean()), "p99": float(np.percentile(ov, 99)),
                                 "max": float(ov.max())}
    # also the whole-bed overlap maximum
    if (gap < 0).any():
        out["overlap_over_d_max_all"] = float((-gap[gap < 0] / (2 * rmin[gap < 0])).max())

    # g(r): centres in the slab, neighbours anywhere, in units of d_ref
    dref = 2 * float(np.median(r))
    edges = np.arange(0.8, 4.0 + 1e-9, 0.02)
    sd = tree.sparse_distance_matrix(cKDTree(P[inslab], boxsize=[Lx, Ly, Lz]),
                                     4.0 * dref, output_type="ndarray")
    rr = sd["v"][sd["v"] > 0] / dref
    h, _ = np.histogram(rr, bins=edges)
    rho = ns / (Lx * Ly * (b - a))
    shell = 4.0 / 3.0 * np.pi * ((edges[1:] * dref) ** 3 - (edges[:-1] * dref) ** 3)
    g = h / (ns * rho * shell)
    out["g_r"] = {"d_ref": dref, "r_over_d": [round(float(v), 4) for v in 0.5 * (edges[1:] + edges[:-1])],
                  "g": [round(float(v), 5) for v in g]}
    return out


def cli(doc, read, fn, hide=()):
    """The command line of a measure: BED [--box L] [--json FILE]; prints the
    JSON without the keys in `hide`, writes all of it to FILE."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bed")
    ap.add_argument("--box", type=float, help="x, y period of a CSV bed")
    ap.add_argument("--json", help="write the JSON here too")
    a = ap.parse_args()
    out = fn(*read(a.bed, a.box))
    out["file"] = a.bed
    if a.json:
        with open(a.json, "w") as f:
            f.write(json.dumps(out, indent=1) + "\n")
    print(json.dumps({k: v for k, v in out.items() if k not in hide}))


def main():
    cli(__doc__, read_bed, measure, hide=("g_r",))


if __name__ == "__main__":
    main()
