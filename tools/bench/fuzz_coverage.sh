#!/usr/bin/env bash
# Source coverage of firmware/ by a fuzz corpus (docs/fuzzing.md): builds the ISR fuzz harness
# once more with clang's source-based coverage (no sanitizers), runs every input of CORPUS once
# (libFuzzer -runs=0), and prints llvm-cov's per-file and total line / region / function / branch
# coverage of the firmware files the harness links (firmware/app/app.c, the HAL binding, is not
# linked). Called by tools/bench/fuzz_bench.sh; also on its own:
#   tools/bench/fuzz_coverage.sh build/fuzz/bench/corpus build/fuzz/bench/coverage
set -euo pipefail
cd "$(dirname "$0")/../.."
CORPUS=${1:?corpus directory}
OUT=${2:?output directory}
LLVM_COV=${LLVM_COV:-llvm-cov-14}
LLVM_PROFDATA=${LLVM_PROFDATA:-llvm-profdata-14}
mkdir -p "$OUT"
rm -f "$OUT"/*.profraw
srcs=(firmware/fixmath/*.c firmware/dtc/*.c firmware/app/*.c
      tools/config/dtc_config_si.c tests/fuzz/fuzz_app_core.c)
clang -std=c99 -O1 -g -fprofile-instr-generate -fcoverage-mapping -fsanitize=fuzzer \
    -Ifirmware/dtc -Ifirmware/app -Ifirmware/fixmath -Ihal/include -Itools/config -Imodel/include \
    "${srcs[@]}" -lm -o "$OUT/fuzz_app_core_cov"
LLVM_PROFILE_FILE="$OUT/run-%p.profraw" "$OUT/fuzz_app_core_cov" -runs=0 "$CORPUS" >"$OUT/replay.log" 2>&1
"$LLVM_PROFDATA" merge -sparse "$OUT"/*.profraw -o "$OUT/fuzz.profdata"
"$LLVM_COV" report "$OUT/fuzz_app_core_cov" -instr-profile="$OUT/fuzz.profdata" \
    -ignore-filename-regex='(tools|tests|model|hal)/' >"$OUT/report.txt"
sed -n '1,2p;/^TOTAL/p' "$OUT/report.txt"
echo "fuzz_coverage: $(ls "$CORPUS" | wc -l) corpus inputs; per file: $OUT/report.txt"
