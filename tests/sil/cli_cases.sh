#!/bin/sh
# dtc-sil as a shell user meets it: exit codes, the message naming the key or cause,
# and no partial output, through the real binary and real signals.
#   cli_cases.sh DTC_SIL SOURCE_DIR WORK_DIR
set -u
exe=$1
src=$2
work=$3
scen="$src/tools/scenarios/fstp_voltage_proposed_full.toml"
rm -rf "$work"
mkdir -p "$work"
pass=0
fail=0

# expect NAME RC PATTERN -- ARGS...: exit status RC, PATTERN in stdout+stderr, nothing partial.
expect() {
    name=$1 rc=$2 pat=$3
    shift 4
    "$exe" "$@" >"$work/log" 2>&1
    got=$?
    if [ "$got" -ne "$rc" ]; then
        echo "FAIL $name: exit $got, expected $rc"; cat "$work/log"; fail=$((fail + 1)); return
    fi
    if ! grep -q -e "$pat" "$work/log"; then
        echo "FAIL $name: no '$pat' in:"; cat "$work/log"; fail=$((fail + 1)); return
    fi
    if ls "$work" | grep -q '\.partial-'; then
        echo "FAIL $name: a staging folder is left"; fail=$((fail + 1)); return
    fi
    echo "ok   $name"
    pass=$((pass + 1))
}
short="--set duration_s=0.005 --set metrics_window_s=0.002"

expect check_ok 0 ': ok$' -- check "$scen"
expect directory 1 'not a regular file' -- run "$work" --out "$work/o1"
: >"$work/empty.toml"
expect empty_file 1 'sets no key' -- run "$work/empty.toml" --out "$work/o1"
expect empty_out 1 'empty directory name' -- run "$scen" --out ""
# Found by fuzz_sil_cli: CLI11's Range passes NaN, and an empty DIR would write into the working directory.
expect pace_nan 1 '--pace: nan: expected a number' -- serve "$scen" --serial "$work/l" --pace nan
expect serve_duration_nan 1 '--duration-s: nan' -- serve "$scen" --serial "$work/l" --duration-s nan
expect max_time_nan 1 '--max-time: nan' -- identify "$scen" --out "$work/o1" --max-time nan
expect identify_empty_out 1 'empty directory name' -- identify "$scen" --out ""
expect serve_empty_serial 1 '--serial: empty path' -- serve "$scen" --serial ""
expect merge_empty_out 1 'empty directory name' -- sweep-merge --out "" "$work"
expect no_period 1 "duration_s: is 1e-300 s: shorter than one control period" -- run "$scen" --out "$work/o1" --set duration_s=1e-300
expect pole_pairs_check 1 'motor.pole_pairs: value 64 is impossible' -- check "$scen" --set motor.pole_pairs=64
expect vdc_names_key 1 'inverter.vdc_v' -- check "$scen" --set inverter.vdc_v=1e6
imscen="$src/tools/scenarios/im_dtc_speed.toml"
expect dfoc_bw_named 1 'control.dfoc_bw_hz.*1/(6 ts_s)' -- check "$imscen" --set control.scheme=dfoc --set control.dfoc_bw_hz=1100
expect dfoc_zeta_named 1 'control.dfoc_zeta.*K_p = 2 zeta w_c sigma L_s - R_s > 0' -- check "$imscen" --set control.scheme=dfoc --set control.dfoc_zeta=0.04
expect step_floor 1 'max_step_s: value 1e-15 is impossible' -- check "$scen" --set max_step_s=1e-15
expect unsafe_protection 1 'protection.allow_unsafe = true' -- run "$scen" --out "$work/o1" --set protection.overcurrent_a=100 --set protection.hw_trip_current_a=0
expect long_run 1 'use --decimate' -- run "$scen" --out "$work/o1" --set duration_s=9e4
test -e "$work/o1" && { echo "FAIL: $work/o1 written by a refused run"; fail=$((fail + 1)); }
# shellcheck disable=SC2086
# long enough for the drive to start after its gates-off calibration (51 ms on the FSTP with the
# mid-point calibration)
expect diverged 3 'plant_diverged' -- run "$scen" --out "$work/o2" -q --set duration_s=0.08 --set metrics_window_s=0.01 --set load.torque_nm=1e300
grep -q '"fault": "plant_diverged"' "$work/o2/metrics.json" || { echo "FAIL diverged: metrics.json"; fail=$((fail + 1)); }
# shellcheck disable=SC2086
expect hw_trip_named 0 'fault: hw_overcurrent' -- run "$src/tools/scenarios/open_loop_rated_current.toml" --out "$work/o3" --no-trace --set protection.hw_trip_current_a=1
# Started at 4000 rpm with the gates off for the offset calibration: the line back-EMF (67 V peak)
# exceeds what the FSTP's diodes block (35 V), the calibration sees rectifier current: named so.
expect rectifier_named 0 'fault: rectifier_conduction' -- run "$scen" --out "$work/o6" --no-trace --set initial_speed_rpm=4000 --set control.speed_ref_rpm=4000 --set duration_s=0.1 --set metrics_window_s=0.05 --set protection.vdc_max_v=200 --set sensors.voltage_range_v=250
# No progress line when stderr is not a terminal.
if grep -q 'ETA' "$work/log"; then echo "FAIL: progress line on a pipe"; fail=$((fail + 1)); fi

# On a terminal (script(1) gives it one) a run longer than 0.5 s wall shows the progress line.
if command -v script >/dev/null 2>&1; then
    script -qec "'$exe' run '$scen' --out '$work/o5' -q --no-trace --set duration_s=150" /dev/null >"$work/tty" 2>&1
    if tr '\r' '\n' <"$work/tty" | grep -a -q 's simulated (.*%), ETA '; then
        echo "ok   progress_on_tty"; pass=$((pass + 1))
    else
        echo "FAIL progress_on_tty:"; cat "$work/tty"; fail=$((fail + 1))
    fi
fi

# SIGTERM: exit 128 + 15, staging folder removed, destination not created.
"$exe" run "$scen" --out "$work/o4" -q --set duration_s=600 --decimate 1000 >"$work/log" 2>&1 &
pid=$!
i=0
while [ $i -lt 200 ] && ! ls "$work" | grep -q '\.partial-'; do sleep 0.05; i=$((i + 1)); done
kill -TERM $pid
wait $pid
rc=$?
if [ $rc -eq 143 ] && ! ls "$work" | grep -q '\.partial-' && [ ! -e "$work/o4" ]; then
    echo "ok   sigterm"; pass=$((pass + 1))
else
    echo "FAIL sigterm: exit $rc"; ls "$work"; fail=$((fail + 1))
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
