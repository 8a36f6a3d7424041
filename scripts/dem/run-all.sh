#!/bin/bash
# Re-run the DEM-vs-packbed peer measurement from scratch: the calibration
# table (3 size distributions x mu 0, 0.3, 0.6 and packbed's rules; about 75
# min of one core for the DEM part, 45 without the extras: EXTRAS=0). With
# REST=1 it then runs the rest of the calibration in the scratch folder WORK
# (common.sh, default /work/dem), one script after another: g(r) and cohesion
# of equal spheres (gr-cohesion.sh), cohesion of the mixtures
# (cohesion-sizes.sh), g(r) of the mixtures (gr-sizes.sh) and the rods
# (rods.sh); many hours of one core in all (their pours' wall times are in
# RESULTS.md).
#   needs: Debian (apt-get), python3 with venv; PB=path/to/packbed (default: the release build, ../../target/release/packbed)
# Every LAMMPS run is serial (one core, OMP_NUM_THREADS=1), niced, one at a time.
set -euo pipefail
cd "$(dirname "$0")"
command -v lmp >/dev/null || { apt-get update && apt-get install -y lammps; }
lmp -h 2>&1 | grep -c "granular" >/dev/null || { echo "LAMMPS without the GRANULAR package" >&2; exit 1; }
[ -x venv/bin/python ] || { python3 -m venv venv && venv/bin/pip install -q numpy scipy matplotlib; }
N=${N:-2000}   # the DEM beds of RESULTS.md are N = 2000 (see there why)
measure() { venv/bin/python measure.py "runs/$1/bed.dump" --json "runs/$1/measure.json"; }
# DEM pours: 3 size distributions x mu = 0, 0.3, 0.6
for dist in equal bidisperse lognormal; do
  for mu in 0 0.3 0.6; do
    ./run_lmp.sh "$dist" "$mu" "$N"
    measure "${dist}_mu${mu}"
  done
done
# extras: the frictionless beds settled longer, and equal mu = 0.3 at N = 4000
if [ "${EXTRAS:-1}" = 1 ]; then
  ./run_lmp.sh equal 0 2000 _settle200 --settle 200;      measure equal_mu0_settle200
  ./run_lmp.sh equal 0.3 4000 _n4000;                     measure equal_mu0.3_n4000
  ./run_lmp.sh bidisperse 0 2000 _settle200 --settle 200; measure bidisperse_mu0_settle200
  ./run_lmp.sh lognormal 0 2000 _settle120 --settle 120;  measure lognormal_mu0_settle120
fi
# packbed beds (3 rules x 3 seeds per distribution), measured the same way
N=2000 ./packbed_runs.sh
mv packbed packbed_n2000.tmp
N=4000 ./packbed_runs.sh
rm -rf packbed_n4000 && mv packbed packbed_n4000 && mv packbed_n2000.tmp packbed
# the momentum rule (restitution 0.5; sliding friction 0, 0.3, 0.6), N = 2000
RULES="m0 m0.3 m0.6" OUT=packbed_momentum N=2000 ./packbed_runs.sh
venv/bin/python fill_results.py   # the tables in RESULTS.md
# the rest of the calibration, with this venv and this packbed
if [ "${REST:-0}" = 1 ]; then
  venv/bin/pip install -q matplotlib   # a venv made before it needed the plots
  PB=$(realpath "${PB:-../../target/release/packbed}")
  export PY=$PWD/venv/bin/python PB
  ./gr-cohesion.sh
  ./cohesion-sizes.sh
  ./gr-sizes.sh
  ./rods.sh
fi
