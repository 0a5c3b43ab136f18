#!/usr/bin/env bash
# Firmware-rules check, object side. Lists the undefined symbols of the cross-built firmware
# library and fails when any is a soft-float, double or integer-division helper: on a Cortex-M0
# (no FPU, no divide instruction) every float, double or '/' and '%' on a variable becomes such a
# call, so an empty list proves the control path uses neither.
#   usage: check_cross_symbols.sh NM LIBRARY...
set -euo pipefail
nm_tool=${1:?usage: check_cross_symbols.sh NM LIBRARY...}
[ $# -ge 2 ] || { echo "usage: check_cross_symbols.sh NM LIBRARY..." >&2; exit 2; }
status=0
for lib in "${@:2}"; do
[ -f "$lib" ] || { echo "check_cross_symbols: $lib not found (did the cross build run?)" >&2; exit 2; }
undef=$("$nm_tool" -u "$lib" | awk 'NF>=2 && $1=="U" {print $2}' | sort -u)
bad=$(grep -E '^(__aeabi_[fd]|__aeabi_.*div|__aeabi_.*mod|__(div|mod|udiv|umod)[sd]i3|__.*(sf|df)[0-9]?$|__(add|sub|mul|div)[sd]f3|__float|__fix|__extend|__trunc|(sqrt|sin|cos|atan2?)f?$)' <<<"$undef" || true)
echo "check_cross_symbols: $(wc -l <<<"$undef" | tr -d ' ') undefined symbols in $(basename "$lib"): $(tr '\n' ' ' <<<"$undef")"
if [ -n "$bad" ]; then
  echo "check_cross_symbols: forbidden helper calls in $(basename "$lib"):" $bad
  status=1
else
  echo "check_cross_symbols: $(basename "$lib"): no float, double or division helpers"
fi
done
exit $status
