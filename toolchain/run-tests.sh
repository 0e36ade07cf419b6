#!/usr/bin/env bash
# Every test of the project, as CI runs it: install the packages, build each preset, run its tests.
set -euo pipefail
cd "$(dirname "$0")/.."
./toolchain/install-deps.sh
jobs=$(nproc)
for preset in host stm32f4 linux-sbc; do
  echo "== preset ${preset} =="
  cmake --preset "${preset}"
  cmake --build --preset "${preset}" -j "${jobs}"
done
# The Raspberry Pi binary, cross-compiled (built, not run here).
echo "== aarch64 cross build of odocal-linux =="
cmake --preset linux-sbc -B build/aarch64 -DCMAKE_TOOLCHAIN_FILE="$PWD/toolchain/aarch64-linux-gnu.cmake"
cmake --build build/aarch64 -j "${jobs}" --target odocal-linux
status=0
for preset in stm32f4 linux-sbc host; do
  echo "== tests ${preset} =="
  ctest --preset "${preset}" -j "${jobs}" || status=1
done
exit ${status}
