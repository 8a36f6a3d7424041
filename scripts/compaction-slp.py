#!/usr/bin/env python3
"""A prototype, not part of packbed: compaction of a settled bed of
frictionless spheres by minimising its potential energy, one linear
programme per step (sequential linear programming).

Each step moves every sphere by at most `delta` per axis and minimises
sum(m_i dz_i) (m_i ~ r_i^3) subject to, for each pair within reach,

    n_ij . (dx_i - dx_j) >= -gap_ij        (n_ij the unit vector from j to i)

and the floor. The distance is a convex function of the positions, so it is
at least its linearisation: a step that keeps the linear constraint keeps the
pair apart exactly (up to the LP solver's tolerance). Collective moves lower
the energy where the one-at-a-time settling of packbed cannot.

Reads a packbed particles.csv of spheres periodic in x and y (period --box)
on a floor at z = 0; writes the compacted bed in the same columns. Prints
the step, the energy, and the bulk solid fraction (the slab 2 d above the
floor to 3 d below the 99th percentile of the tops, as scripts/dem/measure.py).

    python3 scripts/compaction-slp.py bed/particles.csv out.csv --steps 80 --delta 0.05 --box 10

Needs numpy and scipy (HiGHS). docs/settling.md, "Not yet", has what it gave.
"""
import argparse
import math
import time

import numpy as np
from scipy.optimize import linprog
from scipy.sparse import coo_matrix
from scipy.spatial import cKDTree


def bulk_phi(x, r, box):
    top = np.quantile(x[:, 2] + r, 0.99)
    lo = 2.0 * (2 * r.max())
    hi = top - 3.0 * (2 * r.max())
    v = 0.0
    for zi, ri in zip(x[:, 2], r):
        a, b = max(lo, zi - ri), min(hi, zi + ri)
        if b > a:
            f = lambda t: math.pi * (ri * ri * t - t ** 3 / 3)
            v += f(b - zi) - f(a - zi)
    return v / (box * box * (hi - lo)), top


def step(x, r, m, box, delta):
    n = len(r)
    tree = cKDTree(np.c_[x[:, 0] % box, x[:, 1] % box, x[:, 2]], boxsize=[box, box, 1e9])
    reach = 2 * math.sqrt(3) * delta
    pairs = tree.query_pairs(2 * r.max() + reach, output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    d = x[i] - x[j]
    d[:, :2] -= box * np.round(d[:, :2] / box)
    dist = np.linalg.norm(d, axis=1)
    gap = dist - r[i] - r[j]
    keep = gap < reach
    i, j, nv, gap = i[keep], j[keep], (d / dist[:, None])[keep], gap[keep]
    k = len(i)
    rows = np.repeat(np.arange(k), 6)
    cols = np.c_[3 * i, 3 * i + 1, 3 * i + 2, 3 * j, 3 * j + 1, 3 * j + 2].ravel()
    vals = np.c_[nv, -nv].ravel()
    a_ub = coo_matrix((-vals, (rows, cols)), shape=(k, 3 * n)).tocsr()
    c = np.zeros(3 * n)
    c[2::3] = m
    lb = np.full(3 * n, -delta)
    ub = np.full(3 * n, delta)
    lb[2::3] = np.maximum(-delta, r - x[:, 2])
    res = linprog(c, A_ub=a_ub, b_ub=gap, bounds=np.c_[lb, ub], method="highs-ipm")
    if res.status != 0:
        raise SystemExit(f"LP failed: {res.message}")
    x = x + res.x.reshape(n, 3)
    x[:, 0] %= box
    x[:, 1] %= box
    return x, k


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bed")
    ap.add_argument("out")
    ap.add_argument("--steps", type=int, default=80)
    ap.add_argument("--delta", type=float, default=0.05)
    ap.add_argument("--box", type=float, required=True)
    a = ap.parse_args()
    t = np.loadtxt(a.bed, delimiter=",", skiprows=1)
    x, r = t[:, 3:6].copy(), t[:, 6]
    m = (r / r.max()) ** 3
    print("start phi %.4f top %.3f" % bulk_phi(x, r, a.box), flush=True)
    for s in range(a.steps):
        t0 = time.time()
        x, k = step(x, r, m, a.box, a.delta)
        phi, top = bulk_phi(x, r, a.box)
        print(f"{s} E {(m * x[:, 2]).sum():.3f} phi {phi:.4f} top {top:.3f} pairs {k} {time.time() - t0:.1f} s", flush=True)
    n = len(r)
    np.savetxt(a.out, np.c_[np.arange(n), np.zeros(n), np.arange(n), x, r], delimiter=",",
               header="id,species,body,x,y,z,r", comments="", fmt=["%d", "%d", "%d", "%.17g", "%.17g", "%.17g", "%.17g"])


if __name__ == "__main__":
    main()
