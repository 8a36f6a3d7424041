#!/bin/bash
# The settling rules' validation table of docs/settling-validation.md: bulk packing
# fraction and mean coordination of each rule, 3D and 2D, seeds 1-3.
# Run from the repository root after `cargo build --release`; writes into a
# scratch directory and prints one line per bed:
#   dim rule seed bulk_phi bulk_Z bulk_bodies deposit_seconds
set -euo pipefail
PACKBED=$(realpath "${PACKBED:-target/release/packbed}")
cd "$(mktemp -d)"
for dim in 3 2; do
# One rule per row; RULES (lines) runs only those.
ALL_RULES=("" "contacts = 1" "contacts = 2" "contacts = 3" "sticking = 0.1" "sticking = 0.3" "sticking = 0.6" "friction_angle = 15" "friction_angle = 25" "friction_angle = 35" "restitution = 0.3" "restitution = 0.3\\ndrop_height = 20" "restitution = 0.3\\nsliding_friction = 0.3" "restitution = 0.3\\nsliding_friction = 1")
if [ -n "${RULES:-}" ]; then mapfile -t ALL_RULES <<< "$RULES"; fi
for rule in "${ALL_RULES[@]}"; do
 for seed in 1 2 3; do
  if [ $dim = 3 ]; then box="width = 40\ndepth = 40\nheight = 4000"; else box="width = 400\nheight = 40000"; fi
  printf "dim = $dim\nseed = $seed\n[box]\n$box\nperiodic = true\n[fill]\ncount = 20000\nbase_layer = \"none\"\n[[species]]\nradius = 1\n[settling]\n$rule\n" > c.toml
  "$PACKBED" run c.toml --out o --quiet >/dev/null 2>&1 || echo "FAIL $dim $rule"
  python3 -c "
import json;v=json.load(open('o/summary.json'))
print('$dim', '${rule:-roll}'.replace(' ','').replace(chr(10), '+'), $seed, v['packing']['bulk'], v['coordination']['mean_bulk'], v['packing']['bulk_bodies'], v['timing']['deposit_seconds'] if 'timing' in v else '')
"
 done
done
done
