#!/usr/bin/env python3
"""Contact-number histograms (fraction of slab particles, tol 1e-3) of the DEM
beds and of packbed's seed-1 beds, as a Markdown table.  Usage: hist.py [packbed_dir]"""
import json, os, sys
HERE = os.path.dirname(os.path.abspath(__file__))
pdir = sys.argv[1] if len(sys.argv) > 1 else "packbed"
rows = [(f"DEM {d} µ={m}", f"runs/{d}_mu{m}") for d in ("equal", "bidisperse", "lognormal") for m in ("0", "0.3", "0.6")]
rows += [(f"packbed {d} {r} s1", f"{pdir}/{d}_{r}_s1") for d in ("equal", "bidisperse", "lognormal") for r in ("default", "fa10", "fa20")]
print("| bed | " + " | ".join(str(k) for k in range(11)) + " |")
print("|---|" + "---|" * 11)
for name, d in rows:
    p = os.path.join(HERE, d, "measure.json")
    if not os.path.exists(p):
        continue
    h = json.load(open(p))["contact_hist_tol1e-3"]
    n = sum(h.values())
    print(f"| {name} | " + " | ".join(f"{h.get(str(k), 0) / n:.3f}" for k in range(11)) + " |")
