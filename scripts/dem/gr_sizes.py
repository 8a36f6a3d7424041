#!/usr/bin/env python3
"""g(r) of the size distributions side by side: the bidisperse (d = 1 and
1.4, 1 : 1 by number) and lognormal (median 1, gsd 1.3) DEM pours at
mu = 0, 0.3, 0.6 and packbed's default and `restitution = 0.5` rules (mean of
seeds 1-3), from the g_r of each measure.json (measure.py: centres in the
slab, bins of 0.02 d_ref, d_ref = twice the bed's median radius).

measure.py's d_ref is the bed's own: a packbed bed of the 1 : 1 mix draws its
species at random, so its median diameter is 1 or 1.4 as the draw falls
(1.2 in the pours, exactly 1,000 of each). Every curve is therefore put back
in the pours' unit d = 1 (the bidisperse mix's small diameter, the
lognormal's median) and interpolated onto one grid, 1.13-3.99 d in steps of
0.02 d, before it is averaged or compared.

Usage: gr_sizes.py WORK [--png FILE]
  WORK/runs/DIST_mu{0,0.3,0.6}/measure.json and
  WORK/packbed/DIST_{default,m0}_s{1,2,3}/measure.json  (gr-sizes.sh makes them)

A mixture's contacts lie at several distances (the bidisperse pairs at 1,
1.2 and 1.4 d; the lognormal's anywhere from 0.46 to 2.2 d), so the contact
peaks are not compared bin by bin as for equal spheres (gr_plot.py). Printed
per distribution: the mean g over 1.22-1.30 d (just past the contacts of a
small and a large sphere of the mix: its near-contacts), the first minimum
past the bidisperse contacts (3-bin running mean, 1.45-2.1 d), the highest
point of the running mean in 1.8-2.9 d (the second shell), and the rms of
g_packbed - g_DEM over 1.45-3.99 d (past every bidisperse contact),
1.45-2.39 and 2.41-3.99, beside the same rms between the DEM pours and
between packbed's seeds.
"""
import argparse
import json
import os
import statistics as st

import numpy as np

from gr_plot import load_g

DISTS = ("bidisperse", "lognormal")
MUS = ("0", "0.3", "0.6")
RULES = (("packbed default", "default"), ("packbed restitution 0.5", "m0"))
RANGES = (("1.45–3.99", 1.44, 4.0), ("1.45–2.39", 1.44, 2.4), ("2.41–3.99", 2.4, 4.0))
GRID = np.arange(1.13, 4.0, 0.02)


def load_abs(path):
    """A bed's g on GRID, r in the pours' unit d = 1."""
    r, g, _ = load_g(path)
    d_ref = json.load(open(os.path.join(path, "measure.json")))["g_r"]["d_ref"]
    return GRID, np.interp(GRID, r * d_ref, g)


def running(g):
    return np.convolve(g, np.ones(3) / 3, mode="same")


def features(r, g):
    sm = running(g)
    sel = np.nonzero((r > 1.45) & (r < 2.1))[0]
    k = sel[np.argmin(sm[sel])]
    sel2 = np.nonzero((r > 1.8) & (r < 2.9))[0]
    k2 = sel2[np.argmax(sm[sel2])]
    near = (r > 1.21) & (r < 1.31)
    return {"rmin": r[k], "gmin": sm[k], "rpk": r[k2], "gpk": sm[k2], "near": float(g[near].mean())}


def rms(x, y, r, lo, hi):
    sel = (r > lo) & (r < hi)
    return float(np.sqrt(np.mean((x[sel] - y[sel]) ** 2)))


def curves_of(work, dist):
    """name -> (r, mean g, [g of each bed])."""
    out = {}
    for mu in MUS:
        r, g = load_abs(os.path.join(work, "runs", f"{dist}_mu{mu}"))
        out[f"DEM µ = {mu}"] = (r, g, [g])
    for name, rule in RULES:
        gs = []
        for s in (1, 2, 3):
            r, g = load_abs(os.path.join(work, "packbed", f"{dist}_{rule}_s{s}"))
            gs.append(g)
        out[name] = (r, np.mean(gs, axis=0), gs)
    return out


def table(dist, curves):
    print(f"\n### {dist}\n")
    dem = [n for n in curves if n.startswith("DEM")]
    print("| bed | g(1.22–1.30 d) | first minimum (r/d, g) | second shell's peak (r/d, g) | rms to "
          + " / ".join(dem) + " (1.45–3.99 d) |")
    print("|---|---|---|---|---|")
    for name, (r, g, gs) in curves.items():
        fs = [features(r, x) for x in gs]

        def cell(key, nd):
            v = [f[key] for f in fs]
            return f"{v[0]:.{nd}f}" if len(v) == 1 else f"{st.mean(v):.{nd}f} ± {st.stdev(v):.{nd}f}"
        to_dem = "–" if name.startswith("DEM") else " / ".join(
            f"{rms(g, curves[n][1], r, 1.44, 4.0):.3f}" for n in dem)
        print(f"| {name} | {cell('near', 2)} | {cell('rmin', 2)}, {cell('gmin', 2)} | {cell('rpk', 2)}, {cell('gpk', 2)} | {to_dem} |")
    print("\nrms per range (near, far):")
    for name, _ in RULES:
        r, g, _ = curves[name]
        print(f"- {name}: " + "; ".join(
            n + " " + ", ".join(f"{rms(g, curves[n][1], r, lo, hi):.3f} ({lab})" for lab, lo, hi in RANGES[1:])
            for n in dem))
    r = curves[dem[0]][0]
    for x, y in ((dem[1], dem[2]), (dem[0], dem[1]), (RULES[0][0], RULES[1][0])):
        print(f"- {x} vs {y}: " + ", ".join(
            f"{rms(curves[x][1], curves[y][1], r, lo, hi):.3f} ({lab})" for lab, lo, hi in RANGES))
    for name, _ in RULES:
        gs = curves[name][2]
        noise = [np.mean([rms(gs[i], gs[j], r, lo, hi) for i, j in ((0, 1), (0, 2), (1, 2))])
                 for _, lo, hi in RANGES]
        print(f"- {name}, one seed vs another: "
              + ", ".join(f"{v:.3f} ({lab})" for v, (lab, _, _) in zip(noise, RANGES)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("work")
    ap.add_argument("--png")
    a = ap.parse_args()
    every = {dist: curves_of(a.work, dist) for dist in DISTS}
    for dist, curves in every.items():
        table(dist, curves)
    if a.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(len(DISTS), 1, figsize=(8, 8))
        style = {"DEM µ = 0": ("C0", "-"), "DEM µ = 0.3": ("C1", "-"), "DEM µ = 0.6": ("C3", "-"),
                 "packbed default": ("k", "--"), "packbed restitution 0.5": ("C2", "--")}
        for ax, (dist, curves) in zip(axes, every.items()):
            for name, (r, g, _) in curves.items():
                c, ls = style[name]
                label = name + (" (mean of seeds 1–3)" if name.startswith("packbed") else "")
                ax.plot(r, g, color=c, ls=ls, lw=1.2, label=label, drawstyle="steps-mid")
            ax.set_xlim(1.1, 4.0)
            ax.set_ylim(0, 4)
            ax.set_ylabel("g(r) (contact peaks off scale)")
            ax.set_title(f"{dist}, N = 2000, 10 × 10 d periodic: g(r)")
            ax.legend(fontsize=8)
        axes[-1].set_xlabel("r / d (d: the small diameter, or the median)")
        fig.tight_layout()
        fig.savefig(a.png, dpi=110)
        print(f"\nwrote {a.png}")


if __name__ == "__main__":
    main()
