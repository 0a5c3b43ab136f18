#!/usr/bin/env bash
# Installs what the project needs from Debian's packages, and nothing else. Idempotent: it
# installs only what is missing. Works as root on a fresh Debian 12 machine; as another user it
# uses sudo if present, and otherwise prints the apt-get line to run.
set -euo pipefail

PKGS=(
  cmake ninja-build g++ pkg-config         # build
  libeigen3-dev                            # plant model (model/)
  libcmocka-dev                            # C unit tests (stands in for Unity/CMock, not in Debian)
  libgtest-dev                             # C++ model and SIL tests
  gcc-arm-none-eabi libnewlib-arm-none-eabi  # cross-cm0 portability proxy
  gcc-avr avr-libc                         # cross-avr 16-bit-int proxy
  libtomlplusplus-dev                      # scenario files
  nlohmann-json3-dev                       # metrics.json
  libfmt-dev                               # trace.csv: Dragonbox shortest round-trip decimals
  libcli11-dev                             # dtc-sil command line
  libfftw3-dev                             # THD / harmonics
  python3-numpy python3-matplotlib         # plots and report
  python3-serial                           # tools/console/dtc_console.py: the drive's serial line
  python3-distributed                      # dtc-sil sweep --dask (dask.distributed scheduler and workers)
  valgrind                                 # instruction-count budgets
  libsimavr-dev libelf-dev                 # processor-in-the-loop: AVR emulator as a library (tools/pil)
  qemu-system-arm                          # processor-in-the-loop: Cortex-M emulator (mps2-an385)
  clang libclang-rt-14-dev llvm-14         # fuzz preset: libFuzzer + ASan/UBSan runtimes, llvm-cov (tests/fuzz)
)

missing=()
for p in "${PKGS[@]}"; do
  [[ "$p" == \#* ]] && continue
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PKGS[@]} Debian packages present"
  exit 0
fi

echo "setup: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: not root and no sudo. Run as root:" >&2
    echo "  apt-get update && apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
