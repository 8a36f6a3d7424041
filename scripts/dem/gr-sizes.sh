#!/bin/bash
# g(r) of the size distributions beside DEM (docs/settling-validation.md, "The
# DEM calibration", "g(r) of the mixtures"), in a scratch folder WORK (default
# /work/dem), never in the repository:
#   DEM: the bidisperse and lognormal pours of the calibration table (mu 0,
#        0.3, 0.6; pour.py's defaults, the 40 sqrt(d/g) settling cap);
#   packbed: the same distributions, seeds 1-3, N = 2000, the default rule and
#        `restitution = 0.5`; every bed measured with measure.py;
# then gr_sizes.py prints the g(r) tables and draws docs/settling-gr-sizes.png.
# Same settings, locking and niceness as gr-cohesion.sh (common.sh); a bed
# whose measure.json exists is skipped.
#   needs: lmp (Debian's lammps), a python with numpy, scipy and matplotlib
#   (PY), packbed (PB).
set -euo pipefail
source "$(cd "$(dirname "$0")" && pwd)/common.sh"   # WORK, PY, PB, N, lock, pour, bed
for dist in bidisperse lognormal; do
  for mu in 0 0.3 0.6; do pour ${dist}_mu$mu --dist $dist --mu $mu --n $N; done
  for seed in 1 2 3; do
    bed $dist default "" $seed
    bed $dist m0 $'[settling]\nrestitution = 0.5\n' $seed
  done
done
"$PY" "$S/gr_sizes.py" "$WORK" --png "$S/../../docs/settling-gr-sizes.png"
