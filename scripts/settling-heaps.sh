#!/bin/bash
# The heap tables of docs/settling-validation.md: the flank slope (`packing.heap`) of a
# heap poured from a point under each rule, 2D and 3D.
# Run from the repository root after `cargo build --release`.
#   scripts/settling-heaps.sh          every rule, seed 1; prints
#                                      dim rule slope_degrees apex_height flank_bins
#   scripts/settling-heaps.sh elastic  friction angle 15/25/35 with restitution
#                                      0.99 and drops of 3, 5, 7, 10 diameters,
#                                      seeds 1-3; prints
#                                      dim alpha drop_diameters mean sd slopes...
set -euo pipefail
PACKBED=$(realpath "${PACKBED:-target/release/packbed}")
cd "$(mktemp -d)"

# heap DIM SEED RULE: prints "slope apex bins", or "no heap".
heap() {
  local dim=$1 seed=$2 rule=$3 box count spread
  if [ "$dim" = 3 ]; then
    box="width = 200\ndepth = 200\nheight = 400"; count=20000; spread=10
  else
    box="width = 600\nheight = 1200"; count=4000; spread=20
  fi
  printf "dim = $dim\nseed = $seed\n[box]\n$box\n[fill]\ncount = $count\nbase_layer = \"none\"\n[[species]]\nradius = 1\n[feed]\npattern = \"point\"\nspread = $spread\n[settling]\n$rule\n" > c.toml
  "$PACKBED" run c.toml --out o --quiet --no-pictures >/dev/null 2>&1 || echo "FAIL $dim $rule" >&2
  python3 -c "
import json;h=json.load(open('o/summary.json'))['packing']['heap']
print('no heap' if h is None else '%.1f %.1f %d' % (h['slope_degrees'], h['apex_height'], h['flank_bins']))
"
}

if [ "${1:-}" = elastic ]; then
  for dim in 3 2; do
    for a in 15 25 35; do
      for drop in 3 5 7 10; do
        slopes=""
        for seed in 1 2 3; do
          # radius 1: a drop of k diameters is 2k lengths
          slopes="$slopes $(heap $dim $seed "friction_angle = $a\nrestitution = 0.99\ndrop_height = $((2 * drop))" | cut -d' ' -f1)"
        done
        python3 -c "
import statistics as st; v=[float(x) for x in '$slopes'.split()]
print('$dim $a $drop %.1f %.1f' % (st.mean(v), st.stdev(v)), *v)
"
      done
    done
  done
  exit 0
fi

for dim in 3 2; do
for rule in "" "friction_angle = 15" "friction_angle = 25" "friction_angle = 35" \
  "restitution = 0.3" "restitution = 0.3\nsliding_friction = 0.268" \
  "restitution = 0.3\nsliding_friction = 0.466" "restitution = 0.3\nsliding_friction = 0.700" \
  "friction_angle = 15\nrestitution = 0.5" "friction_angle = 25\nrestitution = 0.5" \
  "friction_angle = 35\nrestitution = 0.5" "friction_angle = 15\nrestitution = 0.9" \
  "friction_angle = 25\nrestitution = 0.9" "friction_angle = 35\nrestitution = 0.9"; do
  label=$(printf '%s' "${rule:-roll}" | sed 's/ = /=/g; s/\\n/+/g')
  echo "$dim $label $(heap $dim 1 "$rule")"
done
done
