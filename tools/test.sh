#!/usr/bin/env bash
# The whole test suite, as CI runs it: installs what is missing, then builds and tests the host
# preset (unit, model, SIL, HAL and firmware-rules tests, which include the cross-cm0 and
# cross-avr builds), then the host-sanitize preset (ASan + UBSan, no recovery) on the same suite.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
tools/setup.sh
for preset in host host-sanitize; do
  echo "=== $preset: configure, build, test"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset"
  ctest --preset "$preset"
done
echo "=== all presets passed in $(( $(date +%s) - start )) s"
