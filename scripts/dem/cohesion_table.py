#!/usr/bin/env python3
"""Cohesive DEM pours (equal, mu = 0.3, JKR, Bond number 1, 10, 100) against
packbed's `sticking = p` sweep (equal, seeds 1-3; and, if run, restitution 0.5 + sticking p): the p whose bulk phi matches
each DEM bed, by linear interpolation of the seed-mean phi(p), and Z of both.
Also the per-run wall time and max RSS of every run in WORK.

Usage: cohesion_table.py WORK   (the folders gr-cohesion.sh makes)"""
import glob
import json
import os
import re
import statistics as st
import sys

import numpy as np

W = sys.argv[1]
PS = ["0", "0.05", "0.1", "0.15", "0.2", "0.3", "0.4", "0.6"]
J = lambda p: json.load(open(p))


def time_rss(d):
    t = open(os.path.join(d, "time.txt")).read()
    w = re.search(r"Elapsed \(wall clock\) time.*: (\S+)", t).group(1).split(":")
    return (sum(float(x) * 60 ** k for k, x in enumerate(reversed(w))),
            int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024)


def final(d):
    """kep, vmax, time from the FINAL line of the LAMMPS log."""
    for line in open(os.path.join(d, "log.lammps")):
        if line.startswith("FINAL"):
            f = line.split()
    return float(f[2]), float(f[4]), float(f[6])


FAMILIES = [("stick", "`sticking = p`", PS),
            # extra: the momentum rule with sticking; its p = 0 bed is the `m0` bed
            ("m0stick", "`restitution = 0.5` + `sticking = p`", ["0", "0.05", "0.1", "0.15", "0.2", "0.3"])]


def beds(fam, p):
    rule = "m0" if (fam == "m0stick" and p == "0") else f"{fam}{p}"
    return [J(f) for f in sorted(glob.glob(f"{W}/packbed/equal_{rule}_s*/measure.json"))]


DEMS = (("equal_mu0.3", "0"), ("equal_mu0.3_jkr_bo1", "1"), ("equal_mu0.3_jkr_bo10", "10"),
        ("equal_mu0.3_jkr_bo100", "100"), ("equal_mu0.3_jkr_bo100_settle120", "100 (settle 120)"))
for fam, label, ps in FAMILIES:
    ps = [p for p in ps if len(beds(fam, p)) == 3]
    if not ps:
        continue
    f = lambda v, nd: f"{st.mean(v):.{nd}f} ± {st.stdev(v):.{nd}f}"
    print(f"\npackbed {label}, equal spheres, N = 2000, mean ± sd of seeds 1–3:\n")
    print("| p | φ bulk | Z 1e-6 | Z 1e-3 | rattlers |")
    print("|---|---|---|---|---|")
    for p in ps:
        ms = beds(fam, p)
        print(f"| {p} | {f([m['phi_bulk'] for m in ms], 4)} | {f([m['Z']['1e-6'] for m in ms], 3)} | "
              f"{f([m['Z']['1e-3'] for m in ms], 3)} | {f([m['rattlers_tol1e-3'] for m in ms], 3)} |")
    pv = np.array([float(p) for p in ps])
    phi = np.array([st.mean(m["phi_bulk"] for m in beds(fam, p)) for p in ps])
    zz = np.array([st.mean(m["Z"]["1e-6"] for m in beds(fam, p)) for p in ps])
    print(f"\nDEM equal µ = 0.3 (JKR cohesion) against the p of {label} with the same φ "
          "(linear interpolation of the seed means):\n")
    print("| DEM bed | Bo | φ bulk | Z 1e-6 | Z 1e-3 | rattlers | final KE/(m g d) | matched p | packbed Z at p | ΔZ (packbed − DEM) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, bo in DEMS:
        d = f"{W}/runs/{name}"
        if not os.path.exists(f"{d}/measure.json"):
            continue
        m = J(f"{d}/measure.json")
        x = m["phi_bulk"]
        if x > phi[0]:
            mp, zp = f"none: φ above p = 0 ({phi[0]:.4f})", float("nan")
        elif x < phi[-1]:
            mp, zp = f"none: φ below p = {ps[-1]} ({phi[-1]:.4f})", float("nan")
        else:   # phi(p) decreases: interpolate p and Z on the reversed arrays
            pm = float(np.interp(x, phi[::-1], pv[::-1]))
            zp = float(np.interp(pm, pv, zz))
            mp = f"{pm:.3f}"
        dz = f"{zp - m['Z']['1e-6']:+.2f}" if zp == zp else "–"
        zps = f"{zp:.2f}" if zp == zp else "–"
        print(f"| {name} | {bo} | {x:.4f} | {m['Z']['1e-6']:.3f} | {m['Z']['1e-3']:.3f} | "
              f"{m['rattlers_tol1e-3']:.3f} | {final(d)[0]:.1e} | {mp} | {zps} | {dz} |")

print("\nPer run: wall time (s) and max RSS (MiB), `/usr/bin/time -v`:\n")
print("| run | wall s | max RSS MiB | end time √(d/g) / final KE per particle (m g d) |")
print("|---|---|---|---|")
for d in sorted(glob.glob(f"{W}/runs/*/")):
    w, r = time_rss(d)
    ke, vmax, t = final(d)
    print(f"| DEM {os.path.basename(d.rstrip('/'))} | {w:.0f} | {r:.0f} | {t:.1f} / {ke:.1e} |")
print("\npackbed, one row per rule, the three seeds' runs (s1 / s2 / s3):\n")
print("| rule | wall s | max RSS MiB |")
print("|---|---|---|")
rules = sorted({os.path.basename(d.rstrip("/")).rsplit("_s", 1)[0] for d in glob.glob(f"{W}/packbed/*/")})
for rule in rules:
    tr = [time_rss(f"{W}/packbed/{rule}_s{k}") for k in (1, 2, 3)]
    print(f"| {rule} | " + " / ".join(f"{w:.2f}" for w, _ in tr) + " | "
          + " / ".join(f"{r:.1f}" for _, r in tr) + " |")
