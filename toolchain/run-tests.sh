#!/usr/bin/env bash
# Every test of the project, as CI runs it: install the packages, build each preset, run its tests.
# The last line is the grand total over every preset: "N passed, N failed", counting test cases
# (each GoogleTest case, and each other ctest entry: an image check, the QEMU console test, a
# study); the line before it counts the ctest entries. The exit status is non-zero when a test
# failed or a preset's tests could not run.
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
passed=0
failed=0
skipped=0
cases_passed=0
cases_failed=0
log=$(mktemp)
xml=$(mktemp -d)
trap 'rm -rf "${log}" "${xml}"' EXIT
for preset in stm32f4 linux-sbc host; do
  echo "== tests ${preset} =="
  rm -rf "${xml:?}"/* "build/${preset}/test-xml"
  set +e
  # Each GoogleTest program writes its cases to ${xml}/PROGRAM.xml (GTEST_OUTPUT).
  GTEST_OUTPUT="xml:${xml}/" ctest --preset "${preset}" -j "${jobs}" 2>&1 | tee "${log}"
  ctest_status=${PIPESTATUS[0]}
  set -e
  # The per-test entries' reports (gtest_discover_tests' XML_OUTPUT_DIR) are in the build tree.
  read -r cp cf <<<"$(python3 toolchain/count-test-cases.py "${log}" "${xml}" "build/${preset}/test-xml")"
  cases_passed=$((cases_passed + cp))
  cases_failed=$((cases_failed + cf))
  # ctest ends with "NN% tests passed, F tests failed out of T"; tests that exited with their
  # SKIP_RETURN_CODE are listed as "(Skipped)" and counted neither passed nor failed here.
  summary=$(sed -n 's/^[0-9]*% tests passed, \([0-9]*\) tests* failed out of \([0-9]*\)$/\1 \2/p' "${log}")
  if [ -z "${summary}" ]; then
    echo "run-tests: preset ${preset}: ctest printed no summary (exit ${ctest_status})"
    status=1
    continue
  fi
  read -r f t <<<"${summary}"
  s=$(grep -c '(Skipped)$' "${log}" || true)
  failed=$((failed + f))
  skipped=$((skipped + s))
  passed=$((passed + t - f - s))
  if [ "${ctest_status}" -ne 0 ]; then status=1; fi
done
if [ "${failed}" -ne 0 ]; then status=1; fi
echo "== total over the presets stm32f4, linux-sbc, host =="
if [ "${skipped}" -ne 0 ]; then
  echo "${skipped} skipped (a package the test fetches could not be downloaded)"
fi
echo "ctest entries: ${passed} passed, ${failed} failed"
if [ "${cases_failed}" -ne 0 ]; then status=1; fi
echo "${cases_passed} passed, ${cases_failed} failed"
exit ${status}
