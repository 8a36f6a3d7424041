#!/usr/bin/env bash
# The drying's trends on one bed: the same seed (the same bed) dried from
# liquids of several concentrations (a saturated mother liquor washed down
# to a tenth, a hundredth) and from cakes deliquored at several pressures.
# Prints one line per case. Usage: scripts/drying-trends.sh [PACKBED] [WORKDIR]
set -euo pipefail
PACKBED=${1:-target/release/packbed}
WORK=${2:-$(mktemp -d)}
mkdir -p "$WORK"
base() {
    printf 'dim = 3\nseed = 7\n[box]\nwidth = 16\ndepth = 16\nheight = 80\nperiodic = true\n[fill]\ncount = 4000\n[[species]]\nradius = 1\n[analysis]\nmeasures = ["packing", "agglomeration"]\nlength_unit = "um"\n'
}
run_case() { # name, extra toml
    base > "$WORK/$1.toml"
    printf '%b' "$2" >> "$WORK/$1.toml"
    "$PACKBED" run "$WORK/$1.toml" --out "$WORK/$1" --no-pictures -q
    python3 - "$WORK/$1/summary.json" "$1" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
a, d = s["agglomeration"], s["drainage"]
print(f'{sys.argv[2]:<14} S_res {d["residual_saturation"]:.3f}  c {a["concentration"]:>5g}  '
      f'bonds/particle {a["bonds_per_particle"]:.2f}  mean bond {a.get("mean_bond_strength") or 0:.3e} N  '
      f'agglomerates {a["agglomerates"]:>3}  in them {100*a["fraction_in_agglomerates"]:5.1f} %  '
      f'largest {a["largest_particles"]:>5}  d50 {a["d50_product"]:.2f} (particles {a["d50_particles"]:.2f})')
PY
}
for c in 50 5 0.5 0.05; do
    run_case "c$c" "[analysis.drying]\nconcentration = $c\nsolubility = 50\n"
done
for p in 15 20 40 80; do
    run_case "p$p" "[analysis.drainage]\nreduced_pressure = $p\n[analysis.drying]\nconcentration = 5\nsolubility = 50\n"
done
