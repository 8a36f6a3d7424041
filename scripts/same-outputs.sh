#!/usr/bin/env bash
# Runs every example config through two packbed binaries and compares every
# output file byte for byte (summary.json / ensemble.json: timing fields removed
# first, since wall-clock times differ run to run; timing.json holds nothing
# else; the analysed file's own path is dropped too).
#   scripts/same-outputs.sh OLD_BINARY NEW_BINARY [WORKDIR]
# Exit 0 when every file agrees; prints the files that differ otherwise.
set -euo pipefail
old=$1 new=$2 work=${3:-$(mktemp -d)}
here=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$work/old" "$work/new"; mkdir -p "$work/old" "$work/new"

produce() { # BIN OUTDIR
  local bin=$1 out=$2 cfg name
  "$bin" run --out "$out/default" >/dev/null
  for cfg in "$here"/examples/*.toml "$here"/examples/thesis/*.toml "$here"/examples/thesis/chains/*.toml; do
    name=$(basename "$(dirname "$cfg")")-$(basename "$cfg" .toml)
    if grep -qE '^\[(sweep|ensemble)\]' "$cfg"; then
      "$bin" ensemble "$cfg" --runs 3 --jobs 2 --out "$out/$name" >/dev/null
    else
      "$bin" run "$cfg" --out "$out/$name" >/dev/null
    fi
  done
  "$bin" run --dim 2 --radii 10,20 --beads 3 --seed 9 --out "$out/chains2d" >/dev/null
  "$bin" analyze "$out/default/particles.csv" --out "$out/analyze-default" >/dev/null
  "$bin" render "$out/chains2d/particles.csv" --out "$out/chains2d-render.svg" >/dev/null
  "$bin" render "$out/default/particles.csv" --color chains --out "$out/default-render.png" >/dev/null
}
produce "$old" "$work/old"
produce "$new" "$work/new"

strip_timing() { python3 - "$1" <<'PY'
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in ("source", "timing", "seconds", "wall_seconds", "elapsed_seconds", "rate", "beds_per_second", "particles_per_second")}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(open(sys.argv[1]))), indent=1, sort_keys=True))
PY
}
status=0; count=0
while IFS= read -r -d '' f; do
  rel=${f#"$work/old/"}; g="$work/new/$rel"; count=$((count+1))
  if [[ ! -f $g ]]; then echo "missing in new: $rel"; status=1; continue; fi
  case $rel in
    */timing.json|timing.json) ;; # wall-clock times only
    *.json) cmp -s <(strip_timing "$f") <(strip_timing "$g") || { echo "differs: $rel"; status=1; } ;;
    *) cmp -s "$f" "$g" || { echo "differs: $rel"; status=1; } ;;
  esac
done < <(find "$work/old" -type f -print0)
extra=$(cd "$work/new" && find . -type f | wc -l)
[[ $extra -eq $count ]] || { echo "new wrote $extra files, old $count"; status=1; }
echo "$count files compared in $work: $([[ $status -eq 0 ]] && echo all identical || echo DIFFERENCES)"
exit $status
