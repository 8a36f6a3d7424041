#!/bin/bash
# The runs of RESULTS.md's "Cohesion with a size distribution" subsection: the
# cohesive pours of gr-cohesion.sh repeated for the two size distributions, and
# packbed's sticking sweeps beside them, in a scratch folder WORK (default
# /work/dem), never in the repository:
#   DEM: bidisperse and lognormal at mu 0.3 without cohesion and with JKR
#        cohesion, Bond number BONDS (default "10 100 1", run in that order);
#        Bo is that of a d = 1 pair (pour.py --bond), so a pair of diameter d
#        has Bo / d^2: coarse particles see less cohesion; then the pours of
#        SETTLE_BONDS (default "100 10") again with a 120 sqrt(d/g) settling
#        cap, as gr-cohesion.sh did for equal Bo = 100 (they stop at the
#        40 sqrt(d/g) cap still moving);
#   packbed: the same distributions (the species of packbed_runs.sh), seeds 1-3,
#        N = 2000, `sticking = p` (p = 0 ... 0.6) and `restitution = 0.5` +
#        `sticking = p` (p = 0 ... 0.3); every bed measured with measure.py;
#   extra (stage "dc"): packbed's size-dependent law instead of one p,
#        `cohesion_diameter = d_c` (n = 2, the default: p = 1 / (1 + (d/d_c)^2),
#        the Bo ~ 1/d^2 of one adhesion force), d_c = 0.1 ... 0.7 d, same beds.
# Same settings, locking and niceness as gr-cohesion.sh: every process niced to
# 19 and serialised by flock on WORK/lock (one core, one at a time; the machine
# is shared).  A bed whose measure.json exists is skipped.  The packbed and dc
# stages take the lock once for all their beds (about a minute each), so that
# they do not queue behind every pour.
# Usage: cohesion-sizes.sh [dem|packbed|dc|table]...   (default: all four)
# "table" prints cohesion_table.py's tables for each distribution.
#   needs: lmp (Debian's lammps), a python with numpy, scipy (PY), packbed (PB).
set -euo pipefail
source "$(cd "$(dirname "$0")" && pwd)/common.sh"   # WORK, PY, PB, N, lock, pour, bed
BONDS=${BONDS:-10 100 1}
SETTLE_BONDS=${SETTLE_BONDS:-100 10}
DISTS="bidisperse lognormal"
STAGES=${*:-dem packbed dc table}

for stage in $STAGES; do
  case $stage in
    dem)
      for bo in $BONDS; do
        for dist in $DISTS; do
          pour ${dist}_mu0.3_jkr_bo$bo --dist $dist --mu 0.3 --n $N --cohesion jkr --bond $bo
        done
        # the non-cohesive reference pours (the runs of RESULTS.md's tables),
        # after Bo 10 and 100 so that those come first
        if [ "$bo" = 100 ]; then
          for dist in $DISTS; do pour ${dist}_mu0.3 --dist $dist --mu 0.3 --n $N; done
        fi
      done
      for bo in $SETTLE_BONDS; do
        for dist in $DISTS; do
          pour ${dist}_mu0.3_jkr_bo${bo}_settle120 --dist $dist --mu 0.3 --n $N --cohesion jkr --bond $bo --settle 120
        done
      done ;;
    packbed|dc)
      if [ -z "${IN_LOCK:-}" ]; then lock env IN_LOCK=1 "$0" $stage; continue; fi
      if [ $stage = dc ]; then
        for dist in $DISTS; do for seed in 1 2 3; do for dc in 0.1 0.2 0.3 0.4 0.5 0.7; do
          bed $dist dc$dc "$(printf '[settling]\ncohesion_diameter = %s\n' $dc)" $seed
        done; done; done
        continue
      fi
      for dist in $DISTS; do
        for seed in 1 2 3; do
          bed $dist default "" $seed
          bed $dist m0 $'[settling]\nrestitution = 0.5\n' $seed
          for p in 0 0.05 0.1 0.15 0.2 0.3 0.4 0.6; do
            bed $dist stick$p "$(printf '[settling]\nsticking = %s\n' $p)" $seed
          done
          for p in 0.05 0.1 0.15 0.2 0.3; do
            bed $dist m0stick$p "$(printf '[settling]\nrestitution = 0.5\nsticking = %s\n' $p)" $seed
          done
        done
      done ;;
    table)
      for dist in $DISTS; do "$PY" "$S/cohesion_table.py" "$WORK" --dist $dist; done ;;
    *) echo "unknown stage $stage (dem, packbed, dc, table)" >&2; exit 2 ;;
  esac
done
