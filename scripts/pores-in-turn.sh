#!/usr/bin/env bash
# Times the pore stages of two packbed binaries in turn on one bed:
#   scripts/pores-in-turn.sh BED ROUNDS OLD NEW
# Prints per run: binary, pores/triangulation, pores/network, pores/flow (s),
# then wall time and peak resident memory from /usr/bin/time.
set -euo pipefail
bed=$1 rounds=$2 old=$3 new=$4
out=$(mktemp)
for _ in $(seq "$rounds"); do
  for b in "$old" "$new"; do
    /usr/bin/time -f "%e s %M KB" "$b" bench --bed "$bed" --pores >"$out" 2>&1
    stages=$(grep -E 'pores/(triangulation|network|flow)' "$out" | awk '{print $2}' | tr '\n' ' ')
    echo "$(basename "$b") $stages $(tail -1 "$out")"
  done
done
rm -f "$out"
