#!/bin/bash
# Builds the host simulator with profile-guided optimisation in build/host (docs/simulation.md
# "Speed"): an instrumented build of odocal, a training run of the simulated procedures, then
# the optimised build of odocal, odocal-sim and odocal-bench with that profile. The results of
# every procedure stay bit-identical; only the speed changes. Usage: host_sim/tools/pgo-build.sh
# [-jN]. Undo with: cmake --preset host -DODOCAL_SIM_PGO= && cmake --build --preset host
set -euo pipefail
cd "$(dirname "$0")/../.."
jobs=${1:--j2}
bin=build/host/bin
profile=$PWD/build/host/sim-pgo
cmake --preset host -DODOCAL_SIM_PGO=generate -DODOCAL_SIM_PGO_DIR="$profile" >/dev/null
cmake --build --preset host --target odocal "$jobs"
rm -rf "$profile"
# Training: the procedures' hot path (tick, plant, edges, faults, bumps), a few seconds.
"$bin/odocal" sim umbmark --seed 3 --json >/dev/null
robot=$(mktemp --suffix=.json)
trap 'rm -f "$robot"' EXIT
echo '{"slip_sigma": 0.002, "bump_height_mm": 5, "measure_sigma_mm": 1}' >"$robot"
"$bin/odocal" sim umbmark --seed 4 --side-mm 1500 --json --robot "$robot" >/dev/null
"$bin/odocal" sim validate --seed 2 --trials 6 --runs 1 --replicates 100 --json >/dev/null
"$bin/odocal" sim montecarlo --seed 2 --robots 4 --threads 1 --json >/dev/null
cmake --preset host -DODOCAL_SIM_PGO=use -DODOCAL_SIM_PGO_DIR="$profile" >/dev/null
cmake --build --preset host --target odocal odocal-sim odocal-bench "$jobs"
echo "pgo-build: odocal, odocal-sim and odocal-bench built with the profile in $profile"
