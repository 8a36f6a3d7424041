# What the DEM calibration scripts (gr-cohesion.sh, cohesion-sizes.sh) share,
# sourced by them: the scratch folder WORK (default /work/dem), never the
# repository; the interpreter PY and the packbed binary PB; one LAMMPS pour
# and one packbed bed, each measured with measure.py into its measure.json
# (a run whose measure.json exists is skipped). Every process is niced to 19
# and serialised by flock on WORK/lock (one core, one at a time: the machine
# is shared); IN_LOCK=1 says the caller already holds the lock.
#   needs: lmp (Debian's lammps), a python with numpy, scipy (PY), packbed (PB).
S=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
WORK=${WORK:-/work/dem}
PY=${PY:-/tmp/venv2/bin/python}
PB=${PB:-$S/../../target/release/packbed}
N=2000
mkdir -p "$WORK/runs" "$WORK/packbed"
lock() { if [ -n "${IN_LOCK:-}" ]; then "$@"; else flock "$WORK/lock" "$@"; fi; }

pour() {   # pour NAME pour.py-args...
  local name=$1; shift
  local d=$WORK/runs/$name
  [ -f "$d/measure.json" ] && return 0
  rm -rf "$d"
  python3 "$S/pour.py" --out "$d" "$@"
  (cd "$d" && lock env OMP_NUM_THREADS=1 /usr/bin/time -v -o time.txt nice -n 19 \
      lmp -in in.pour -log log.lammps > screen.txt 2>&1)
  echo "$name $(grep FINAL "$d/log.lammps" | tail -1) $(date -u +%T)"
  lock nice -n 19 "$PY" "$S/measure.py" "$d/bed.dump" --json "$d/measure.json" > /dev/null
}

species() {   # the species block of a size distribution (packbed_runs.sh's)
  case $1 in
    equal)      printf '[[species]]\nradius = 0.5\n' ;;
    bidisperse) printf '[[species]]\nradius = 0.5\nratio = 1\n\n[[species]]\nradius = 0.7\nratio = 1\n' ;;
    lognormal)  printf '[[species]]\nsize = { dist = "lognormal", median = 0.5, gsd = 1.3 }\n' ;;
  esac
}

bed() {    # bed DIST RULE "SETTLING-TOML" SEED: N spheres in the pours' box
  local d=$WORK/packbed/$1_$2_s$4
  [ -f "$d/measure.json" ] && return 0
  mkdir -p "$d"
  printf 'dim = 3\nseed = %s\n\n[box]\nwidth = 10\ndepth = 10\nheight = 200\nperiodic = true\n\n[fill]\ncount = %s\nbase_layer = "none"\n\n%s\n%s' \
    "$4" "$N" "$(species "$1")" "$3" > "$d/cfg.toml"
  lock env RAYON_NUM_THREADS=1 /usr/bin/time -v -o "$d/time.txt" nice -n 19 \
    "$PB" run "$d/cfg.toml" --out "$d" --no-pictures --measures packing,coordination -q
  lock nice -n 19 "$PY" "$S/measure.py" "$d/particles.csv" --box 10 --json "$d/measure.json" > /dev/null
}
