#!/bin/bash
# The "Settling rules" table of BENCHMARKS.md: every rule's throughput on
# N equal spheres (default 10^6) in the bench's periodic cube, the rules in
# turn, the whole round twice (so a passing load shows as a disagreement of
# the two runs), each against the default rule's mean of the same rounds.
# Run from the repository root after `cargo build --release`, on an idle
# machine; prints one Markdown row per rule.
set -euo pipefail
PACKBED=$(realpath "${PACKBED:-target/release/packbed}")
N=${N:-1000000}
RULES=("" "--contacts 1" "--contacts 2" "--sticking 0.3" "--friction-angle 25"
  "--restitution 0.3" "--restitution 0.5 --sliding-friction 0.6"
  "--friction-angle 25 --restitution 0.5" "--friction-angle 25 --restitution 0.9")
out=$(mktemp)
for round in 1 2; do
  for i in "${!RULES[@]}"; do
    # shellcheck disable=SC2086
    "$PACKBED" bench --n "$N" --periodic ${RULES[$i]} --json | sed "s/^/$i /" >> "$out"
  done
done
python3 - "$out" "${RULES[@]}" <<'PY'
import json, sys
rows = {}
for line in open(sys.argv[1]):
    i, js = line.split(" ", 1)
    rows.setdefault(int(i), []).append(json.loads(js))
rules = sys.argv[2:]
base = sum(r["seconds"] for r in rows[0]) / len(rows[0])
print("| rule | time (two runs) | moves per particle | µs per move (wall) | particles per second | against the default | peak RSS |")
print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
for i, runs in sorted(rows.items()):
    t = sum(r["seconds"] for r in runs) / len(runs)
    n, moves = runs[0]["bodies"], runs[0]["moves"]
    print("| %s | %s s | %.1f | %.3f | %.2g | %.2f× | %.1f MiB |" % (
        "`" + rules[i] + "`" if rules[i] else "default",
        ", ".join("%.3f" % r["seconds"] for r in runs),
        moves / n, t * 1e6 / moves, n / t, base / t,
        max(r["peak_rss_bytes"] for r in runs) / 2**20))
PY
rm -f "$out"
