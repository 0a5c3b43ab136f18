#!/usr/bin/env bash
# A Monte Carlo tolerance study of the default PM drive (FSTP, voltage model, proposed
# compensation, 1500 rpm, full load), as a drive engineer would run it before ordering parts:
#   * current sensors: offset and gain error per phase within a datasheet's range (a +-10 A Hall
#     sensor: offset 1 sigma 10 mA, gain error 1 sigma 0.7 %, i.e. about +-2 % at 3 sigma);
#   * DC-link and mid-point voltage sensors: offset 1 sigma 0.3 V, gain 1 sigma 0.7 %;
#   * the firmware's own machine parameters (firmware.* keys) +-10 % (uniform) against the plant's.
# Then histograms and the worst cases (tools/plot/plot_sweep.py) and an envelope check.
#
#   tools/sweep/monte_carlo_example.sh [N] [OUT]        (default 500 runs into out/monte_carlo)
set -euo pipefail
cd "$(dirname "$0")/../.."
n=${1:-500}
out=${2:-out/monte_carlo}
exe=build/host/bin/dtc-sil
[ -x "$exe" ] || { echo "build first: cmake --preset host && cmake --build --preset host" >&2; exit 1; }
rm -rf "$out"
args=(--sample "sensors.current_offset_a=normal:0:0.01" --sample "sensors.current_gain_error=normal:0:0.007")
for k in vdc vmid; do
  args+=(--sample "sensors.${k}_offset_v=normal:0:0.3" --sample "sensors.${k}_gain_error=normal:0:0.007")
done
# Firmware parameter mismatch, where this build has the keys.
for k in rs_ohm ls_h psi_m_wb; do
  if "$exe" keys | grep -q "\`firmware.$k\`"; then
    nominal=$("$exe" keys | grep "\`motor.$k\`" | awk -F'|' '{gsub(/ /,"",$5); print $5}')
    args+=(--sample "firmware.$k=uniform:$(python3 -c "print($nominal*0.9)"):$(python3 -c "print($nominal*1.1)")")
  fi
done
"$exe" sweep tools/scenarios/fstp_voltage_proposed_full.toml --out "$out" --n "$n" --seed 1 "${args[@]}" \
  --assert 'speed_mean_rpm>=1485' --assert 'hw_trip==0' || echo "monte_carlo_example: envelope violated (see above)"
/usr/bin/python3 tools/plot/plot_sweep.py "$out"
