#!/usr/bin/env bash
# Regenerates docs/performance.md from fresh measurements: the host benchmarks (odocal-bench),
# the STM32F4 image sizes and budgets (the build and the map file), the control tick in QEMU
# during a UMBmark square (the QEMU console test), and the machine and its load.
#
#   tests/bench/make-performance.sh            # writes docs/performance.md
#   tests/bench/make-performance.sh --stdout   # prints the page instead
#
# Needs the host and stm32f4 presets configured (cmake --preset host; cmake --preset stm32f4).
# It builds only odocal-bench and the two images. Takes about 2-4 minutes on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=docs/performance.md
[[ "${1:-}" == "--stdout" ]] && out=/dev/stdout
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
cmake --build --preset host --target odocal-bench -j2 >"$work/host-build.log"
cmake --build --preset stm32f4 -j2 >"$work/fw-build.log"
grep -E -- "-- odocal-fw(-qemu)?\.elf:" "$work/fw-build.log" >"$work/budgets.txt" || true
if [[ ! -s "$work/budgets.txt" ]]; then
  # Nothing relinked: run the same check the build runs.
  for image in odocal-fw odocal-fw-qemu; do
    ctest --preset stm32f4 -R "^${image}_image_checks$" -V 2>/dev/null |
      grep -E -o "odocal-fw(-qemu)?\.elf: flash.*" >>"$work/budgets.txt" || true
  done
fi
for image in odocal-fw odocal-fw-qemu; do
  python3 firmware/stm32f4/tools/image_report.py --elf "build/stm32f4/bin/$image.elf" \
    --map "build/stm32f4/bin/$image.map" --objdump arm-none-eabi-objdump >"$work/$image.report"
done
python3 firmware/stm32f4/tools/qemu_console_test.py --qemu qemu-system-arm \
  --elf build/stm32f4/bin/odocal-fw-qemu.elf >"$work/qemu.log" 2>&1 || true
build/host/bin/odocal-bench --benchmark_format=json >"$work/bench.json" 2>/dev/null
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$work" "$load_before" "$load_after" >"$out" <<'EOF'
import datetime, json, os, re, subprocess, sys
work, load_before, load_after = sys.argv[1:4]
cpu = "unknown CPU"
for line in open("/proc/cpuinfo"):
    if line.startswith("model name"):
        cpu = line.split(":", 1)[1].strip()
        break
cores = os.cpu_count()
# Names carry suffixes such as "/iterations:2/real_time": key by the benchmark's own name.
bench = {b["name"].split("/")[0]: b for b in json.load(open(f"{work}/bench.json"))["benchmarks"]}

def t(name, unit=None):
    b = bench.get(name)
    if b is None:
        return "not run"
    return f"{b['cpu_time']:.3g} {b['time_unit']}"

def counter(name, key):
    b = bench.get(name)
    return b.get(key) if b else None

qemu = open(f"{work}/qemu.log").read()
tick = re.search(r"measured: control tick max (\d+) instructions \(avg (\d+)\)", qemu)
tick_max, tick_avg = (tick.group(1), tick.group(2)) if tick else ("not measured", "not measured")
qemu_fails = [l for l in qemu.splitlines() if l.startswith("FAIL")]
budgets = open(f"{work}/budgets.txt").read().strip().splitlines()

def component_table(image):
    rows, stack = [], []
    text = open(f"{work}/{image}.report").read()
    section = None
    for line in text.splitlines():
        if line.startswith(" flash B"):
            section = "size"
            continue
        if line.startswith("worst-case stack"):
            section = "stack"
            continue
        if line.startswith("instructions per function"):
            section = "edge"
            continue
        if section == "size":
            m = re.match(r"\s*(\d+)\s+(\d+)\s+(.*)", line)
            if m:
                rows.append(f"| {m.group(3)} | {int(m.group(1)):,} | {int(m.group(2)):,} |")
        elif section == "stack":
            m = re.match(r"\s*(\d+) B\s+([^:]*)", line)
            if m:
                stack.append(f"| {m.group(2).strip()} | {int(m.group(1)):,} |")
    return rows, stack

def edge_counts(image):
    """(instructions of the edge handler: the decoder, or with LTO the firmware's edge callback
    the decoder is inlined into; of the whole edge path)."""
    total, decoder, handler = 0, 0, 0
    section = False
    for line in open(f"{work}/{image}.report"):
        if line.startswith("instructions per function"):
            section = True
            continue
        m = re.match(r"\s*(\d+)\s+(\S.*)", line)
        if section and m:
            total += int(m.group(1))
            if "QuadratureDecoder::on_edge" in m.group(2):
                decoder = int(m.group(1))
            if "on_encoder_edge" in m.group(2):
                handler = int(m.group(1))
    return (decoder, "`QuadratureDecoder::on_edge`", "≤ 30 instructions") if decoder else (
        handler, "`on_encoder_edge` with `QuadratureDecoder::on_edge` inlined into it by LTO",
        "≤ 30 for the decoder; decoder and callback were 24 + 21 = 45 before LTO"), total

robot_rows, robot_stack = component_table("odocal-fw")
qemu_rows, qemu_stack = component_table("odocal-fw-qemu")
ratio = counter("BM_SimUmbmarkRealTimeRatio", "realtime_x")
robots_per_s = counter("BM_MonteCarloPerRobot", "robots_per_s")
now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                        text=True).stdout.strip()

p = print
p("# Performance, size and stack")
p()
p("<!-- Generated by tests/bench/make-performance.sh: do not edit by hand, re-run the script. -->")
p()
p(f"Measured {now} at commit `{commit}` on {cores} x {cpu}; load average "
  f"{load_before} before and {load_after} after the run (the machine is shared with other "
  "builds: host-time figures vary by tens of percent with load, QEMU instruction counts do "
  "not). Regenerate with `tests/bench/make-performance.sh` (about 3 minutes).")
p()
p("## Drive stack on the host (`build/host/bin/odocal-bench`)")
p()
p("| benchmark | what | CPU time |")
p("| --- | --- | --- |")
p(f"| `BM_EdgeHandler` | `QuadratureDecoder::on_edge` | {t('BM_EdgeHandler')} |")
p(f"| `BM_ControlTickOnAPath` | one `ControlLoop::tick` on the UMBmark square | "
  f"{t('BM_ControlTickOnAPath')} |")
p(f"| `BM_OdometryUpdate` | one exact-arc update | {t('BM_OdometryUpdate')} |")
p(f"| `BM_InverseKinematics` | eq. 7, 2x2 map | {t('BM_InverseKinematics')} |")
p()
p("## Drive stack on the Cortex-M4 (QEMU image, `-icount shift=0`: 1 instruction = 1 ns)")
p()
p("| target | budget | measured |")
p("| --- | --- | --- |")
p(f"| control tick during a UMBmark square, worst / average | 1,500 instructions (the QEMU "
  f"test fails above it) | **{tick_max}** / {tick_avg} |")
(decoder, decoder_name, edge_budget), edge_total = edge_counts("odocal-fw")
p(f"| encoder edge ({decoder_name}, straight-line count, robot image, `image_report.py`) "
  f"| {edge_budget} | **{decoder}**; the whole EXTI path (dispatch, EXTI service, clock "
  f"read, decoder) {edge_total} |")
if qemu_fails:
    p()
    p("QEMU console test checks that failed in this run (the tick-rate check compares QEMU's "
      "virtual clock with the host's and fails when the host is overloaded):")
    p()
    for f in qemu_fails:
        p(f"- `{f}`")
p()
p("## Calibration engine (`odocal-bench`, host)")
p()
p("| benchmark | target | CPU time |")
p("| --- | --- | --- |")
p(f"| bootstrap, B = 10,000, 20 training rows, 20 unknowns | ≤ 100 ms | "
  f"{t('BM_Bootstrap_B10000_m20_u20')} |")
p(f"| the same with the plain reference implementation (tests/support/bootstrap_reference.hpp: "
  f"heap vectors, a QR refit per replicate, sorting; same draws, results equal to rounding, "
  f"tested) | for comparison | {t('BM_BootstrapReference_B10000_m20_u20')} |")
p(f"| UMBmark, small-angle formulas | ≤ 10 µs | {t('BM_UmbmarkSolve_Approx')} |")
p(f"| UMBmark, exact Gauss–Newton solve | ≤ 10 µs | {t('BM_UmbmarkSolve_Exact')} |")
p()
p("## Simulation (`odocal-bench`, host, one thread unless said)")
p()
p("| benchmark | goal | measured |")
p("| --- | --- | --- |")
p(f"| `odocal sim umbmark` real-time ratio (`BM_SimUmbmarkRealTimeRatio`) | 20,000x "
  f"| **{ratio:,.0f}x** |" if ratio else "| sim real-time ratio | 20,000x | not run |")
if robots_per_s:
    p(f"| `odocal sim montecarlo --robots 1000` on 2 threads (`BM_MonteCarloPerRobot`: 20 "
      f"robots, 1.5 m square, 500 Hz) | < 60 s | {robots_per_s:.1f} robots/s, i.e. "
      f"{1000.0 / robots_per_s:.0f} s per 1,000 |")
p()
p("## STM32F4 images (`cmake --build --preset stm32f4` prints these; over a budget fails it)")
p()
p("Budgets are the CMake cache variables `ODOCAL_FW_FLASH_BUDGET`, `ODOCAL_FW_RAM_BUDGET` "
  "(static RAM plus the reserved stack) and their `ODOCAL_FW_QEMU_*` twins "
  "(firmware/stm32f4/CMakeLists.txt). Goals for the robot image: flash ≤ 32 KiB, RAM ≤ 8 KiB; "
  "the budgets are set at what the image reaches, so any growth fails the build.")
p()
for line in budgets:
    p(f"- `{line.strip()}`")
p()
p("Both images are linked with link-time optimisation, so code is attributed to the component "
  "of the function it ended up in (the control tick, for instance, is inlined into the "
  "firmware's tick handler and counts for firmware/stm32f4).")
p()
p("Robot image `odocal-fw.elf` by component (from the linker map):")
p()
p("| component | flash B | static RAM B |")
p("| --- | --- | --- |")
for r in robot_rows:
    p(r)
p()
p("QEMU image `odocal-fw-qemu.elf` (the same plus the simulated plant, double precision):")
p()
p("| component | flash B | static RAM B |")
p("| --- | --- | --- |")
for r in qemu_rows:
    p(r)
p()
p("## Worst-case stack (`-fstack-usage` frames along the static call graph, `image_report.py`)")
p()
p("Frames from each function's prologue in the linked image; the call graph follows direct "
  "calls, the console's command table (every `Console::cmd_*` handler) and each HAL "
  "interface's virtual. The reserve is 4 KiB for the robot and 6 KiB for the QEMU image "
  "(firmware/stm32f4/stm32f405.ld); `ctest --preset stm32f4` fails when the nested worst case "
  "outgrows it.")
p()
p("| context (robot image) | bytes |")
p("| --- | --- |")
for r in robot_stack:
    p(r)
p()
p("| context (QEMU image) | bytes |")
p("| --- | --- |")
for r in qemu_stack:
    p(r)
p()
p("## Not regenerated by the script")
p()
p("- Linux board (`tests/linux/run-vm-test.sh`, a QEMU x86_64 guest): see docs/linux.md.")
p("- Parameter store wear (docs/parameters.md): one 256-byte slot per `save`, a 16 KiB sector "
  "erase per 64 saves, about 2.4 years at one save a minute on 10,000-cycle flash.")
EOF
