#!/usr/bin/env bash
# Proves the source check can fail: it must reject a file with a float and accept a clean one.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/bad" "$tmp/good"
printf '#include <stdint.h>\n/* a float in a comment is fine */\nfloat gain = 1;\n' > "$tmp/bad/x.c"
printf '#include <stdint.h>\n/* double in a comment is fine */\nint32_t gain = 1;\n' > "$tmp/good/x.c"
if "$here/check_firmware_source.sh" "$tmp/bad" >/dev/null; then
  echo "selftest: the checker accepted a float"; exit 1
fi
"$here/check_firmware_source.sh" "$tmp/good" >/dev/null
echo "selftest: checker rejects float, accepts clean code"
