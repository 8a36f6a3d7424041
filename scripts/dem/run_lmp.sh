#!/bin/bash
# Run one DEM pour: run_lmp.sh DIST MU [N] [TAG] [extra pour.py args...]
#   -> runs/DIST_muMU[TAG]/{in.pour,batch_*.data,log.lammps,screen.txt,bed.dump,time.txt}
# One core (OMP_NUM_THREADS=1, serial lmp), one run at a time, niced: the machine is shared.
set -euo pipefail
cd "$(dirname "$0")"
dist=$1; mu=$2; n=${3:-4000}; tag=${4:-}
shift $(( $# < 4 ? $# : 4 ))
dir=runs/${dist}_mu${mu}${tag}
rm -rf "$dir"
python3 pour.py --dist "$dist" --mu "$mu" --n "$n" --out "$dir" "$@"
cd "$dir"
OMP_NUM_THREADS=1 /usr/bin/time -v -o time.txt nice -n 10 lmp -in in.pour -log log.lammps > screen.txt 2>&1
grep -E "Elapsed|Maximum resident" time.txt
grep FINAL log.lammps | tail -1
