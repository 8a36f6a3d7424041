#!/usr/bin/env bash
# Peer tools measured SIDE BY SIDE with packbed's permeability -- never a
# dependency of packbed. Measures permeability k (x, y, z) of a packbed bed
# with (1) PoreSpy snow2 + OpenPNM StokesFlow and (2) Yade's FlowEngine.
#
#   bash scripts/bench-peers.sh BED_DIR [RES...]
#
# BED_DIR: packbed output folder (particles.csv + summary.json), e.g. made by
#   packbed run --radii 10 --box 200,200,800 --periodic --count 4000 \
#       --no-pictures --measures packing --out BED_DIR
# RES: PoreSpy voxels per sphere diameter (default: 5 10).
# Env: WORK (scratch folder, default /tmp/packbed-peers), NICE (default 19),
#      AXES (default xyz), SKIP_YADE=1, SKIP_PORESPY=1.
# Installs (as needed): a scratch venv with `porespy openpnm` (PyPI) and the
# Debian package `yade` (apt; needs root). Results: $WORK/peers.jsonl, and
# /usr/bin/time -v logs ($WORK/*.time) for wall time and peak memory.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bed="${1:?usage: bench-peers.sh BED_DIR [RES...]}"
shift || true
[ "$#" -gt 0 ] && resolutions=("$@") || resolutions=(5 10)
work="${WORK:-/tmp/packbed-peers}"
nice_n="${NICE:-19}"
axes="${AXES:-xyz}"
mkdir -p "$work"
out="$work/peers.jsonl"
name="$(basename "$bed")"

echo "peer measurement (not a packbed dependency) of $bed into $work"

if [ -z "${SKIP_PORESPY:-}" ]; then
  if [ ! -x "$work/venv/bin/python" ]; then
    python3 -m venv "$work/venv"
    nice -n "$nice_n" "$work/venv/bin/pip" install -q porespy openpnm
  fi
  "$work/venv/bin/python" -c 'import porespy, openpnm; print("porespy", porespy.__version__, "openpnm", openpnm.__version__)'
  for res in "${resolutions[@]}"; do
    echo "== PoreSpy/OpenPNM, $res voxels per diameter"
    /usr/bin/time -v -o "$work/porespy-$name-r$res.time" \
      nice -n "$nice_n" "$work/venv/bin/python" "$here/peer-porespy.py" "$bed" \
      --res "$res" --axes "$axes" --json "$out" | grep -v '^RESULT '
    grep -E 'Elapsed|Maximum resident' "$work/porespy-$name-r$res.time"
  done
fi

if [ -z "${SKIP_YADE:-}" ]; then
  if ! command -v yade >/dev/null; then
    apt-get update -q
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends yade
  fi
  echo "== Yade FlowEngine"
  /usr/bin/time -v -o "$work/yade-$name.time" \
    nice -n "$nice_n" yade -n -x "$here/peer-yade.py" "$bed" "$axes" "$out" \
    | grep -E '^(RESULT|yade|total)' | cut -c1-400
  grep -E 'Elapsed|Maximum resident' "$work/yade-$name.time"
fi
echo "results: $out"
