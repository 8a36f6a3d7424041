#!/usr/bin/env python3
"""Fit the cohesion law's d_c to a published porosity-against-size relation,
and check the fitted law against a relation it was not fitted to.

The law (docs/settling.md; its fit: docs/settling-validation.md): a particle
of diameter d sticks at a new contact with probability p = 1 / (1 + (d / d_c)^n).  Its two parameters are fitted
here to Wu & Wang (2006), the porosity of freshly deposited sediment against
its median diameter, and compared with Komura (1963), which was not used in
the fit.  Both are correlations of measured porosities of particles settled
from water, as a filter cake settles from its slurry.

Two steps:
  1. porosity against p: equal spheres settled with `sticking = p` on a grid
     of p (3D, periodic, bulk porosity), seeds 1..S;
  2. (d_c, n) minimising the squared difference between porosity(p(d)) and
     Wu & Wang's porosity at diameters 1..100 um (log-spaced), by a grid
     search on log d_c and n (two parameters: a fine grid is exact enough);
     the same with n = 2 held (the single-adhesion-force law) for contrast;
then a check: new beds settled with the fitted `cohesion_diameter` and
`cohesion_exponent`, in micrometres, against both correlations: equal
spheres of each diameter, and lognormal powders (gsd 1.5) by median.

Usage, from the repository root after `cargo build --release`:
    python3 scripts/cohesion-fit.py [--seeds 3] [--count 20000] [--plot F.png]
Prints Markdown tables; the plot needs matplotlib (skipped, with a line,
without it).
"""
import argparse
import math
import tempfile

from settling_bed import settle

# Fit and check diameters, micrometres.
DIAMETERS = [1, 2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100]
STICKING = [0.0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]


def wu_wang(d_um):
    """Wu & Wang (2006), J. Hydraul. Eng. 132(8) 858: porosity of deposited
    sediment, d50 in mm."""
    return 0.13 + 0.21 / (d_um / 1000.0 + 0.002) ** 0.21


def komura(d_um):
    """Komura (1963), as quoted by Wu & Wang (2006): d50 in mm."""
    return 0.245 + 0.0864 / (0.1 * d_um / 1000.0) ** 0.21


def sticking_of(d, d_c, n):
    return 1.0 / (1.0 + (d / d_c) ** n)


def bulk_porosity(settling_line, radius, seed, count, work, gsd=None):
    """One bed of spheres (equal, or lognormal of median radius `radius`),
    3D periodic, box 40 x 40 radii."""
    size = f"radius = {radius}" if gsd is None else \
        f'size = {{ dist = "lognormal", median = {radius}, gsd = {gsd} }}'
    v = settle(work, seed=seed, count=count, width=40.0 * radius, size=size,
               rule=settling_line, measures=["packing"])
    return 1.0 - v["packing"]["bulk"]


def mean_sd(xs):
    m = sum(xs) / len(xs)
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else 0.0
    return m, sd


def interpolate(curve, p):
    """Porosity at p, linear between the grid's points (porosity rises with p)."""
    for (p0, e0), (p1, e1) in zip(curve, curve[1:]):
        if p0 <= p <= p1:
            return e0 + (e1 - e0) * (p - p0) / (p1 - p0)
    return curve[-1][1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--count", type=int, default=20000)
    ap.add_argument("--plot")
    args = ap.parse_args()
    seeds = range(1, args.seeds + 1)
    work = tempfile.mkdtemp()

    curve = []
    print("Porosity against the sticking probability (equal spheres, bulk):\n")
    print("| p | porosity |\n|---|---|")
    for p in STICKING:
        m, sd = mean_sd([bulk_porosity(f"sticking = {p}", 1.0, s, args.count, work) for s in seeds])
        curve.append((p, m))
        print(f"| {p:g} | {m:.3f} ± {sd:.3f} |")

    def fit(exponents):
        best = None
        for i in range(0, 1501):
            d_c = 10 ** (-1.0 + i * 0.002)
            for n in exponents:
                sse = sum((interpolate(curve, sticking_of(d, d_c, n)) - wu_wang(d)) ** 2
                          for d in DIAMETERS)
                if best is None or sse < best[0]:
                    best = (sse, d_c, n)
        return best[1], best[2], math.sqrt(best[0] / len(DIAMETERS))

    d_c2, _, rms2 = fit([2.0])
    d_c, n, rms = fit([k * 0.01 for k in range(10, 401)])
    print(f"\nFitted to Wu & Wang at {len(DIAMETERS)} diameters 1-100 um:")
    print(f"- n held at 2: d_c = {d_c2:.2f} um, rms residual {rms2:.3f}")
    print(f"- both free:   d_c = {d_c:.2f} um, n = {n:.2f}, rms residual {rms:.3f}\n")
    d_c, n = round(d_c, 1), round(n, 2)
    law = f"cohesion_diameter = {d_c}\ncohesion_exponent = {n}"

    print(f"Check: new beds settled with cohesion_diameter = {d_c}, cohesion_exponent = {n}:\n")
    print("| bed | d or d50 (µm) | p at d | packbed porosity | Wu & Wang 2006 (fitted) | Komura 1963 (not fitted) |")
    print("|---|---|---|---|---|---|")
    rows = []
    beds = [("equal", d, None) for d in DIAMETERS] + [("lognormal gsd 1.5", d, 1.5) for d in (5, 20, 60)]
    for kind, d, gsd in beds:
        m, sd = mean_sd([bulk_porosity(law, d / 2.0, s, args.count, work, gsd) for s in seeds])
        rows.append((kind, d, m, sd))
        print(f"| {kind} | {d} | {sticking_of(d, d_c, n):.3f} | {m:.3f} ± {sd:.3f} | "
              f"{wu_wang(d):.3f} | {komura(d):.3f} |")
    for name, f in (("Wu & Wang", wu_wang), ("Komura", komura)):
        for kind in ("equal", "lognormal gsd 1.5"):
            res = [m - f(d) for k, d, m, _ in rows if k == kind]
            rms_k = math.sqrt(sum(r * r for r in res) / len(res))
            print(f"\nAgainst {name}, {kind}: rms {rms_k:.3f}, "
                  f"largest |difference| {max(abs(r) for r in res):.3f}")

    if args.plot:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("\nno matplotlib: plot skipped")
            return
        fine = [10 ** (i / 50.0) for i in range(0, 151)]
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(fine, [wu_wang(d) for d in fine], "-", label="Wu & Wang 2006 (fitted to)")
        ax.plot(fine, [komura(d) for d in fine], "--", label="Komura 1963 (not fitted to)")
        eq = [r for r in rows if r[0] == "equal"]
        ln = [r for r in rows if r[0] != "equal"]
        ax.errorbar([r[1] for r in eq], [r[2] for r in eq], yerr=[r[3] for r in eq], fmt="o",
                    label=f"packbed, equal spheres, d_c = {d_c} µm, n = {n}")
        ax.errorbar([r[1] for r in ln], [r[2] for r in ln], yerr=[r[3] for r in ln], fmt="s",
                    label="packbed, lognormal gsd 1.5 (by d50)")
        ax.set_xscale("log")
        ax.set_xlabel("particle diameter (µm)")
        ax.set_ylabel("porosity")
        ax.legend(loc="lower left", fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"\nplot: {args.plot}")


if __name__ == "__main__":
    main()
