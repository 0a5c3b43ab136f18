#!/bin/sh
# The hostile-input corpus (docs/reliability.md): every refusal class of dtc-sil (scenario files,
# --set, run, check, sweep, sweep-merge, sweep-exec) and dtc_config_gen, through the real binaries.
# Each case checks the exit status, that the message names the key (and for files the line), and
# that nothing is left behind: no staging folder or file, no output folder of a refused run.
#   hostile.sh DTC_SIL DTC_CONFIG_GEN SOURCE_DIR WORK_DIR
# Prints one line per case and, last, "hostile: N cases, P passed, F failed; exits: RC xCOUNT ...".
set -u
abs() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
exe=$(abs "$1")
gen=$(abs "$2")
src=$(abs "$3")
work=$(abs "$4")
scen="$src/tools/scenarios/fstp_voltage_proposed_full.toml"
rm -rf "$work"
mkdir -p "$work/in"
pass=0
fail=0
exits=""
short="--set duration_s=0.005 --set metrics_window_s=0.002"

note_exit() { exits="$exits $1"; }
bad() { echo "FAIL $1: $2"; sed 's/^/    /' "$work/log" | head -c 2000; fail=$((fail + 1)); }

# expect NAME RC PATTERN -- PROGRAM ARGS...: exit RC, PATTERN in stdout+stderr (grep -E), the
# message under 4 KB (nothing echoed whole), no staging left in $work, $work/out not created.
expect() {
    name=$1 rc=$2 pat=$3
    shift 4
    rm -rf "$work/out"
    "$@" >"$work/log" 2>&1
    got=$?
    note_exit $got
    if [ "$got" -ne "$rc" ]; then bad "$name" "exit $got, expected $rc"; return; fi
    if [ -n "$pat" ] && ! grep -q -E -e "$pat" "$work/log"; then bad "$name" "no /$pat/ in the output"; return; fi
    if [ "$(wc -c <"$work/log")" -gt 4096 ] && [ "$rc" -ne 0 ]; then bad "$name" "message over 4 KB"; return; fi
    if find "$work" -name '*.partial-*' | grep -q .; then bad "$name" "a staging folder or file is left"; return; fi
    if [ "$rc" -ne 0 ] && [ -e "$work/out" ]; then bad "$name" "output written by a refused run"; return; fi
    echo "ok   $name"
    pass=$((pass + 1))
}
sil() {
    n=$1 r=$2 p=$3
    shift 3
    expect "$n" "$r" "$p" -- "$exe" "$@"
}
# file NAME TEXT: a scenario file in $work/in
file() { printf '%s' "$2" >"$work/in/$1.toml"; }
py() { /usr/bin/python3 -c "$1"; }

# ---- the TOML reader: limits before parsing ----
py "open('$work/in/deep_dot.toml','w').write('.'.join(['a']*50000)+' = 1\n')"
expect deep_dotted_key 1 'deep_dot.toml:1:[0-9]+: a key of more than 8 dotted parts' -- "$exe" check "$work/in/deep_dot.toml"
py "open('$work/in/deep_hdr.toml','w').write('duration_s = 0.1\n['+'.'.join(['a']*50000)+']\nx = 1\n')"
expect deep_header 1 'deep_hdr.toml:2:[0-9]+: a key of more than 8' -- "$exe" check "$work/in/deep_hdr.toml"
py "open('$work/in/deep_aot.toml','w').write(''.join('[['+'.'.join(['a']*(i%8+1))+']]\n' for i in range(20000)))"
expect many_array_tables 1 'deep_aot.toml:1:[0-9]+: a: unknown key' -- "$exe" check "$work/in/deep_aot.toml"
py "open('$work/in/deep_arr.toml','w').write('duration_s = 0.1\nx = '+'['*50000+']'*50000+'\n')"
expect deep_arrays 1 'deep_arr.toml:2:[0-9]+: arrays or inline tables nested more than 8' -- "$exe" check "$work/in/deep_arr.toml"
py "open('$work/in/deep_inl.toml','w').write('motor = '+'{a = '*30000+'1'+'}'*30000+'\n')"
expect deep_inline_tables 1 'deep_inl.toml:1:[0-9]+: arrays or inline tables nested' -- "$exe" check "$work/in/deep_inl.toml"
py "open('$work/in/long_key.toml','w').write('duration_s = 0.1\n[motor]\n'+'k'*200+' = 1\n')"
expect long_key 1 'long_key.toml:3:[0-9]+: a key longer than 128 bytes' -- "$exe" check "$work/in/long_key.toml"
py "open('$work/in/long_quoted_key.toml','w').write('\"'+'k'*5000+'\" = 1\n')"
expect long_quoted_key 1 'long_quoted_key.toml:1:[0-9]+: a key longer than 128' -- "$exe" check "$work/in/long_quoted_key.toml"
py "open('$work/in/big.toml','w').write('[motor]\ntype = \"'+'x'*5000000+'\"\n')"
expect five_mb_string 1 'big.toml: [0-9]+ bytes, above the 1048576' -- "$exe" run "$work/in/big.toml" --out "$work/out"
py "open('$work/in/long_str.toml','w').write('[motor]\ntype = \"'+'x'*500000+'\"\n')"
expect long_string_not_echoed 1 'long_str.toml:2:[0-9]+: motor.type: expected one of .*\.\.\. \(500000 bytes\)' -- "$exe" check "$work/in/long_str.toml"
file quoted_dot 'duration_s = 0.1
"control.speed_ref_rpm" = -1500.0
[control]
speed_ref_rpm = 1500.0
'
expect quoted_dotted_key 1 'quoted_dot.toml:2:1: "control.speed_ref_rpm": unknown key \(quoted' -- "$exe" run "$work/in/quoted_dot.toml" --out "$work/out"
file quoted_dot_in_table '[control]
"speed_ref_rpm.x" = 1.0
'
expect quoted_dotted_key_in_table 1 'quoted_dot_in_table.toml:2:1: control."speed_ref_rpm.x": unknown key' -- "$exe" check "$work/in/quoted_dot_in_table.toml"
file quoted_plain '[control]
"speed_ref_rpm" = 300.0
'
expect quoted_plain_key_is_the_key 0 ': ok$' -- "$exe" check "$work/in/quoted_plain.toml"
file k_derived '[motor]
rs_ohm = 1000'
expect derived_refusal_file_line 1 'k_derived.toml:2:[0-9]+: motor.rs_ohm: .* follows from motor.rs_ohm' -- "$exe" check "$work/in/k_derived.toml"
file motor_only '[motor]
'
expect only_motor_table 1 'sets no key \(.*motor_only.toml:1:[0-9]+: \[motor\] empty\)' -- "$exe" run "$work/in/motor_only.toml" --out "$work/out"
file empty ''
expect empty_file 1 'empty.toml: the scenario sets no key' -- "$exe" run "$work/in/empty.toml" --out "$work/out"
file syntax 'duration_s = 0.1
[motor
'
expect toml_syntax 1 'syntax.toml:2:[0-9]+: TOML syntax error' -- "$exe" check "$work/in/syntax.toml"
file unknown_table 'duration_s = 0.1
[motr]
rs_ohm = 1.0
'
expect unknown_table 1 'unknown_table.toml:2:[0-9]+: \[motr\]: unknown table' -- "$exe" check "$work/in/unknown_table.toml"
file unknown_key '[motor]
rs_ohms = 1.0
'
expect unknown_key 1 'unknown_key.toml:2:[0-9]+: motor.rs_ohms: unknown key' -- "$exe" check "$work/in/unknown_key.toml"

# ---- one case for each class of key, from a file (key and line named) ----
file k_num '[motor]
rs_ohm = -1.0
'
expect number_out_of_range 1 'k_num.toml:2:[0-9]+: motor.rs_ohm: value -1 is impossible' -- "$exe" check "$work/in/k_num.toml"
file k_nan '[motor]
rs_ohm = nan
'
expect number_nan 1 'k_nan.toml:2:[0-9]+: motor.rs_ohm: value nan is impossible' -- "$exe" check "$work/in/k_nan.toml"
file k_inf '[inverter]
vdc_v = inf
'
expect number_inf 1 'k_inf.toml:2:[0-9]+: inverter.vdc_v: value inf is impossible' -- "$exe" check "$work/in/k_inf.toml"
file k_date 'duration_s = 1979-05-27
'
expect number_given_a_date 1 'k_date.toml:1:[0-9]+: duration_s: expected a number, got date' -- "$exe" check "$work/in/k_date.toml"
file k_int '[motor]
pole_pairs = 2.5
'
expect integer_not_whole 1 'k_int.toml:2:[0-9]+: motor.pole_pairs: expected an integer' -- "$exe" check "$work/in/k_int.toml"
file k_int_big '[sensors]
seed = 9223372036854775807
'
expect integer_huge 1 'k_int_big.toml:2:[0-9]+: sensors.seed: value .* is impossible' -- "$exe" check "$work/in/k_int_big.toml"
file k_bool '[inverter]
drops = "yes"
'
expect boolean_given_a_string 1 'k_bool.toml:2:[0-9]+: inverter.drops: expected true or false, got string' -- "$exe" check "$work/in/k_bool.toml"
file k_choice '[motor]
type = "dc"
'
expect choice_unknown 1 'k_choice.toml:2:[0-9]+: motor.type: expected one of "pmsm", "im", got "dc"' -- "$exe" check "$work/in/k_choice.toml"
file k_path '[control]
mode = "open_loop"
voltage_csv = "no_such.csv"
'
expect path_missing 1 'control.voltage_csv' -- "$exe" check "$work/in/k_path.toml"
file k_arr '[motor]
emf_gain = [1.0, 1.0]
'
expect array3_short 1 'k_arr.toml:2:[0-9]+: motor.emf_gain: expected an array of 3 numbers, got 2 elements' -- "$exe" check "$work/in/k_arr.toml"
file k_arr_type '[motor]
emf_gain = [1.0, "a", 1.0]
'
expect array3_element 1 'k_arr_type.toml:2:[0-9]+: motor.emf_gain: expected an array of 3 numbers, element 1 is string' -- "$exe" check "$work/in/k_arr_type.toml"
file k_fw '[firmware]
rs_ohm = -0.1
'
expect firmware_key 1 'k_fw.toml:2:[0-9]+: firmware.rs_ohm: value -0.1 is impossible' -- "$exe" check "$work/in/k_fw.toml"
file k_fault '[faults]
current_sensor_code = 5000
'
expect faults_key 1 'k_fault.toml:2:[0-9]+: faults.current_sensor_code: value 5000 is impossible' -- "$exe" check "$work/in/k_fault.toml"
file k_table_as_value 'motor = 1.0
'
expect section_not_a_table 1 'k_table_as_value.toml:1:[0-9]+: motor: expected a table' -- "$exe" check "$work/in/k_table_as_value.toml"

# ---- --set (the command line: the option and the key named) ----
sil set_unknown_key 1 "--set #1 'motor.rs_ohms=1': motor.rs_ohms: unknown key" check "$scen" --set motor.rs_ohms=1
sil set_nan 1 "duration_s: expected a number, got 'nan'|duration_s: value nan is impossible" check "$scen" --set duration_s=nan
sil set_quoted_key 1 'unknown key' check "$scen" --set '"control.speed_ref_rpm"=1'
sil set_no_equals 1 'expected key=value' check "$scen" --set duration_s
# a refused member the user did not set (derived): the key the user set that makes it impossible
sil derived_refusal_names_the_set_key 1 "--set #1 'motor.rs_ohm=1000': motor.rs_ohm: handover_speed_rpm .* follows from motor.rs_ohm" check "$src/tools/scenarios/sstp_current_full.toml" --set motor.rs_ohm=1000
# a refused member whose own keys the scenario sets (cal_hold lists motor.psi_m_wb, set in the
# file): the key that causes it, not the first listed key the scenario happens to set
sil derived_refusal_names_the_cause 1 "--set #1 'motor.rs_ohm=1000': motor.rs_ohm: cal_hold: .* follows from motor.rs_ohm" check "$scen" --set motor.rs_ohm=1000
py "open('$work/in/k_cause.toml','w').write(open('$scen').read().replace('rs_ohm = 0.466', 'rs_ohm = 1000.0'))"
expect derived_refusal_cause_file_line 1 'k_cause.toml:[0-9]+:[0-9]+: motor.rs_ohm: cal_hold: .* follows from motor.rs_ohm' -- "$exe" check "$work/in/k_cause.toml"
sil derived_refusal_names_the_belief 1 "--set #1 'firmware.rs_ohm=1000': firmware.rs_ohm: cal_hold: .* follows from firmware.rs_ohm" check "$scen" --set firmware.rs_ohm=1000 --set motor.rs_ohm=0.5
# no hardware comparator: an IM law and the PM ITC predict their currents (accepted); the PM DTC
# without the delay compensation does not (refused)
sil no_comparator_im_accepted 0 'im_dtc_speed.toml: ok' check "$src/tools/scenarios/im_dtc_speed.toml" --set protection.hw_trip_current_a=0
sil no_comparator_itc_accepted 0 'sstp_itc_full.toml: ok' check "$src/tools/scenarios/sstp_itc_full.toml" --set protection.hw_trip_current_a=0
sil no_comparator_no_prediction_refused 1 'protection.hw_trip_current_a: 0 \(no hardware comparator\) needs a firmware path' check "$src/tools/scenarios/sstp_current_full.toml" --set protection.hw_trip_current_a=0 --set control.delay_comp=false
sil huge_value_says_why 1 'motor.j_kgm2: inertia_kgm2 = 1e\+308: beyond the largest value' check "$scen" --set motor.j_kgm2=1e308
long=$(py "print('x'*100000)")
sil set_long_value_not_echoed 1 "motor.type: expected one of .*\.\.\. \(100000 bytes\)" check "$scen" --set "motor.type=$long"
sil window_50000_check 1 'metrics_window_s: is 50000 s, 1e\+09 samples' check "$scen" --set duration_s=50000 --set metrics_window_s=50000
sil window_50000_run 1 'metrics_window_s: is 50000 s' run "$scen" --out "$work/out" --set duration_s=50000 --set metrics_window_s=50000
sil window_over_duration 1 'metrics_window_s: is 2 s, longer than duration_s = 1 s' check "$scen" --set duration_s=1 --set metrics_window_s=2
sil periods_over_2e9 1 'duration_s: more than 2e9 control periods' check "$scen" --set duration_s=2e5
sil trace_guard 1 'trace.csv would be about .* use --decimate' run "$scen" --out "$work/out" --set duration_s=9e4
sil decimate_zero 1 'decimate' run "$scen" --out "$work/out" --decimate 0
sil unknown_option 1 'bogus' run "$scen" --out "$work/out" --bogus
sil out_empty 1 'empty directory name' run "$scen" --out ""
: >"$work/in/a_file"
sil out_is_a_file 1 'exists and is not a directory' run "$scen" --out "$work/in/a_file" $short
sil record_isr_reference 1 'record-isr' run "$scen" --out "$work/out" $short --set control.implementation=reference --record-isr "$work/rec.bin"

# ---- runs that complete: the result is right, not only the exit ----
sil angle_1e13_reduced 0 'fault: none' run "$scen" --out "$work/o_angle" --no-trace --set duration_s=0.12 --set metrics_window_s=0.02 --set initial_theta_m_rad=1e13
grep -q '"fault": "none"' "$work/o_angle/metrics.json" || { echo "FAIL angle: metrics.json"; fail=$((fail + 1)); }
sil diverged_exit_3 3 'plant_diverged' run "$scen" --out "$work/o_div" -q --set duration_s=0.08 --set metrics_window_s=0.01 --set load.torque_nm=1e300
sil trip_has_its_time 0 'fault: hw_overcurrent' run "$src/tools/scenarios/open_loop_rated_current.toml" --out "$work/o_trip" --no-trace --set protection.hw_trip_current_a=1
if grep -q '"fault_time_s": null' "$work/o_trip/metrics.json"; then echo "FAIL trip_has_its_time: fault_time_s null"; fail=$((fail + 1)); fi
# An existing output folder: the previous results stay until the new ones replace them all.
mkdir -p "$work/o_keep" && echo previous >"$work/o_keep/metrics.json" && echo mine >"$work/o_keep/notes.txt"
sil refused_run_keeps_previous 1 'unknown key' run "$scen" --out "$work/o_keep" --set nokey=1
grep -q previous "$work/o_keep/metrics.json" && grep -q mine "$work/o_keep/notes.txt" || { echo "FAIL previous output changed"; fail=$((fail + 1)); }

# SIGINT during --record-isr: exit 130, no recording under its name, no staging file.
"$exe" run "$scen" --out "$work/o_rec" -q --no-trace --set duration_s=600 --record-isr "$work/rec.bin" >"$work/log" 2>&1 &
pid=$!
i=0
while [ $i -lt 200 ] && ! ls "$work" | grep -q 'rec.bin.partial-'; do sleep 0.05; i=$((i + 1)); done
sleep 0.3
kill -INT $pid
wait $pid
rc=$?
note_exit $rc
if [ $rc -eq 130 ] && [ ! -e "$work/rec.bin" ] && ! ls "$work" | grep -q 'partial-' && grep -q 'nothing written' "$work/log"; then
    echo "ok   record_isr_sigint"; pass=$((pass + 1))
else
    bad record_isr_sigint "exit $rc"; ls "$work"
fi

# --out D where the move into D crosses file systems or fails part-way (mounts in a private mount
# namespace, where unshare -m is allowed): D a mount point (the staging folder goes inside it),
# a previous file of D that cannot be moved aside (a busy mount point: the files moved in so far
# are moved back, exit 2, nothing written), D on a read-only file system.
sil out_parent_missing 0 '' run "$scen" --out "$work/o_new/a/b" -q --no-trace $short
[ -s "$work/o_new/a/b/metrics.json" ] || { echo "FAIL out_parent_missing: no metrics.json"; fail=$((fail + 1)); }
if unshare -m true 2>/dev/null; then
    mkdir -p "$work/o_mnt" "$work/o_busy/trace.csv" "$work/o_ro"
    echo previous >"$work/o_busy/metrics.json"
    cat >"$work/mounts.sh" <<EOS
mount -t tmpfs none "$work/o_mnt" && mount -t tmpfs none "$work/o_busy/trace.csv" && mount -t tmpfs -o ro none "$work/o_ro" || exit 99
"$exe" run "$scen" --out "$work/o_mnt" -q $short; echo "rc_mnt=\$?"
ls -A "$work/o_mnt"
"$exe" run "$scen" --out "$work/o_busy" -q $short; echo "rc_busy=\$?"
ls -A "$work/o_busy"; cat "$work/o_busy/metrics.json"
"$exe" run "$scen" --out "$work/o_ro/D" -q $short; echo "rc_ro=\$?"
ls -A "$work/o_ro"
EOS
    unshare -m sh "$work/mounts.sh" >"$work/log" 2>&1
    if grep -q '^rc_mnt=0$' "$work/log" && grep -q '^trace.csv$' "$work/log"; then
        echo "ok   out_mount_point"; pass=$((pass + 1))
    else
        bad out_mount_point "the run into a mount point failed"
    fi
    if grep -q '^rc_busy=2$' "$work/log" && grep -q 'o_busy: cannot move the previous trace.csv aside' "$work/log" &&
        grep -q 'nothing written to .*o_busy' "$work/log" && grep -q '^previous$' "$work/log" &&
        [ "$(cat "$work/o_busy/metrics.json")" = previous ]; then
        echo "ok   out_move_fails_partway"; pass=$((pass + 1))
    else
        bad out_move_fails_partway "not all-or-nothing"
    fi
    if grep -q '^rc_ro=2$' "$work/log" && grep -q 'Read-only file system' "$work/log" &&
        ! grep -q '^D$' "$work/log"; then
        echo "ok   out_read_only"; pass=$((pass + 1))
    else
        bad out_read_only "a read-only parent"
    fi
    if find "$work" -name '*partial-*' | grep -q .; then bad out_mounts "a staging folder is left"; fi
else
    echo "skip out_mount_point, out_move_fails_partway, out_read_only: unshare -m not allowed here"
fi

# ---- sweeps ----
sw="sweep $scen --out $work/out $short"
sil sweep_timeout_nan 1 'timeout-s' $sw --grid control.speed_ref_rpm=100,200 --timeout-s nan
sil sweep_timeout_inf 1 'timeout-s' $sw --grid control.speed_ref_rpm=100,200 --timeout-s inf
sil sweep_n_1e8 1 '--n 100000000: the plan has 1e\+08 runs .* above the 1000000' $sw --sample motor.rs_ohm=uniform:0.5:0.6 --n 100000000
sil sweep_n_2p64m1 1 'above the 1000000' $sw --sample motor.rs_ohm=uniform:0.5:0.6 --n 18446744073709551615
sil sweep_n_2p64 1 '--n [0-9]+: the plan has' $sw --sample motor.rs_ohm=uniform:0.5:0.6 --n 18446744073709551616
sil sweep_grid_product 1 'the plan has .* runs' $sw --grid motor.rs_ohm=$(py "print(','.join(str(0.5+i*1e-4) for i in range(1001)))") --grid control.speed_ref_rpm=$(py "print(','.join(str(100+i) for i in range(1001)))")
sil sweep_assert_phase 1 "--assert fundamental_a\[Z\]>0: fundamental_a has no element \[Z\]" $sw --grid control.speed_ref_rpm=100 --assert 'fundamental_a[Z]>0'
sil sweep_assert_index 1 'has no element \[3\]' $sw --grid control.speed_ref_rpm=100 --assert 'fundamental_a[3]>0'
sil sweep_assert_unknown 1 "unknown metric 'nosuch'" $sw --grid control.speed_ref_rpm=100 --assert 'nosuch<1'
sil sweep_assert_nan 1 'right-hand side must be a finite number' $sw --grid control.speed_ref_rpm=100 --assert 'imbalance_pct<nan'
sil sweep_grid_unknown_key 1 "unknown scenario key 'motor.rs_ohms'" $sw --grid motor.rs_ohms=1
sil sweep_grid_bad_value 1 '--grid motor.rs_ohm: value -1 is rejected' $sw --grid motor.rs_ohm=-1
sil sweep_shard 1 'I must be below N' $sw --grid control.speed_ref_rpm=100 --shard 2/2
sil sweep_sample_nan 1 'finite numbers' $sw --sample motor.rs_ohm=uniform:nan:1 --n 2
echo 'not json' >"$work/in/chunk.txt"
expect sweep_exec_garbage 1 'not a sweep chunk' -- sh -c "'$exe' sweep-exec <'$work/in/chunk.txt'"

# One crashed (killed by SIGSEGV), one hanging (timeout) and one diverged run: exit 4, each named.
rm -rf "$work/sw3"
"$exe" sweep "$scen" --out "$work/sw3" --zip duration_s=600,600,0.08 --zip load.torque_nm=0.3,0.3,1e300 \
    --set metrics_window_s=0.01 --timeout-s 4 --jobs 3 >"$work/log" 2>&1 &
pid=$!
sleep 1.5
victim=$(pgrep -P $pid | sort -n | head -1)
[ -n "$victim" ] && kill -SEGV "$victim"
wait $pid
rc=$?
note_exit $rc
# (signal 11 in a plain build; under ASan its SEGV handler makes the run exit with status 1 instead)
if [ $rc -eq 4 ] && grep -qE 'run 0: crashed: run process (died: signal 11|exited with status 1 and no result)' "$work/log" &&
    grep -q 'run 1: timeout' "$work/log" && grep -q 'run 2: diverged' "$work/log"; then
    echo "ok   sweep_crash_hang_diverge"; pass=$((pass + 1))
else
    bad sweep_crash_hang_diverge "exit $rc"
fi
# The same rows accepted: --allow-failed-runs (with --resume nothing is rerun: the rows stand).
sil sweep_allow_failed 0 'sweep: 3 of 3 runs' sweep "$scen" --out "$work/sw3" --zip duration_s=600,600,0.08 --zip load.torque_nm=0.3,0.3,1e300 --set metrics_window_s=0.01 --timeout-s 4 --jobs 3 --resume --allow-failed-runs

# sweep-merge with a shard missing: exit 2, the missing runs counted.
"$exe" sweep "$scen" --out "$work/sh0" $short --grid control.speed_ref_rpm=100,200,300 --shard 0/2 -q >/dev/null 2>&1
sil merge_missing_shard 2 '1 of 3 runs have no row' sweep-merge --out "$work/merged" "$work/sh0"
sil merge_not_a_sweep 1 'not a sweep folder' sweep-merge --out "$work/merged2" "$work/in"

# Killing a sweep (SIGKILL: no handler runs) kills its runs too; SIGINT exits 130 and kills them.
for sig in KILL INT; do
    rm -rf "$work/swk"
    "$exe" sweep "$scen" --out "$work/swk" --grid control.speed_ref_rpm=100,200 --set duration_s=60 --set metrics_window_s=0.01 --jobs 2 >"$work/log" 2>&1 &
    pid=$!
    sleep 1
    kids=$(pgrep -P $pid)
    kill -$sig $pid
    wait $pid
    rc=$?
    note_exit $rc
    # gone, or a zombie waiting for init to reap it, within 3 s
    i=0
    alive="$kids"
    while [ $i -lt 30 ] && [ -n "$alive" ]; do
        alive=""
        for k in $kids; do
            st=$(ps -o stat= -p "$k" 2>/dev/null)
            case $st in "" | Z*) ;; *) alive="$alive $k" ;; esac
        done
        [ -n "$alive" ] && sleep 0.1
        i=$((i + 1))
    done
    want=137
    [ $sig = INT ] && want=130
    if [ -n "$kids" ] && [ -z "$alive" ] && [ $rc -eq $want ]; then
        echo "ok   sweep_sig$sig"; pass=$((pass + 1))
    else
        bad sweep_sig$sig "exit $rc (expected $want), runs $kids, still alive:$alive"
        for k in $alive; do kill -KILL "$k"; done
    fi
done

# ---- dtc_config_gen ----
cd "$work" || exit 1
gen_case() { expect "$@"; }
gen_case gen_help 0 'Usage:' -- "$gen" --help
gen_case gen_h 0 'Usage:' -- "$gen" -h
gen_case gen_version 0 'dtc_config_gen [0-9]+\.[0-9]+\.[0-9]+ \(configuration version [0-9]+\)' -- "$gen" --version
gen_case gen_unknown_option 2 'not expected: --bogus' -- "$gen" --bogus out.c
gen_case gen_no_args 2 'output is required' -- "$gen"
gen_case gen_relay_nan 2 'reconfig-relay.*\(0, 10\]' -- "$gen" --reconfig-relay nan out.c
gen_case gen_relay_order 0 "" -- "$gen" --reconfig-relay 0.015 --f2812-board out_relay.c
gen_case gen_im_relay 2 'reconfig-relay with --im: the IM law has no post-fault configuration' -- "$gen" --im --reconfig-relay 0.015 out_im.c
gen_case gen_bad_symbol 2 "SYMBOL '9bad': is not a C identifier" -- "$gen" out.c 9bad
gen_case gen_keyword_symbol 2 "SYMBOL 'int': is a C keyword" -- "$gen" out.c int
gen_case gen_reserved_symbol 2 'reserved' -- "$gen" out.c __x
gen_case gen_long_symbol 2 'is 60 characters' -- "$gen" out.c "$(py "print('a'*60)")"
gen_case gen_full_disk 1 '/dev/full: write error: No space left on device' -- "$gen" /dev/full
gen_case gen_missing_dir 1 'no_dir/out.c.partial-[0-9]+: No such file' -- "$gen" no_dir/out.c
for f in -- --help -h --version --bogus --f2812-board out.c; do
    [ -e "$work/$f" ] && { echo "FAIL dtc_config_gen wrote a file named $f"; fail=$((fail + 1)); }
done
if [ -s "$work/out_relay.c" ] && cc -std=c99 -Wall -Werror -c -I"$src/firmware/dtc" -I"$src/firmware/fixmath" \
    -o "$work/out_relay.o" "$work/out_relay.c" 2>"$work/log"; then
    echo "ok   gen_output_compiles"; pass=$((pass + 1))
else
    bad gen_output_compiles "the generated C does not compile"
fi

total=$((pass + fail))
summary=$(for x in $exits; do echo "$x"; done | sort -n | uniq -c | awk '{printf " %s x%s", $2, $1}')
echo "hostile: $total cases, $pass passed, $fail failed; exits:$summary"
[ $fail -eq 0 ]
