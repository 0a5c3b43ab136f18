#!/usr/bin/env bash
# Firmware-rules check, source side. Fails (exit 1) when any C file under the given firmware
# folder uses float or double, includes <math.h>, uses int8_t/uint8_t (absent on the C28x, whose
# char is 16 bits) or calls the heap. Comments are stripped first with the C preprocessor
# (-fpreprocessed: comments removed, macros and includes left alone), so prose may name them.
#   usage: check_firmware_source.sh FIRMWARE_DIR
set -euo pipefail
dir=${1:?usage: check_firmware_source.sh FIRMWARE_DIR}
cc=${CC:-cc}
pattern='\b(float|double)\b|<math\.h>|\b(u?int8_t)\b|\b(malloc|calloc|realloc|free)[[:space:]]*\('
status=0
count=0
while IFS= read -r -d '' f; do
  count=$((count + 1))
  hits=$("$cc" -fpreprocessed -dD -E -P -x c "$f" 2>/dev/null | grep -E "$pattern" || true)
  if [ -n "$hits" ]; then
    # Report the line of the original file (the stripped text has its own numbering).
    while IFS= read -r h; do
      line=$(grep -nF -- "$(sed 's/^[[:space:]]*//' <<<"$h")" "$f" | head -1 | cut -d: -f1)
      echo "firmware rule violated at $f:${line:-?}: $h"
    done <<<"$hits"
    status=1
  fi
done < <(find "$dir" -type f \( -name '*.c' -o -name '*.h' -o -name '*.inc' \) -print0)
if [ "$count" -eq 0 ]; then
  echo "check_firmware_source: no C files under $dir" >&2
  exit 2
fi
if [ $status -eq 0 ]; then
  echo "check_firmware_source: $count files clean (no float/double, <math.h>, int8_t/uint8_t, heap)"
fi
exit $status
