#!/usr/bin/env bash
# The grade efficiency of two granular media against two slurries beside the
# classic retention criteria (docs/guide/filtration.md, "Against the filter
# criteria"): each medium 600 spheres (median diameter 60, gsd 1.05 or 1.4)
# in a 300 x 300 periodic box, about ten grains deep; each slurry 400
# particles, under a monolayer, so that no cake forms and the clean medium
# alone decides what passes; the slurry bounces (restitution 0.5).
#   scripts/filtration-criteria.sh [PACKBED] [SEEDS]
set -euo pipefail
bin="${1:-target/release/packbed}"
seeds="${2:-3}"
out="$(mktemp -d)"
printf '| medium gsd | slurry median d | seeds | passed | x50 | D15 | d85 | D15/d85 (Terzaghi: retains ≤ 4) | D15/5 (Kenney) | d_c35 | d85,SA | d_c35/d85,SA (Indraratna: retains ≤ 1) |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n'
for gsd in 1.05 1.4; do
    for median in 3.0 6.0; do
        for seed in $(seq 1 "$seeds"); do
            cat > "$out/c.toml" <<TOML
dim = 3
seed = $seed
[box]
width = 300
depth = 300
height = 20000
periodic = true
[fill]
base_layer = "none"
[[species]]
name = "medium"
size = { dist = "lognormal", median = 30.0, gsd = $gsd }
[[species]]
name = "slurry"
size = { dist = "lognormal", median = $median, gsd = 1.5 }
[[feeds]]
species = ["medium"]
count = 600
medium = true
[[feeds]]
species = ["slurry"]
count = 400
settling = { restitution = 0.5 }
[analysis]
measures = ["packing"]
TOML
            "$bin" run "$out/c.toml" --out "$out/s$seed" --no-pictures >/dev/null 2>&1
        done
        python3 - "$out" "$seeds" "$gsd" "$median" <<'PY'
import json, sys, statistics as st
out, seeds, gsd, median = sys.argv[1], int(sys.argv[2]), sys.argv[3], float(sys.argv[4])
caps = [json.load(open(f"{out}/s{k}/summary.json"))["capture"] for k in range(1, seeds + 1)]
m = lambda f: st.mean(f(c) for c in caps)
passed = m(lambda c: c["passed"] / c["fed"])
x50s = [c["x50"] for c in caps if c["x50"] is not None]
x50 = f"{st.mean(x50s):.2f}" if x50s else "-"
cr = lambda k: m(lambda c: c["criteria"][k])
dc35 = m(lambda c: c["criteria"]["constriction_diameter"][1])
print(f"| {gsd} | {2 * median:g} | {seeds} | {100 * passed:.1f} % | {x50} | {cr('medium_d15'):.1f} | "
      f"{cr('slurry_d85'):.2f} | {cr('terzaghi_ratio'):.1f} | {cr('kenney_constriction'):.1f} | "
      f"{dc35:.2f} | {cr('slurry_d85_by_surface'):.2f} | {cr('indraratna_ratio'):.2f} |")
PY
    done
done
rm -rf "$out"
