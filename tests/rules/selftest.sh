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

# The literal check must reject a constant the C28x's 32-bit double folds differently and accept
# the same constant written as a ratio of integers.
mkdir -p "$tmp/lit_bad" "$tmp/lit_good"
printf 'static const long k = IQ(1.0 / 3.0);\n' > "$tmp/lit_bad/x.c"
printf 'static const long k = IQ_FRAC(1, 3);\nstatic const long h = IQ(0.5);\n' > "$tmp/lit_good/x.c"
if python3 "$here/check_fix_literals.py" "$tmp/lit_bad" >/dev/null; then
  echo "selftest: the literal check accepted IQ(1.0 / 3.0)"; exit 1
fi
python3 "$here/check_fix_literals.py" "$tmp/lit_good" >/dev/null
echo "selftest: literal check rejects IQ(1.0 / 3.0), accepts IQ_FRAC(1, 3) and IQ(0.5)"
