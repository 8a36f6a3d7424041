#!/usr/bin/env python3
"""Cohesive DEM pours (mu = 0.3, JKR, Bond number 1, 10, 100) against
packbed's `sticking = p` sweep (seeds 1-3; and, if run, restitution 0.5 + sticking p)
of the same size distribution: the p whose bulk phi matches
each DEM bed, by linear interpolation of the seed-mean phi(p), and Z of both.
Also the per-run wall time and max RSS of every run of that distribution in WORK.

Usage: cohesion_table.py WORK [--dist equal|bidisperse|lognormal]
  (the folders gr-cohesion.sh makes for equal spheres, cohesion-sizes.sh for the
  other two; default equal)"""
import argparse
import glob
import json
import os
import re
import statistics as st

import numpy as np

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("work")
ap.add_argument("--dist", default="equal", choices=["equal", "bidisperse", "lognormal"])
A = ap.parse_args()
W, DIST = A.work, A.dist
NAMES = {"equal": "equal spheres", "bidisperse": "bidisperse (d = 1 and 1.4, 1:1 by number)",
         "lognormal": "lognormal (median d = 1, gsd 1.3)"}
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


DCS = ["0.1", "0.2", "0.3", "0.4", "0.5", "0.7"]
FAMILIES = [("stick", "`sticking = p`", PS, "p"),
            # extra: the momentum rule with sticking; its p = 0 bed is the `m0` bed
            ("m0stick", "`restitution = 0.5` + `sticking = p`", ["0", "0.05", "0.1", "0.15", "0.2", "0.3"], "p"),
            # extra (cohesion-sizes.sh dc): the size-dependent law, n = 2
            ("dc", "`cohesion_diameter = d_c` (n = 2)", DCS, "d_c")]


def beds(fam, p, dist=None):
    rule = "m0" if (fam == "m0stick" and p == "0") else f"{fam}{p}"
    return [J(f) for f in sorted(glob.glob(f"{W}/packbed/{dist or DIST}_{rule}_s*/measure.json"))]


def match(x, pv, phi):
    """the parameter at which the decreasing phi(pv) equals x (None if outside)"""
    if x > phi[0] or x < phi[-1]:
        return None
    return float(np.interp(x, phi[::-1], pv[::-1]))


DEMS = ((f"{DIST}_mu0.3", "0"), (f"{DIST}_mu0.3_jkr_bo1", "1"), (f"{DIST}_mu0.3_jkr_bo10", "10"),
        (f"{DIST}_mu0.3_jkr_bo10_settle120", "10 (settle 120)"), (f"{DIST}_mu0.3_jkr_bo100", "100"),
        (f"{DIST}_mu0.3_jkr_bo100_settle120", "100 (settle 120)"))
for fam, label, ps, sym in FAMILIES:
    ps = [p for p in ps if len(beds(fam, p)) == 3]
    if not ps:
        continue
    f = lambda v, nd: f"{st.mean(v):.{nd}f} ± {st.stdev(v):.{nd}f}"
    print(f"\npackbed {label}, {NAMES[DIST]}, N = 2000, mean ± sd of seeds 1–3:\n")
    print(f"| {sym} | φ bulk | Z 1e-6 | Z 1e-3 | rattlers |")
    print("|---|---|---|---|---|")
    for p in ps:
        ms = beds(fam, p)
        print(f"| {p} | {f([m['phi_bulk'] for m in ms], 4)} | {f([m['Z']['1e-6'] for m in ms], 3)} | "
              f"{f([m['Z']['1e-3'] for m in ms], 3)} | {f([m['rattlers_tol1e-3'] for m in ms], 3)} |")
    pv = np.array([float(p) for p in ps])
    phi = np.array([st.mean(m["phi_bulk"] for m in beds(fam, p)) for p in ps])
    zz = np.array([st.mean(m["Z"]["1e-6"] for m in beds(fam, p)) for p in ps])
    print(f"\nDEM {DIST} µ = 0.3 (JKR cohesion) against the {sym} of {label} with the same φ "
          "(linear interpolation of the seed means):\n")
    print(f"| DEM bed | Bo | φ bulk | Z 1e-6 | Z 1e-3 | rattlers | final KE/(m g d) | matched {sym} | packbed Z at {sym} | ΔZ (packbed − DEM) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, bo in DEMS:
        d = f"{W}/runs/{name}"
        if not os.path.exists(f"{d}/measure.json"):
            continue
        m = J(f"{d}/measure.json")
        x = m["phi_bulk"]
        if x > phi[0]:
            mp, zp = f"none: φ above {sym} = {ps[0]} ({phi[0]:.4f})", float("nan")
        elif x < phi[-1]:
            mp, zp = f"none: φ below {sym} = {ps[-1]} ({phi[-1]:.4f})", float("nan")
        else:   # phi(p) decreases: interpolate p and Z on the reversed arrays
            pm = float(np.interp(x, phi[::-1], pv[::-1]))
            zp = float(np.interp(pm, pv, zz))
            mp = f"{pm:.3f}"
        dz = f"{zp - m['Z']['1e-6']:+.2f}" if zp == zp else "–"
        zps = f"{zp:.2f}" if zp == zp else "–"
        print(f"| {name} | {bo} | {x:.4f} | {m['Z']['1e-6']:.3f} | {m['Z']['1e-3']:.3f} | "
              f"{m['rattlers_tol1e-3']:.3f} | {final(d)[0]:.1e} | {mp} | {zps} | {dz} |")
    if fam != "dc" or DIST == "equal":
        continue
    # does the law carry the equal-sphere match to this distribution?  The p matched
    # on the equal pour of the same Bo gives d_c = sqrt(p / (1 - p)) (p at d = 1);
    # packbed's phi of this distribution at that d_c against its DEM pour.
    eps = [q for q in PS if len(beds("stick", q, "equal")) == 3]
    epv = np.array([float(q) for q in eps])
    ephi = np.array([st.mean(m["phi_bulk"] for m in beds("stick", q, "equal")) for q in eps])
    print(f"\nThe equal-sphere match carried to {DIST} by the law (d_c = √(p/(1−p)), p the "
          "`sticking` matched on the equal pour of the same Bo; packbed φ and Z interpolated at that d_c):\n")
    print("| Bo | equal DEM φ | matched p (equal) | d_c | packbed φ at d_c | packbed Z at d_c | DEM φ | DEM Z | Δφ (packbed − DEM) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, bo in DEMS:
        en = name.replace(DIST, "equal", 1)
        if not (os.path.exists(f"{W}/runs/{en}/measure.json") and os.path.exists(f"{W}/runs/{name}/measure.json")):
            continue
        ex, m = J(f"{W}/runs/{en}/measure.json")["phi_bulk"], J(f"{W}/runs/{name}/measure.json")
        pe = match(ex, epv, ephi)
        if pe is None:
            print(f"| {bo} | {ex:.4f} | none | – | – | – | {m['phi_bulk']:.4f} | {m['Z']['1e-6']:.3f} | – |")
            continue
        dc = (pe / (1 - pe)) ** 0.5
        if not pv[0] <= dc <= pv[-1]:
            print(f"| {bo} | {ex:.4f} | {pe:.3f} | {dc:.3f} (outside the sweep) | – | – | "
                  f"{m['phi_bulk']:.4f} | {m['Z']['1e-6']:.3f} | – |")
            continue
        ph, zd = float(np.interp(dc, pv, phi)), float(np.interp(dc, pv, zz))
        print(f"| {bo} | {ex:.4f} | {pe:.3f} | {dc:.3f} | {ph:.4f} | {zd:.2f} | {m['phi_bulk']:.4f} | "
              f"{m['Z']['1e-6']:.3f} | {ph - m['phi_bulk']:+.4f} |")

print("\nContact-number histograms (fraction of slab particles, tol 1e-3; packbed the mean of "
      "seeds 1–3) and, for DEM, the overlap of touching pairs in the slab (mean / max, in d of the smaller):\n")
print("| bed | " + " | ".join(str(k) for k in range(10)) + " | ≥ 10 | overlap mean / max |")
print("|---|" + "---|" * 12)


def hist(ms):
    """fractions with 0 ... 9 and >= 10 contacts, mean over the beds ms"""
    h = lambda m, k: m["contact_hist_tol1e-3"].get(str(k), 0) / m["n_slab"]
    return ([st.mean(h(m, k) for m in ms) for k in range(10)]
            + [st.mean(sum(h(m, k) for k in range(10, 40)) for m in ms)])


for name, bo in DEMS:
    if os.path.exists(f"{W}/runs/{name}/measure.json"):
        m = J(f"{W}/runs/{name}/measure.json")
        o = m.get("overlap_over_d", {})
        print(f"| DEM {name} | " + " | ".join(f"{v:.3f}" for v in hist([m]))
              + f" | {o.get('mean', 0):.1e} / {o.get('max', 0):.1e} |")
for p in ["0", "0.05", "0.1", "0.15", "0.2", "0.3"]:
    if len(beds("stick", p)) == 3:
        print(f"| packbed stick{p} | " + " | ".join(f"{v:.3f}" for v in hist(beds("stick", p))) + " | – |")

print("\nPer run: wall time (s) and max RSS (MiB), `/usr/bin/time -v`:\n")
print("| run | wall s | max RSS MiB | end time √(d/g) / final KE per particle (m g d) |")
print("|---|---|---|---|")
for d in sorted(glob.glob(f"{W}/runs/{DIST}_*/")):
    if not os.path.exists(f"{d}/measure.json"):   # not run yet or under way
        continue
    w, r = time_rss(d)
    ke, vmax, t = final(d)
    print(f"| DEM {os.path.basename(d.rstrip('/'))} | {w:.0f} | {r:.0f} | {t:.1f} / {ke:.1e} |")
print("\npackbed, one row per rule, the three seeds' runs (s1 / s2 / s3):\n")
print("| rule | wall s | max RSS MiB |")
print("|---|---|---|")
rules = sorted({os.path.basename(d.rstrip("/")).rsplit("_s", 1)[0]
                for d in glob.glob(f"{W}/packbed/{DIST}_*/")})
for rule in rules:
    tr = [time_rss(f"{W}/packbed/{rule}_s{k}") for k in (1, 2, 3)]
    print(f"| {rule} | " + " / ".join(f"{w:.2f}" for w, _ in tr) + " | "
          + " / ".join(f"{r:.1f}" for _, r in tr) + " |")
