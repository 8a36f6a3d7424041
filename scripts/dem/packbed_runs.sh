#!/bin/bash
# packbed beds beside the DEM pours: 3 size distributions x 3 rules x 3 seeds,
# periodic 10 x 10 d box, N = 4000 (or $N), bare floor; measured with measure.py.
# RULES picks the rules (default: default fa10 fa20; the momentum rule's rows
# are m0 m0.3 m0.6: restitution 0.5, sliding friction 0, 0.3, 0.6; cMU is the
# default rule then [compaction] with friction MU, e.g. c0.04); OUT the folder;
# DISTS and SEEDS pick the size distributions and seeds (default: all, 1 2 3).
# One thread (RAYON_NUM_THREADS=1), niced: the machine is shared.
set -euo pipefail
cd "$(dirname "$0")"
PB=${PB:-../../target/release/packbed}
PY=${PY:-./venv/bin/python}
N=${N:-4000}
RULES=${RULES:-default fa10 fa20}
OUT=${OUT:-packbed}
mkdir -p "$OUT"
DISTS=${DISTS:-equal bidisperse lognormal}
SEEDS=${SEEDS:-1 2 3}
for dist in $DISTS; do
  case $dist in
    equal)      species=$'[[species]]\nradius = 0.5\n' ;;
    bidisperse) species=$'[[species]]\nradius = 0.5\nratio = 1\n\n[[species]]\nradius = 0.7\nratio = 1\n' ;;
    lognormal)  species=$'[[species]]\nsize = { dist = "lognormal", median = 0.5, gsd = 1.3 }\n' ;;
  esac
  for rule in $RULES; do
    case $rule in
      default) settling="" ;;
      fa10)    settling=$'[settling]\nfriction_angle = 10\n' ;;
      fa20)    settling=$'[settling]\nfriction_angle = 20\n' ;;
      m0)      settling=$'[settling]\nrestitution = 0.5\n' ;;
      m0.3)    settling=$'[settling]\nrestitution = 0.5\nsliding_friction = 0.3\n' ;;
      m0.6)    settling=$'[settling]\nrestitution = 0.5\nsliding_friction = 0.6\n' ;;
      c*)      settling=$'[compaction]\nfriction = '"${rule#c}"$'\n' ;;
      *)       echo "unknown rule $rule" >&2; exit 2 ;;
    esac
    for seed in $SEEDS; do
      d=$OUT/${dist}_${rule}_s${seed}
      mkdir -p "$d"
      cat > "$d/cfg.toml" <<TOML
dim = 3
seed = $seed

[box]
width = 10
depth = 10
height = 200
periodic = true

[fill]
count = $N
base_layer = "none"

$species
$settling
TOML
      RAYON_NUM_THREADS=1 /usr/bin/time -v -o "$d/time.txt" nice -n 10 \
        "$PB" run "$d/cfg.toml" --out "$d" --no-pictures --measures packing,coordination -q
      "$PY" measure.py "$d/particles.csv" --box 10 --json "$d/measure.json" > /dev/null
      echo "$d $(grep -E 'Elapsed' "$d/time.txt" | awk '{print $NF}')"
    done
  done
done
