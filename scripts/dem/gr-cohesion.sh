#!/bin/bash
# The runs of RESULTS.md's "g(r) and cohesion" section, in a scratch folder
# WORK (default /work/dem), never in the repository:
#   DEM: the three equal pours (mu 0, 0.3, 0.6) and three cohesive ones
#        (mu 0.3, JKR, Bond number 1, 10, 100; pour.py --cohesion jkr --bond BO);
#   packbed: equal spheres, seeds 1-3, N = 2000, rules default, restitution 0.5
#        and sticking p = 0 ... 0.6;  every bed measured with measure.py.
# Every process niced to 19 and serialised by flock on WORK/lock (one core, one
# at a time; the machine is shared).  A bed whose measure.json exists is skipped.
# Then gr_plot.py draws docs/settling-gr.png and prints the g(r) tables, and
# cohesion_table.py the cohesion tables and the wall time / max RSS of every run.
#   needs: lmp (Debian's lammps), a python with numpy, scipy, matplotlib (PY).
set -euo pipefail
source "$(cd "$(dirname "$0")" && pwd)/common.sh"   # WORK, PY, PB, N, lock, pour, bed
for mu in 0 0.3 0.6; do pour equal_mu$mu --dist equal --mu $mu --n $N; done
for bo in 1 10 100; do pour equal_mu0.3_jkr_bo$bo --dist equal --mu 0.3 --n $N --cohesion jkr --bond $bo; done
# Bo = 100 had not settled at the 40 sqrt(d/g) cap: the same pour settled for up to 120
pour equal_mu0.3_jkr_bo100_settle120 --dist equal --mu 0.3 --n $N --cohesion jkr --bond 100 --settle 120

for seed in 1 2 3; do
  bed equal default "" $seed
  bed equal m0 $'[settling]\nrestitution = 0.5\n' $seed
  for p in 0 0.05 0.1 0.15 0.2 0.3 0.4 0.6; do
    bed equal stick$p "$(printf '[settling]\nsticking = %s\n' $p)" $seed
  done
  # extra: the momentum rule with sticking (its p = 0 is the m0 bed above)
  for p in 0.05 0.1 0.15 0.2 0.3; do
    bed equal m0stick$p "$(printf '[settling]\nrestitution = 0.5\nsticking = %s\n' $p)" $seed
  done
done
"$PY" "$S/gr_plot.py" "$WORK" --png "$S/../../docs/settling-gr.png"
"$PY" "$S/cohesion_table.py" "$WORK"
