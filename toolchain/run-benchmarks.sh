#!/usr/bin/env bash
# The statistical studies (ctest label `benchmark`): how close auto comes to the true geometry,
# whether the procedures compose, whether the stated precision covers the error left. They run
# sessions by the hundred (about half an hour on two cores), so CI leaves them out and runs their
# two-robot smoke tests instead (label `smoke`). Run this after a change that can move a figure;
# host_sim/tools/make-results.sh regenerates docs/results.md from the same scripts.
# Usage: toolchain/run-benchmarks.sh [ctest options, e.g. -R coverage]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset host
cmake --build --preset host -j "$(nproc)"
ctest --preset benchmark -j "$(nproc)" "$@"
