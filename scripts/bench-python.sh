#!/usr/bin/env bash
# Python vs the command: 10^6 spheres (radius 10, periodic 1500 x 1500 floor,
# packing and coordination), deposited and written, timed as whole processes
# (interpreter start and `import packbed` included), alternating, ROUNDS times.
# Usage: scripts/bench-python.sh PYTHON [PACKBED_BIN] [N]
# PYTHON must have the package installed (pip install ./python).
set -euo pipefail
PY="${1:?python with packbed installed}"
BIN="${2:-$(dirname "$0")/../target/release/packbed}"
N="${3:-1000000}"
ROUNDS="${ROUNDS:-3}"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
ARGS=(--radii 10 --box 1500,1500,8000 --periodic --count "$N" --seed 1 --measures packing,coordination)
now() { date +%s.%N; }
for round in $(seq "$ROUNDS"); do
    rm -rf "$WORK/cli" "$WORK/py"
    t0=$(now)
    "$BIN" run "${ARGS[@]}" --no-pictures --quiet --out "$WORK/cli"
    t1=$(now)
    "$PY" - "$WORK/py" "$N" <<'PYEOF'
import sys
import packbed
out, n = sys.argv[1], int(sys.argv[2])
bed = packbed.deposit(radii=10, box=[1500, 1500, 8000], periodic=True, count=n, seed=1,
                      measures=["packing", "coordination"], progress=False)
bed.write(out, pictures=False)
assert bed.positions.shape == (n, 3)
PYEOF
    t2=$(now)
    cmp "$WORK/cli/particles.csv" "$WORK/py/particles.csv"
    python3 -c "import sys; c, p = float(sys.argv[1]), float(sys.argv[2]); print(f'round $round: command {c:.2f} s, python {p:.2f} s, ratio {p / c:.3f}')" \
        "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)"
done
