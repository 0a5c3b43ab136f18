#!/usr/bin/env bash
# DTC budget report: prints the figures, does not judge them (targets in brackets).
#   1. host instructions per dtc_step() (valgrind --tool=callgrind, host preset build of
#      tools/bench/bench_dtc.c: FSTP, voltage model, Table VI compensation, speed loop on):
#      average, and the speed-loop steps (the worst path)            [avg <= 1500, worst <= 2500]
#   2. cross-cm0 stack usage of the control path (-fstack-usage per function from the preset's
#      build, worst call chain from -fcallgraph-info=su)              [<= 256 bytes]
#   3. cross-cm0 code and data size of the firmware library (arm-none-eabi-size)
# usage: tools/bench/run_budget.sh        (or: cmake --build build/host --target dtc_budget)
#   DTC_BENCH=path/to/dtc_bench  DTC_BENCH_STEPS=20000
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bench=${DTC_BENCH:-$root/build/host/bin/dtc_bench}
steps=${DTC_BENCH_STEPS:-20000}
py=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

[ -x "$bench" ] || { echo "run_budget: $bench not built (cmake --build build/host --target dtc_bench)" >&2; exit 2; }

echo "== 1. host instructions per dtc_step (valgrind callgrind, $steps periods = $(( steps / 20 )) ms)"
valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" "$bench" "$steps" >"$tmp/bench.txt" 2>"$tmp/vg.txt"
cat "$tmp/bench.txt"
callgrind_annotate --inclusive=yes "$tmp/cg.out" >"$tmp/ann.txt" 2>/dev/null
"$py" - "$tmp/bench.txt" "$tmp/ann.txt" <<'PY'
import re, sys
bench, ann = open(sys.argv[1]).read(), open(sys.argv[2]).read()
n_norm, n_tick = map(int, re.search(r"calls normal (\d+) tick (\d+)", bench).groups())
def ir(fn):
    m = re.search(r"^\s*([\d,]+)\s+\([^)]*\)\s+\S*:%s\b" % fn, ann, re.M)
    return int(m.group(1).replace(",", "")) if m else None
i_norm, i_tick, i_step = ir("bench_step_normal"), ir("bench_step_tick"), ir("dtc_step")
print("  dtc_step inclusive: %d instructions in %d calls" % (i_step, n_norm + n_tick))
print("  average per dtc_step (all calls)        : %7.1f   [target <= 1500]" % (i_step / (n_norm + n_tick)))
print("  average per ordinary step (%5d calls)  : %7.1f" % (n_norm, i_norm / n_norm))
print("  average per speed-loop step (%4d calls) : %7.1f   [worst path; target <= 2500]" % (n_tick, i_tick / n_tick))
print("  (the wrapper adds ~3 instructions per call to the last two figures)")
for fn in ("flux_est_step", "vcomp_step", "iq_mag", "fix_isqrt64", "speed_meas_step", "speed_pi_step"):
    v = ir(fn)
    if v is not None:
        print("    of which %-16s %7.1f per step" % (fn, v / (n_norm + n_tick)))
PY


# Per-call distribution: collect only inside one wrapper and dump after every call, so each dump
# holds exactly one dtc_step() (plus the wrapper's call/return).
percall_steps=${DTC_BENCH_PERCALL_STEPS:-2000}
for kind in normal tick; do
  mkdir -p "$tmp/pc_$kind"
  valgrind --tool=callgrind --callgrind-out-file="$tmp/pc_$kind/cg" --collect-atstart=no \
    --toggle-collect=bench_step_$kind --dump-after=bench_step_$kind "$bench" "$percall_steps" \
    >/dev/null 2>&1
  grep -h '^totals:' "$tmp/pc_$kind"/cg.* | awk -v k="$kind" '$2 > 0 { n++; s += $2; if ($2 > m) m = $2; if (mn == "" || $2 < mn) mn = $2 }
    END { printf "  per call, %-6s steps (%4d calls, first %d periods): min %d, mean %.1f, max %d instructions\n", k, n, '"$percall_steps"', mn, s / n, m }'
done
echo "  (worst single call = the max of the speed-loop steps; target <= 2500)"

echo
echo "== 2. cross-cm0 stack usage of the control path"
(cd "$root" && env -u CC -u CXX cmake --preset cross-cm0 >/dev/null && cmake --build --preset cross-cm0 >/dev/null)
echo "  -fstack-usage of the cross-cm0 build (build/cross-cm0, MinSizeRel):"
find "$root/build/cross-cm0/firmware" -name '*.su' -print0 | xargs -0 cat |
  grep -E ':(dtc_step|dtc_shadow_adopt|flux_est_[a-z_]+|vcomp_step|vrec_[a-z]+|speed_meas_step|speed_pi_step|swtab_[a-z_0-9]+|fix_isqrt64|iq_mag|fix_sin|fix_cos|fix_sector6|fix_quadrant|dtc_adopt)\s' |
  sed -E 's#^.*/##' | awk -F'\t' '{ printf "    %-44s %5s bytes %s\n", $1, $2, $3 }'
# The call graph: the same sources, flags as the preset (toolchain-arm-none-eabi-cm0 + MinSizeRel).
for f in "$root"/firmware/dtc/*.c "$root"/firmware/fixmath/fixmath.c; do
  arm-none-eabi-gcc -std=c99 -mcpu=cortex-m0 -mthumb -ffreestanding -fno-common -ffunction-sections \
    -fdata-sections -Os -DNDEBUG -fstack-usage -fcallgraph-info=su \
    -I"$root/firmware/dtc" -I"$root/firmware/fixmath" -c "$f" -o "$tmp/$(basename "$f" .c).o"
done
"$py" "$root/tools/bench/stack_report.py" dtc_step "$tmp" "$(arm-none-eabi-gcc -mcpu=cortex-m0 -mthumb -print-libgcc-file-name)"

echo
echo "== 3. cross-cm0 code and data size (arm-none-eabi-size, bytes)"
lib="$root/build/cross-cm0/firmware/libdtc_firmware.a"
arm-none-eabi-size -t "$lib" | sed -E 's#\(ex [^)]*\)##' | awk 'NR==1 || /dtc|fix|vrec|vcomp|flux|speed|swtab|hyst|clarke|TOTALS/ { printf "  %s\n", $0 }'
echo "  (text = code + constant tables in flash; data + bss = RAM: none, the modules keep no"
echo "   static state. The controller state dtc_t is caller-owned; its size on the target:)"
printf '#include "dtc.h"\ndtc_t dtc_budget_instance;\nconst dtc_config_t *dtc_budget_cfg;\n' >"$tmp/sz.c"
arm-none-eabi-gcc -std=c99 -mcpu=cortex-m0 -mthumb -ffreestanding -fno-common -Os \
  -I"$root/firmware/dtc" -I"$root/firmware/fixmath" -c "$tmp/sz.c" -o "$tmp/sz.o"
hex=$(arm-none-eabi-nm -S "$tmp/sz.o" | awk '/dtc_budget_instance/ { print $2 }')
echo "  sizeof(dtc_t) = $((16#$hex)) bytes of RAM" 
