#!/usr/bin/env bash
# Peer drainage measured SIDE BY SIDE with packbed's (issue 58) -- never a
# dependency of packbed: PoreSpy snow2 + OpenPNM Drainage / InvasionPercolation
# (scripts/peer-drainage.py) at several resolutions, and Yade's
# TwoPhaseFlowEngine (scripts/peer-yade-drainage.py) if `yade` is installed.
#
#   bash scripts/bench-drainage.sh BED_DIR [RES...]
#
# BED_DIR: packbed output folder, e.g. the issue's 4,000 equal spheres:
#   packbed run --radii 10 --box 200,200,800 --periodic --count 4000 --seed 1 \
#       --no-pictures --measures packing --out BED_DIR
# RES: voxels per sphere diameter (default: 6 10 20; 30 needs ~4 GB).
# Env: WORK (scratch folder, default /tmp/packbed-peers), NICE (default 10),
#      SKIP_YADE=1, SKIP_PORESPY=1.
# Results: $WORK/drainage.jsonl; /usr/bin/time -v logs ($WORK/*.time).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bed="${1:?usage: bench-drainage.sh BED_DIR [RES...]}"
shift || true
[ "$#" -gt 0 ] && resolutions=("$@") || resolutions=(6 10 20)
work="${WORK:-/tmp/packbed-peers}"
nice_n="${NICE:-10}"
mkdir -p "$work"
out="$work/drainage.jsonl"
name="$(basename "$bed")"

echo "peer drainage (not a packbed dependency) of $bed into $work"

if [ -z "${SKIP_PORESPY:-}" ]; then
  if [ ! -x "$work/venv/bin/python" ]; then
    python3 -m venv "$work/venv"
    nice -n "$nice_n" "$work/venv/bin/pip" install -q porespy openpnm
  fi
  "$work/venv/bin/python" -c 'import porespy, openpnm; print("porespy", porespy.__version__, "openpnm", openpnm.__version__)'
  for res in "${resolutions[@]}"; do
    echo "== PoreSpy/OpenPNM drainage, $res voxels per diameter"
    /usr/bin/time -v -o "$work/drainage-$name-r$res.time" \
      nice -n "$nice_n" "$work/venv/bin/python" "$here/peer-drainage.py" "$bed" \
      --res "$res" --json "$out" 2>&1 | grep -E '^(image|snow2|summary)'
    grep -E 'Elapsed|Maximum resident' "$work/drainage-$name-r$res.time"
  done
fi

if [ -z "${SKIP_YADE:-}" ] && [ -f "$here/peer-yade-drainage.py" ]; then
  if ! command -v yade >/dev/null; then
    echo "yade not installed (Debian: apt-get install yade); skipped"
  else
    for walls in closed open; do
      echo "== Yade TwoPhaseFlowEngine drainage, side walls $walls"
      /usr/bin/time -v -o "$work/yade-drainage-$name-$walls.time" \
        nice -n "$nice_n" yade -n -x "$here/peer-yade-drainage.py" "$bed" "$out" both "$walls" 2>&1 \
        | grep -E '^(summary|yade|  trap)' | cut -c1-900
      grep -E 'Elapsed|Maximum resident' "$work/yade-drainage-$name-$walls.time"
    done
  fi
fi
echo "results: $out"
