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
S=$(cd "$(dirname "$0")" && pwd)
WORK=${WORK:-/work/dem}
PY=${PY:-/tmp/venv2/bin/python}
PB=${PB:-$S/../../target/release/packbed}
N=2000
mkdir -p "$WORK/runs" "$WORK/packbed"
lock() { flock "$WORK/lock" "$@"; }

pour() {   # pour NAME pour.py-args...
  local name=$1; shift
  local d=$WORK/runs/$name
  [ -f "$d/measure.json" ] && return 0
  rm -rf "$d"
  python3 "$S/pour.py" --out "$d" "$@"
  (cd "$d" && lock env OMP_NUM_THREADS=1 /usr/bin/time -v -o time.txt nice -n 19 \
      lmp -in in.pour -log log.lammps > screen.txt 2>&1)
  grep FINAL "$d/log.lammps" | tail -1
  lock nice -n 19 "$PY" "$S/measure.py" "$d/bed.dump" --json "$d/measure.json" > /dev/null
}
for mu in 0 0.3 0.6; do pour equal_mu$mu --dist equal --mu $mu --n $N; done
for bo in 1 10 100; do pour equal_mu0.3_jkr_bo$bo --dist equal --mu 0.3 --n $N --cohesion jkr --bond $bo; done
# Bo = 100 had not settled at the 40 sqrt(d/g) cap: the same pour settled for up to 120
pour equal_mu0.3_jkr_bo100_settle120 --dist equal --mu 0.3 --n $N --cohesion jkr --bond 100 --settle 120

bed() {    # bed RULE "SETTLING-TOML" SEED
  local d=$WORK/packbed/equal_$1_s$3
  [ -f "$d/measure.json" ] && return 0
  mkdir -p "$d"
  printf 'dim = 3\nseed = %s\n\n[box]\nwidth = 10\ndepth = 10\nheight = 200\nperiodic = true\n\n[fill]\ncount = %s\nbase_layer = "none"\n\n[[species]]\nradius = 0.5\n\n%s' \
    "$3" "$N" "$2" > "$d/cfg.toml"
  lock env RAYON_NUM_THREADS=1 /usr/bin/time -v -o "$d/time.txt" nice -n 19 \
    "$PB" run "$d/cfg.toml" --out "$d" --no-pictures --measures packing,coordination -q
  lock nice -n 19 "$PY" "$S/measure.py" "$d/particles.csv" --box 10 --json "$d/measure.json" > /dev/null
}
for seed in 1 2 3; do
  bed default "" $seed
  bed m0 $'[settling]\nrestitution = 0.5\n' $seed
  for p in 0 0.05 0.1 0.15 0.2 0.3 0.4 0.6; do
    bed stick$p "$(printf '[settling]\nsticking = %s\n' $p)" $seed
  done
  # extra: the momentum rule with sticking (its p = 0 is the m0 bed above)
  for p in 0.05 0.1 0.15 0.2 0.3; do
    bed m0stick$p "$(printf '[settling]\nrestitution = 0.5\nsticking = %s\n' $p)" $seed
  done
done
"$PY" "$S/gr_plot.py" "$WORK" --png "$S/../../docs/settling-gr.png"
"$PY" "$S/cohesion_table.py" "$WORK"
