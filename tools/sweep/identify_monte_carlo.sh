#!/usr/bin/env bash
# The self-commissioning's Monte Carlo (docs/commissioning.md): `dtc-sil sweep --identify` on the
# Hoang Table VIII rig with every machine parameter drawn +-30 % (uniform) around Table VIII, the
# pole pairs on a grid, the encoder mounted anywhere, datasheet-grade sensor errors, noise and
# dead time; each run identifies the machine and its row holds the errors against the plant's true
# values, asserted against the self-commissioning targets:
#   R_s 5 %, L_s 5 % (L_d as ls_h, and L_q: the machine is a surface PM, L_q = L_d), psi_m 3 %, encoder offset 3 degrees electrical, direction and pole pairs
#   exact, the inverter's drop at rated current 10 %, J 10 %.
# Draws (1 sigma for normal ones):
#   * motor: R_s 0.466 ohm, L_s 3.19 mH, psi_m 0.0928 Wb, J 5e-4 kg m^2 (rotor and DC generator),
#     viscous friction 4.77e-4 N.m.s/rad: each uniform within +-30 %; pole pairs 1, 2, 4 (grid, or
#     $POLE_PAIRS);
#   * encoder offset uniform over a turn;
#   * current sensors (a +-10 A Hall sensor): offset 10 mA, gain error 0.7 % per phase, noise 10 mA
#     rms per sample; DC-link and mid-point dividers: offset 0.3 V, gain error 0.7 %, noise 50 mV rms;
#   * inverter: dead time uniform 0.7 .. 1.3 us (the gate driver's tolerance), V_CE, V_D and R_on of
#     the plant uniform within +-30 % of Hoang Table IV (the identification's datasheet R_on, V_CE
#     and V_D are the plant's: `identify` reads inverter.*, docs/commissioning.md).
# Then a summary (DIR/SCENARIO/summary.csv per topology, DIR/identify_summary.md: per quantity the
# mean, worst and 95th percentile of the error and how many runs met the target).
#
#   tools/sweep/identify_monte_carlo.sh [N] [OUT] [JOBS] [SCENARIO...]
#     default 50 draws per pole-pair count and scenario into out/identify_mc, 1 job, the FSTP
#     (fstp_voltage_proposed_full) and SSTP (sstp_voltage_simple_full) rigs; exit 3 when a run
#     missed a target (the summary is written all the same). POLE_PAIRS=1 (environment) keeps the
#     Table VIII machine's pole pairs instead of the grid 1,2,4.
set -euo pipefail
cd "$(dirname "$0")/../.."
n=${1:-50}
out=${2:-out/identify_mc}
jobs=${3:-1}
shift $(($# < 3 ? $# : 3))
scenarios=("$@")
[ ${#scenarios[@]} -gt 0 ] || scenarios=(fstp_voltage_proposed_full sstp_voltage_simple_full)
exe=${DTC_SIL:-build/host/bin/dtc-sil}
[ -x "$exe" ] || { echo "build first: cmake --preset host && cmake --build --preset host" >&2; exit 1; }
rm -rf "$out"
mkdir -p "$out"
u() { python3 -c "print(f'uniform:{$1*0.7!r}:{$1*1.3!r}')"; }
args=(--identify --grid "motor.pole_pairs=${POLE_PAIRS:-1,2,4}" --n "$n" --seed 30 --jobs "$jobs" -q
  --sample "motor.rs_ohm=$(u 0.466)" --sample "motor.ls_h=$(u 3.19e-3)" --sample "motor.psi_m_wb=$(u 0.0928)"
  --sample "motor.j_kgm2=$(u 5e-4)" --sample "motor.b_nm_s_per_rad=$(u 4.7746e-4)"
  --sample "sensors.encoder_offset_rad=uniform:-3.14159:3.14159"
  --sample "sensors.current_offset_a=normal:0:0.01" --sample "sensors.current_gain_error=normal:0:0.007"
  --set "sensors.current_noise_a_rms=0.01" --set "sensors.voltage_noise_v_rms=0.05"
  --sample "inverter.dead_time_s=uniform:0.7e-6:1.3e-6"
  --sample "inverter.v_ce_v=$(u 0.9)" --sample "inverter.v_d_v=$(u 1.25)" --sample "inverter.r_on_ohm=$(u 0.075)")
for k in vdc vmid; do
  args+=(--sample "sensors.${k}_offset_v=normal:0:0.3" --sample "sensors.${k}_gain_error=normal:0:0.007")
done
asserts=(--assert "ok==1" --assert "rs_ohm.abs_error_pct<5" --assert "ls_h.abs_error_pct<5"
  --assert "lq_h.abs_error_pct<5"
  --assert "psi_m_wb.abs_error_pct<3" --assert "encoder_offset_el_deg.abs_error<3" --assert "pole_pairs.abs_error==0"
  --assert "encoder_reversed.abs_error==0" --assert "drop_at_rated_v.abs_error_pct<10" --assert "j_kgm2.abs_error_pct<10")
rc=0
for sc in "${scenarios[@]}"; do
  nice "$exe" sweep "tools/scenarios/$sc.toml" --out "$out/$sc" "${args[@]}" "${asserts[@]}" || rc=$?
done
python3 - "$out" <<'EOF'
import csv, math, os, sys
out = sys.argv[1]
targets = [("rs_ohm.abs_error_pct", 5, "R_s", "%"), ("ls_h.abs_error_pct", 5, "L_s (L_d)", "%"),
           ("lq_h.abs_error_pct", 5, "L_q", "%"),
           ("psi_m_wb.abs_error_pct", 3, "psi_m", "%"), ("encoder_offset_el_deg.abs_error", 3, "encoder offset", "deg el."),
           ("pole_pairs.abs_error", 0, "pole pairs", ""), ("encoder_reversed.abs_error", 0, "direction", ""),
           ("drop_at_rated_v.abs_error_pct", 10, "drop at rated current", "%"), ("j_kgm2.abs_error_pct", 10, "J", "%"),
           ("b_nm_s_per_rad.abs_error_pct", None, "viscous friction", "%"), ("standstill_s", 3, "standstill time", "s"),
           ("duration_s", 10, "whole sequence", "s")]
lines = ["| topology | quantity | runs | mean | 95th pct | worst | target | met |", "|---|---|---|---|---|---|---|---|"]
for sc in sorted(os.listdir(out)):
    path = os.path.join(out, sc, "summary.csv")
    if not os.path.exists(path):
        continue
    rows = list(csv.DictReader(open(path)))
    failed = [r for r in rows if r["status"] != "ok"]
    lines.append(f"| {sc} | identification succeeded | {len(rows)} | | | | all | {len(rows) - len(failed)} |")
    for r in failed:
        lines.append(f"| {sc} | failed run {r['run']} | | | | | | {r['fault']} |")
    for col, tgt, name, unit in targets:
        xs = sorted(float(r[col]) for r in rows if r.get(col, "") not in ("", None))
        if not xs:
            continue
        p95 = xs[min(len(xs) - 1, math.ceil(0.95 * len(xs)) - 1)]
        met = "" if tgt is None else str(sum(1 for x in xs if (x <= tgt if tgt == 0 else x < tgt)))
        lines.append(f"| {sc} | {name} ({unit}) | {len(xs)} | {sum(xs)/len(xs):.3g} | {p95:.3g} | {xs[-1]:.3g} | "
                     f"{'' if tgt is None else tgt} | {met} |")
text = "\n".join(lines) + "\n"
open(os.path.join(out, "identify_summary.md"), "w").write(text)
print(text, end="")
EOF
exit "$rc"
