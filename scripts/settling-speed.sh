#!/bin/bash
# The settling rules' speed table of docs/settling.md: 10^6 equal spheres,
# 3D, periodic 100 x 100 diameters, each rule against the default.
# Run from the repository root after `cargo build --release`.
set -euo pipefail
PACKBED=$(realpath "${PACKBED:-target/release/packbed}")
cd "$(mktemp -d)"
for rule in "" "contacts = 1" "contacts = 2" "sticking = 0.3" "friction_angle = 25"; do
  printf "dim = 3\nseed = 1\n[box]\nwidth = 200\ndepth = 200\nheight = 100000\nperiodic = true\n[fill]\ncount = 1000000\nbase_layer = \"none\"\n[[species]]\nradius = 1\n[settling]\n$rule\n" > s.toml
  /usr/bin/time -f "%e s %M KB" "$PACKBED" run s.toml --out so --quiet --measures packing 2>&1 | tail -1
  python3 -c "
import json;v=json.load(open('so/summary.json'));t=v['timing']['deposit_seconds'];print('${rule:-roll}', 'deposit', t, 's', 1e6/t, 'spheres/s', 'bulk', v['packing']['bulk'])"
done
