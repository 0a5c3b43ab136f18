#!/usr/bin/env bash
# The ISR fuzzer's benchmark (docs/fuzzing.md): builds the `fuzz` preset and runs the libFuzzer
# harness of the application ISR (tests/fuzz/fuzz_app_core.c) for RUNS inputs (10^7 unless set)
# from a corpus holding only tests/fuzz/seeds.py's seeds ($OUT/corpus, emptied first) with a fixed
# seed, then prints the count,
# libFuzzer's coverage (cov: instrumented edges reached, ft: features; harness and host converter
# included), the wall time and how many steps each state and law variant received; then the
# source coverage of firmware/ by the corpus it grew (tools/bench/fuzz_coverage.sh). Any
# invariant failure or sanitizer report stops it with a non-zero exit and leaves the input in
# $OUT. Not part of the test run (the ctest slice fuzz.slice is).
#   RUNS=10000000 SEED=1 OUT=build/fuzz/bench tools/bench/fuzz_bench.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
RUNS=${RUNS:-10000000}
SEED=${SEED:-1}
OUT=${OUT:-build/fuzz/bench}
env --unset=CC --unset=CXX cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
python3 tests/fuzz/seeds.py "$OUT/corpus"
log="$OUT/fuzz_bench.log"
echo "fuzz_bench: $RUNS inputs, seed $SEED, log $log"
start=$(date +%s)
set +e
FUZZ_APP_STATS=1 build/fuzz/bin/fuzz_app_core -seed="$SEED" -runs="$RUNS" -print_final_stats=1 \
    -artifact_prefix="$OUT/" "$OUT/corpus" >"$log" 2>&1
rc=$?
set -e
secs=$(( $(date +%s) - start ))
grep -E '^#[0-9]+[[:space:]]+DONE' "$log" || true
grep -E '^stat::|^fuzz_app_core:' "$log" || true
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
cov=$(sed -n 's/^#[0-9]*[[:space:]]*DONE[[:space:]]*cov: \([0-9]*\) ft: \([0-9]*\).*/cov \1 ft \2/p' "$log")
echo "fuzz_bench: executed ${execs:-?} inputs in $secs s, ${cov:-no final coverage line}, exit $rc"
if [ "$rc" -ne 0 ] || grep -qE 'runtime error|ERROR: (AddressSanitizer|libFuzzer)|invariant failed' "$log"; then
  echo "fuzz_bench: FAILED: see $log" >&2
  grep -E 'runtime error|ERROR:|invariant failed|Test unit written' "$log" >&2 || true
  exit 1
fi
echo "fuzz_bench: no sanitizer report, no invariant failure"
tools/bench/fuzz_coverage.sh "$OUT/corpus" "$OUT/coverage"
