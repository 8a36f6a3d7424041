#!/usr/bin/env bash
# Deposition (and, with --analysis, analysis) speed of broad size distributions
# against equal spheres, in one run on one machine: the polydisperse rows of
# BENCHMARKS.md. Usage: scripts/bench-polydisperse.sh [N] [extra bench options]
# (default N = 100000; e.g. `scripts/bench-polydisperse.sh 100000 --analysis`).
set -euo pipefail
cd "$(dirname "$0")/.."
n="${1:-100000}"
shift || true
cargo build --release -q -p packbed-cli
bin=./target/release/packbed
printf '| radii | s | particles/s | vs equal | moves/body | µs/move | move cost vs equal | re-drops | peak RSS bytes/particle | analysis s | analysis per particle vs equal |\n'
printf '| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n'
eq_rate=""; eq_move=""; eq_an=""
for sizes in "--gsd 1.0" "--gsd 1.3" "--gsd 1.6" "--gsd 2.0" "--gsd 2.5" "--radii 10,50" "--radii 10,50 --base-layer"; do
    # shellcheck disable=SC2086
    json=$($bin bench --periodic --n "$n" $sizes --json "$@")
    IFS=$'\t' read -r rate move line an < <(python3 - "$json" "$sizes" "$eq_rate" "$eq_move" "$eq_an" <<'PY'
import json, sys
r = json.loads(sys.argv[1]); sizes = sys.argv[2]
eq_rate, eq_move, eq_an = (float(x) if x else None for x in sys.argv[3:6])
n = r["n"]; dropped = max(r["bodies"] - r["base_layer"], 1)
move = r["seconds"] / max(r["moves"], 1)
stages = dict(r.get("analysis", []))
an = sum(stages.values()) if stages else None
rate = r["particles_per_second"]
cells = [sizes, f'{r["seconds"]:.3f}', f"{rate:,.0f}",
         f"{rate / eq_rate:.2f}" if eq_rate else "1",
         f'{r["moves"] / dropped:.2f}', f"{1e6 * move:.3f}",
         f"{move / eq_move:.2f}" if eq_move else "1",
         str(r["redrops"]), f'{r["peak_rss_bytes"] / n:.0f}',
         f"{an:.3f}" if an is not None else "-",
         (f"{an / eq_an:.2f}" if eq_an else "1") if an is not None else "-"]
print(rate, move, "| " + " | ".join(cells) + " |", an if an is not None else "", sep="\t")
PY
)
    if [ -z "$eq_rate" ]; then eq_rate=$rate; eq_move=$move; eq_an=$an; fi
    echo "$line"
done
