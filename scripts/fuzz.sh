#!/usr/bin/env bash
# Coverage-guided fuzzing of packbed's input layers with AFL++ (cargo-afl,
# stable toolchain). Targets: fuzz/src/lib.rs (bed, config, psd_table, merge,
# resume, compare).
#
#   scripts/fuzz.sh [--seconds N] [--memory MIB] [TARGET ...]   (default: all)
#
# Each target runs N seconds (default 60) under an address-space limit of MIB
# (default 4096; an input that makes packbed allocate beyond it is a crash),
# starting from its seeds (fuzz/seeds/TARGET) or resuming its last run
# (fuzz/out/TARGET, not committed). Prints each target's executions, paths and
# findings; exits 1 if any target found a crash or a hang. A finding is fixed
# in packbed, then its input is kept in fuzz/regressions/TARGET, which
# `cargo test` replays (fuzz/tests/replay.rs).
#
# Needs cargo-afl (`cargo install cargo-afl`); it builds AFL++ itself.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=60
memory=4096
targets=()
while [ $# -gt 0 ]; do
    case "$1" in
        --seconds) seconds="$2"; shift 2 ;;
        --memory) memory="$2"; shift 2 ;;
        -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
        all) shift ;;
        *) targets+=("$1"); shift ;;
    esac
done
[ ${#targets[@]} -gt 0 ] || targets=(bed config psd_table merge resume compare)

command -v cargo-afl >/dev/null || { echo "fuzz.sh: cargo-afl not found (cargo install cargo-afl)" >&2; exit 1; }

# A target directory of its own: AFL++'s instrumentation flags would
# otherwise invalidate the workspace's ordinary builds.
export CARGO_TARGET_DIR="$PWD/target/afl"
cargo afl build --release --features afl -p packbed-fuzz

# The machine is shared (CI, other fuzzers, a developer): no CPU pinning, no
# UI, and no demand that core dumps go to a file.
export AFL_NO_AFFINITY=1 AFL_NO_UI=1 AFL_SKIP_CPUFREQ=1
export AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_SKIP_CRASHES=1
# Coverage of a persistent Rust target varies a little between runs (rayon's
# threads); that is not a finding.
export AFL_IGNORE_PROBLEMS=1

mkdir -p fuzz/out
status=0
for t in "${targets[@]}"; do
    [ -d "fuzz/seeds/$t" ] || { echo "fuzz.sh: unknown target $t (fuzz/seeds/$t missing)" >&2; exit 1; }
    out="fuzz/out/$t"
    bin="$CARGO_TARGET_DIR/release/fuzz-${t//_/-}"
    if [ -f "$out/default/fuzzer_stats" ]; then
        input=-   # resume
    else
        input="fuzz/seeds/$t"
    fi
    echo "== fuzz $t: ${seconds}s, ${memory} MiB"
    # The rayon pool of the library: one thread, so that a run is one core.
    RAYON_NUM_THREADS=1 cargo afl fuzz -i "$input" -o "$out" -V "$seconds" -m "$memory" -t 10000 \
        -- "$bin" >"fuzz/out/$t.log" 2>&1 || { tail -20 "fuzz/out/$t.log" >&2; status=1; continue; }
    stats="$out/default/fuzzer_stats"
    get() { sed -n "s/^$1 *: //p" "$stats"; }
    crashes=$(get saved_crashes)
    hangs=$(get saved_hangs)
    echo "   $(get execs_done) executions in $(get run_time) s, $(get corpus_count) inputs in the corpus, edges $(get edges_found), crashes $crashes, hangs $hangs"
    if [ "${crashes:-0}" != 0 ] || [ "${hangs:-0}" != 0 ]; then
        echo "   findings in $out/default/crashes and $out/default/hangs" >&2
        status=1
    fi
done
# Scratch directories of target processes that have ended (not of fuzzers
# still running beside this one).
for d in /dev/shm/packbed-fuzz-*; do
    [ -d "$d" ] && ! kill -0 "${d##*-}" 2>/dev/null && rm -rf "$d"
done
exit $status
