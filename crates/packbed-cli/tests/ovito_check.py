"""Loads packbed's LAMMPS dump and extended XYZ exports of a 3D bed with the real
OVITO Python module and checks them against packbed's own files in the run
directory: particle count, radii, box and periodic flags, and OVITO's
coordination analysis (cutoff just above one diameter, equal spheres) against
packbed's mean coordination. Exit code 0 when everything matches, 1 when a
check fails, 3 when the ovito module is missing.

Usage: python3 ovito_check.py RUN_DIR
"""
import csv
import json
import os
import sys

try:
    from ovito.io import import_file
    from ovito.modifiers import CoordinationAnalysisModifier
except ImportError as e:  # the caller decides whether that is allowed
    print(f"ovito_check: the ovito module is not installed ({e})", file=sys.stderr)
    sys.exit(3)

import numpy as np


def main(run_dir):
    summary = json.load(open(os.path.join(run_dir, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(run_dir, "particles.csv"))))
    n = summary["counts"]["particles"]
    assert len(rows) == n, (len(rows), n)
    radii = np.array([float(r["r"]) for r in rows])
    assert np.all(radii == radii[0]), "this check needs equal spheres"
    d = 2.0 * radii[0]
    box = [summary["box"]["width"], summary["box"]["depth"], summary["box"]["height"]]
    periodic = summary["box"]["periodic"]
    z_packbed = summary["coordination"]["mean"]
    failures = []
    for name in ("bed.dump", "bed.xyz"):
        pipeline = import_file(os.path.join(run_dir, name))
        # Contacts have gaps <= 1e-6 r; the next neighbours are far further.
        pipeline.modifiers.append(CoordinationAnalysisModifier(cutoff=d * (1.0 + 1e-6), number_of_bins=50))
        data = pipeline.compute()
        got_n = data.particles.count
        r = np.asarray(data.particles["Radius"])
        cell = np.asarray(data.cell.matrix)
        extents = [cell[0, 0], cell[1, 1], cell[2, 2]]
        pbc = list(data.cell.pbc)
        z = np.asarray(data.particles["Coordination"]).mean()
        print(f"{name}: {got_n} particles, radius {r.min()}..{r.max()}, box {extents}, "
              f"pbc {pbc}, mean coordination {z:.6f} (packbed {z_packbed:.6f})")
        if got_n != n:
            failures.append(f"{name}: {got_n} particles, packbed wrote {n}")
        if not np.array_equal(np.sort(r), np.sort(radii)):
            failures.append(f"{name}: radii differ")
        if not np.allclose(extents, box, rtol=0, atol=1e-9 * max(box)):
            failures.append(f"{name}: box {extents}, packbed {box}")
        if pbc != [periodic, periodic, False]:
            failures.append(f"{name}: periodic flags {pbc}, packbed periodic={periodic}")
        if abs(z - z_packbed) > 1e-12:
            failures.append(f"{name}: mean coordination {z}, packbed {z_packbed}")
    for f in failures:
        print("FAILED:", f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
