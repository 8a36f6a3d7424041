#!/usr/bin/env python3
"""The rods' table (docs/settling-validation.md, "Momentum for rods"): DEM
pours and packbed rules side by side, from rods.sh's WORK/rods/*/measure.json
and time.txt.
Usage: rods_table.py [WORK/rods]"""
import glob
import json
import os
import re
import statistics
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "/work/dem/rods"


def cost(d):
    t = open(os.path.join(d, "time.txt")).read()
    wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", t)
    h, m, s = wall.groups()
    secs = int(h or 0) * 3600 + int(m) * 60 + float(s)
    mem = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
    return secs, mem


def fmt(vals, nd):
    if len(vals) == 1:
        return f"{vals[0]:.{nd}f}"
    return f"{statistics.mean(vals):.{nd}f} ± {statistics.stdev(vals):.{nd}f}"


rows = {}
for d in sorted(glob.glob(os.path.join(root, "*"))):
    m = os.path.join(d, "measure.json")
    if not os.path.exists(m):
        continue
    name = re.sub(r"_s\d+$", "", os.path.basename(d))
    rows.setdefault(name, []).append((json.load(open(m)), cost(d)))
print("| bed | φ (bulk) | Z per rod | rods touched | S | θ from vertical | wall time | peak memory |")
print("|---|---|---|---|---|---|---|---|")
for name, rs in rows.items():
    ms = [r[0] for r in rs]
    t = [r[1][0] for r in rs]
    mem = [r[1][1] for r in rs]
    print(f"| {name} ({len(rs)}) | {fmt([m['phi_bulk'] for m in ms], 3)} | {fmt([m['Z_rod'] for m in ms], 2)} | "
          f"{fmt([m['neighbours'] for m in ms], 2)} | {fmt([m['S'] for m in ms], 2)} | "
          f"{fmt([m['theta_deg'] for m in ms], 1)}° | {min(t):.2f}–{max(t):.2f} s | {max(mem):.0f} MiB |")
