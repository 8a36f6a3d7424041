#!/usr/bin/env bash
# Speed of `packbed fragment` (its targets: BENCHMARKS.md, "Contact forces and breakage"): periodic beds of
# equal spheres under shear. Builds the beds with `packbed run`, then reports
# the first solve and the breaks as timed by `packbed fragment` itself
# (summary.json timing.*).
#   scripts/bench-fragment.sh [DIR]      (release build in target/release)
set -euo pipefail
P=${PACKBED:-$(cd "$(dirname "$0")/.." && pwd)/target/release/packbed}
DIR=${1:-$(mktemp -d)}
mkdir -p "$DIR"
cd "$DIR"
field() { python3 -c "import json,sys; d=json.load(open('$1')); print(eval('d'+sys.argv[1]))" "$2"; }
report() {
  local name=$1 out=$2
  printf '%-34s bodies %7s bonds %7s first solve %7.3f s  breaks %4s in %7.3f s  failed %s\n' "$name" \
    "$(field "$out/summary.json" "['counts']['bodies']")" \
    "$(field "$out/summary.json" "['fragmentation']['bonds']")" \
    "$(field "$out/summary.json" "['timing']['first_solve_seconds']")" \
    "$(field "$out/summary.json" "['fragmentation']['breaks']")" \
    "$(field "$out/summary.json" "['timing']['breakage_seconds']")" \
    "$(field "$out/summary.json" "['fragmentation']['breaks_to_failure']")"
}
# The 2D thesis bed (walls; equal discs of radius 10), broken to failure.
"$P" run --dim 2 --radii 10 --seed 1 --out thesis2d --no-pictures -q
"$P" fragment thesis2d/particles.csv --out f-thesis2d --no-pictures -q
report "2D thesis bed, to failure" f-thesis2d
# The 2D thesis box made periodic.
"$P" fragment thesis2d/particles.csv --box 600,600 --periodic --out f-thesis2d-p --no-pictures -q
report "2D thesis bed periodic, to failure" f-thesis2d-p
# 2D, 10^5 discs, periodic, 1000 diameters wide; 100 breaks.
"$P" run --dim 2 --radii 10 --count 100000 --periodic --box 20000,3000 --seed 1 --out b2d --no-pictures -q
"$P" fragment b2d/particles.csv --breaks 100 --out f-b2d --no-pictures -q
report "2D 10^5 periodic, 100 breaks" f-b2d
# 3D, 2·10^4 spheres, periodic, 30 × 30 diameters; 100 breaks.
"$P" run --dim 3 --radii 10 --count 20000 --periodic --box 600,600,600 --seed 1 --out b3d --no-pictures -q
"$P" fragment b3d/particles.csv --breaks 100 --out f-b3d --no-pictures -q
report "3D 2·10^4 periodic, 100 breaks" f-b3d
