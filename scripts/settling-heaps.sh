#!/bin/bash
# The heap table of docs/settling.md: the flank slope (`packing.heap`) of a
# heap poured from a point under each rule, 2D and 3D, seed 1.
# Run from the repository root after `cargo build --release`; prints
#   dim rule slope_degrees apex_height flank_bins
set -euo pipefail
PACKBED=$(realpath "${PACKBED:-target/release/packbed}")
cd "$(mktemp -d)"
for dim in 3 2; do
for rule in "" "friction_angle = 15" "friction_angle = 25" "friction_angle = 35" \
  "restitution = 0.3" "restitution = 0.3\nsliding_friction = 0.268" \
  "restitution = 0.3\nsliding_friction = 0.466" "restitution = 0.3\nsliding_friction = 0.700" \
  "friction_angle = 15\nrestitution = 0.5" "friction_angle = 25\nrestitution = 0.5" \
  "friction_angle = 35\nrestitution = 0.5" "friction_angle = 15\nrestitution = 0.9" \
  "friction_angle = 25\nrestitution = 0.9" "friction_angle = 35\nrestitution = 0.9"; do
  if [ $dim = 3 ]; then
    box="width = 200\ndepth = 200\nheight = 400"; count=20000; spread=10
  else
    box="width = 600\nheight = 1200"; count=4000; spread=20
  fi
  printf "dim = $dim\nseed = 1\n[box]\n$box\n[fill]\ncount = $count\nbase_layer = \"none\"\n[[species]]\nradius = 1\n[feed]\npattern = \"point\"\nspread = $spread\n[settling]\n$rule\n" > c.toml
  "$PACKBED" run c.toml --out o --quiet >/dev/null 2>&1 || echo "FAIL $dim $rule"
  python3 -c "
import json;h=json.load(open('o/summary.json'))['packing']['heap']
r='''${rule:-roll}'''.replace(' ','').replace(chr(10),'+')
print('$dim', r, 'no heap' if h is None else '%.1f %.1f %d' % (h['slope_degrees'], h['apex_height'], h['flank_bins']))
"
done
done
