#!/bin/bash
# DEM pours of rigid 3-bead rods (pour_rods.py) beside packbed's rules for the
# same rods, measured alike by measure_rods.py (docs/settling-validation.md,
# "Momentum for rods": the DEM peer).  Scratch folder WORK (default /work/dem),
# never the repository; one process at a time, each on one core (common.sh).
#   needs: lmp (Debian's lammps, with RIGID and GRANULAR), PY (numpy, scipy), PB.
set -euo pipefail
S=$(cd "$(dirname "$0")" && pwd)
source "$S/common.sh"
RODS=${RODS:-667}
mkdir -p "$WORK/rods"
for seed in ${DEM_SEEDS:-1 2 3}; do
  for mu in ${MUS:-0 0.3 0.6}; do
    d=$WORK/rods/dem_mu${mu}_s$seed
    [ -f "$d/measure.json" ] && continue
    rm -rf "$d"
    python3 "$S/pour_rods.py" --mu "$mu" --rods "$RODS" --seed $((4767547 + seed)) --out "$d"
    (cd "$d" && lock env OMP_NUM_THREADS=1 /usr/bin/time -v -o time.txt nice -n 19 \
        lmp -in in.pour -log log.lammps > screen.txt 2>&1)
    echo "dem mu $mu seed $seed $(grep FINAL "$d/log.lammps" | tail -1) $(date -u +%T)"
    (cd "$S" && lock nice -n 19 "$PY" measure_rods.py "$d/bed.dump" --json "$d/measure.json")
  done
done
# packbed: the same rods (radius 0.5, touching beads, random entry) in the same box
rule() {
  case $1 in
    default) echo "" ;;
    m0)      printf '[settling]\nrestitution = 0.5\n' ;;
    m0.3)    printf '[settling]\nrestitution = 0.5\nsliding_friction = 0.3\n' ;;
    m0.6)    printf '[settling]\nrestitution = 0.5\nsliding_friction = 0.6\n' ;;
    a10)     printf '[settling]\nfriction_angle = 10\n' ;;
    a20)     printf '[settling]\nfriction_angle = 20\n' ;;
    *)       echo "rods.sh: unknown rule $1 (default m0 m0.3 m0.6 a10 a20)" >&2; return 1 ;;
  esac
}
for r in ${RULES:-default m0 m0.3 m0.6 a10 a20}; do
  for seed in 1 2 3; do
    d=$WORK/rods/packbed_${r}_s$seed
    [ -f "$d/measure.json" ] && continue
    spec=$(rule "$r")
    mkdir -p "$d"
    printf 'dim = 3\nseed = %s\n\n[box]\nwidth = 10\ndepth = 10\nheight = 80\nperiodic = true\n\n[fill]\ncount = %s\nbase_layer = "none"\n\n[[species]]\nradius = 0.5\nshape = "chain"\nbeads = 3\nspacing = 2\norientation = "random"\n\n%s\n' \
      "$seed" "$((3 * RODS))" "$spec" > "$d/cfg.toml"
    lock env RAYON_NUM_THREADS=1 /usr/bin/time -v -o "$d/time.txt" nice -n 19 \
      "$PB" run "$d/cfg.toml" --out "$d" --no-pictures -q
    (cd "$S" && lock nice -n 19 "$PY" measure_rods.py "$d/particles.csv" --box 10 --json "$d/measure.json" > /dev/null)
  done
done
