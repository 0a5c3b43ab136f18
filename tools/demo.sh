#!/usr/bin/env bash
# The main job: installs what is missing, builds the host preset and shows what was built.
# (Becomes the SIL demo once the runner lands.)
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cmake --preset host >/dev/null
cmake --build --preset host
echo "=== built (build/host):"
find build/host -maxdepth 3 \( -name '*.a' -o -path '*/bin/*' \) -type f | sort
