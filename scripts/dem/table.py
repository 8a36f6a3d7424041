#!/usr/bin/env python3
"""Collect the measure.json files into Markdown tables (DEM rows, packbed rows
as the mean +- sd over seeds).  Usage: table.py [packbed_dir ...]"""
import glob
import json
import os
import re
import statistics as st
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def load(p):
    with open(p) as f:
        return json.load(f)


def time_rss(d):
    """Wall time (s) and max RSS (MiB) from a /usr/bin/time -v file."""
    try:
        t = open(os.path.join(d, "time.txt")).read()
    except OSError:
        return None, None
    w = re.search(r"Elapsed \(wall clock\) time.*: (\S+)", t).group(1).split(":")
    secs = sum(float(x) * 60 ** k for k, x in enumerate(reversed(w)))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
    return secs, rss


def final_ke(d):
    try:
        for line in open(os.path.join(d, "log.lammps")):
            if line.startswith("FINAL"):
                return line.split()
    except OSError:
        pass
    return None


def fmt(vals, nd=3):
    if len(vals) == 1:
        return f"{vals[0]:.{nd}f}"
    return f"{st.mean(vals):.{nd}f} ± {st.stdev(vals):.{nd}f}"


def main():
    print("### DEM (LAMMPS)\n")
    print("| bed | N | φ bulk | Z 1e-6 | Z 1e-3 | Z 1e-2 | Z overlap | rattlers | mean / max overlap (d) | final KE/(m g d) | wall s | RSS MiB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for dist in ("equal", "bidisperse", "lognormal"):
        for mu in ("0", "0.3", "0.6"):
          # the main run, then any extra runs of the same bed (tagged dirs)
          extras = sorted(glob.glob(os.path.join(HERE, "runs", f"{dist}_mu{mu}_*")))
          for d in [os.path.join(HERE, "runs", f"{dist}_mu{mu}")] + extras:
            tag = os.path.basename(d)[len(f"{dist}_mu{mu}"):]
            p = os.path.join(d, "measure.json")
            if not os.path.exists(p):
                print(f"| {dist} µ={mu}{tag} | not run |")
                continue
            m = load(p)
            z = m["Z"]
            w, rss = time_rss(d)
            fk = final_ke(d)
            ov = m.get("overlap_over_d", {})
            print(f"| {dist} µ={mu}{tag} | {m['n']} | {m['phi_bulk']:.4f} | {z['1e-6']:.3f} | {z['1e-3']:.3f} | {z['1e-2']:.3f} | "
                  f"{z['overlap']:.3f} | {m['rattlers_tol1e-3']:.3f} | {ov.get('mean', 0):.1e} / {m.get('overlap_over_d_max_all', 0):.1e} | "
                  f"{float(fk[2]) if fk else float('nan'):.1e} | {w:.0f} | {rss:.0f} |")
    for pdir in sys.argv[1:] or ["packbed"]:
        print(f"\n### packbed ({pdir}, mean ± sd over 3 seeds)\n")
        print("| bed | N | φ bulk | Z 1e-6 | Z 1e-3 | Z 1e-2 | rattlers | wall s (max of 3) |")
        print("|---|---|---|---|---|---|---|---|")
        for dist in ("equal", "bidisperse", "lognormal"):
            for rule in ("default", "fa10", "fa20"):
                ms = [load(p) for p in sorted(glob.glob(os.path.join(HERE, pdir, f"{dist}_{rule}_s*", "measure.json")))]
                if not ms:
                    continue
                ws = [time_rss(os.path.dirname(p))[0] for p in
                      sorted(glob.glob(os.path.join(HERE, pdir, f"{dist}_{rule}_s*", "measure.json")))]
                print(f"| {dist} {rule} | {ms[0]['n']} | {fmt([m['phi_bulk'] for m in ms], 4)} | "
                      f"{fmt([m['Z']['1e-6'] for m in ms])} | {fmt([m['Z']['1e-3'] for m in ms])} | "
                      f"{fmt([m['Z']['1e-2'] for m in ms])} | {fmt([m['rattlers_tol1e-3'] for m in ms])} | "
                      f"{max(ws):.2f} |")


if __name__ == "__main__":
    main()
