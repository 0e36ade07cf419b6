#!/usr/bin/env python3
"""The docs' figures about the STM32F4 images, from the build: each figure the docs quote sits in
a block between `<!-- figures:begin NAME -->` and `<!-- figures:end -->` in README.md or
docs/*.md, and this script writes (--write) or checks (the default) every such block.

  python3 firmware/stm32f4/tools/doc_figures.py [--build-dir build/stm32f4] [--write] [DOC...]
  python3 firmware/stm32f4/tools/doc_figures.py --self-test   # the check itself

Sources, all in the stm32f4 build directory: the budgets are its CMake cache variables
(ODOCAL_FW_*); flash and RAM are what check_image.cmake (the build's own size check) prints;
the edge path's instruction count and the stack figures come from image_report.py; the control
tick's from the last QEMU console test (figures/qemu_tick.json, written by
qemu_console_test.py --figures-out for the same image, checked by its hash).
The check is exact except for the control tick, which QEMU measures differently from run to run
(which ticks run while the plant moves depends on the host's timing): the doc's maximum must be
within TICK_MAX_TOLERANCE of the measured one and its average within TICK_AVG_TOLERANCE
(--write keeps the doc's tick figures while they are, so a regeneration does not churn them).
Exit status 1 when a block differs (with a diff and the command that regenerates it).
"""

import argparse
import difflib
import hashlib
import json
import os
import pathlib
import re
import subprocess
import sys

# Relative. Six runs on a 2-core host at load 5-10 gave max 929-940, average 766-787; the
# figures docs/stm32f4.md had before (same code, load unknown) were 940 and 741. Under load 12-14
# the same image gave max 935-1024 (a USART interrupt landing inside the longest tick: its byte
# arrives in real time, so the maximum depends on the host): 12 % holds those.
TICK_MAX_TOLERANCE = 0.12
TICK_AVG_TOLERANCE = 0.10
ROOT = pathlib.Path(__file__).resolve().parents[3]
TOOLS = pathlib.Path(__file__).resolve().parent
BLOCK = re.compile(r"(<!-- figures:begin (\S+) -->\n)(.*?)(<!-- figures:end -->)", re.S)
TICK = re.compile(r"([\d,]+) instructions max, ([\d,]+) average")
REGENERATE = "python3 firmware/stm32f4/tools/doc_figures.py --write"


def n(value):
    return f"{value:,}"


def sha256(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


class Build:
    """Measures lazily: a doc without a tick block needs no QEMU run."""

    def __init__(self, build_dir):
        self.dir = pathlib.Path(build_dir)
        cache = (self.dir / "CMakeCache.txt").read_text()
        self.cache = dict(re.findall(r"^(\w+):\w+=(.*)$", cache, re.M))
        self.bin = self.dir / "bin"
        self._reports = {}

    def budget(self, name):
        return int(self.cache[name])

    def sizes(self, image):
        """flash, static RAM, reserved stack: check_image.cmake's own figures."""
        c = self.cache
        prefix = image.upper().replace("-", "_") + "_"  # odocal-fw-qemu: ODOCAL_FW_QEMU_
        out = subprocess.run(
            [c["CMAKE_COMMAND"], f"-DELF={self.bin / image}.elf", f"-DNM={c['CMAKE_NM']}",
             f"-DSIZE={c['ODOCAL_ARM_SIZE']}", f"-DFLASH_BUDGET={c[prefix + 'FLASH_BUDGET']}",
             f"-DRAM_BUDGET={c[prefix + 'RAM_BUDGET']}",
             "-P", str(TOOLS.parent / "check_image.cmake")],
            capture_output=True, text=True)
        out = out.stdout + out.stderr
        m = re.search(r"flash (\d+) B .*RAM \d+ B \(static (\d+) \+ stack (\d+)\)", out)
        if not m:
            sys.exit(f"doc_figures: no size line from check_image.cmake for {image}:\n{out}")
        return tuple(int(g) for g in m.groups())

    def report(self, image):
        if image not in self._reports:
            self._reports[image] = subprocess.run(
                [sys.executable, str(TOOLS / "image_report.py"), "--elf", f"{self.bin / image}.elf",
                 "--map", f"{self.bin / image}.map", "--objdump", self.cache["CMAKE_OBJDUMP"]],
                capture_output=True, text=True, env={**os.environ, "PYTHONHASHSEED": "0"}
            ).stdout  # a fixed hash seed: the same deepest path among equal ones every run
        return self._reports[image]

    def edge(self):
        """(executed on the longest way, instructions in all, calls), worst EXTI vector."""
        found = re.findall(r"(\d+) executed, (\d+) in all, (\d+) calls", self.report("odocal-fw"))
        return max(tuple(int(x) for x in f) for f in found)

    def stack(self, image):
        """[(context, bytes, deepest path)] and the nested worst case."""
        rows = re.findall(r"^\s*(\d+) B  (.+): (\S.*)$", self.report(image), re.M)
        nested = re.search(r"^\s*(\d+) B  all nested", self.report(image), re.M)
        return [(label, int(b), path) for b, label, path in rows], int(nested.group(1))

    def components(self, image):
        return [(int(f), int(r), name) for f, r, name in
                re.findall(r"^\s*(\d+)\s+(\d+)  (.+)$", self.report(image), re.M)
                if not name.startswith("total")]

    def tick(self):
        path = self.dir / "figures" / "qemu_tick.json"
        if not path.exists():
            sys.exit(f"doc_figures: no {path}: run `ctest --preset stm32f4 -R "
                     "odocal_fw_qemu_console` first")
        tick = json.loads(path.read_text())
        if tick["elf_sha256"] != sha256(self.bin / "odocal-fw-qemu.elf"):
            sys.exit(f"doc_figures: {path} is from another odocal-fw-qemu.elf: run `ctest "
                     "--preset stm32f4 -R odocal_fw_qemu_console` again")
        return tick["tick_max"], tick["tick_avg"]


def images_table(build, tick):
    flash, static, stack = build.sizes("odocal-fw")
    qflash, qstatic, qstack = build.sizes("odocal-fw-qemu")
    mflash, mstatic, mstack = build.sizes("odocal-fw-qemu-mouse")
    wflash, wstatic, wstack = build.sizes("odocal-fw-mouse")
    budget_flash, budget_ram = build.budget("ODOCAL_FW_FLASH_BUDGET"), build.budget(
        "ODOCAL_FW_RAM_BUDGET")
    edge_run, edge_all, edge_calls = build.edge()
    tick_max, tick_avg = tick
    return f"""\
| | robot `odocal-fw` | budget (goal) | mouse `odocal-fw-mouse` (budget) | QEMU `odocal-fw-qemu` (budget) | QEMU mouse twin `odocal-fw-qemu-mouse` (budget) |
| --- | --- | --- | --- | --- | --- |
| flash (vectors + code + constants + .data image) | {n(flash)} B ({flash / 1024:.1f} KiB), {n(budget_flash - flash)} B to spare | {n(budget_flash)} B ({budget_flash / 1024:g} KiB) | {n(wflash)} B ({n(build.budget("ODOCAL_FW_MOUSE_FLASH_BUDGET"))} B) | {n(qflash)} B ({n(build.budget("ODOCAL_FW_QEMU_FLASH_BUDGET"))} B) | {n(mflash)} B ({n(build.budget("ODOCAL_FW_QEMU_MOUSE_FLASH_BUDGET"))} B) |
| RAM: static (.data + .bss) + reserved main stack | {n(static)} + {n(stack)} = {n(static + stack)} B, {n(budget_ram - static - stack)} B to spare | {n(budget_ram)} B ({budget_ram / 1024:g} KiB) | {n(wstatic)} + {n(wstack)} = {n(wstatic + wstack)} B ({n(build.budget("ODOCAL_FW_MOUSE_RAM_BUDGET"))} B) | {n(qstatic)} + {n(qstack)} = {n(qstatic + qstack)} B ({n(build.budget("ODOCAL_FW_QEMU_RAM_BUDGET"))} B) | {n(mstatic)} + {n(mstack)} = {n(mstatic + mstack)} B ({n(build.budget("ODOCAL_FW_QEMU_MOUSE_RAM_BUDGET"))} B) |
| control tick, QEMU, the console test's script (a UMBmark square, an arc with `wheelbase_arc_mm` set, the self-test); max ±{TICK_MAX_TOLERANCE * 100:g} %, average ±{TICK_AVG_TOLERANCE * 100:g} % from run to run | {n(tick_max)} instructions max, {n(tick_avg)} average | {n(build.budget("ODOCAL_FW_TICK_BUDGET"))} (the QEMU test fails above it) | the robot's loop | (measured in QEMU) | (not measured) |
| encoder edge: the whole path from the EXTI vector (pending clear, pin sample, TIM5 stamp, decoder inlined), longest way through | {edge_run} instructions ({edge_all} in all), {edge_calls or "no"} call{"s" if edge_calls != 1 else ""} | {build.budget("ODOCAL_FW_EDGE_MAX")} (the report test fails above it, or on a call) | the robot's path, under the same limit | plant instead | plant instead |
| double arithmetic, 64-bit division | none (the build fails if linked) | none | none (as the robot) | the plant is double | the plant and the wall sensors are double |
"""


def stack_table(build, _tick):
    robot, robot_nested = build.stack("odocal-fw")
    qemu, qemu_nested = build.stack("odocal-fw-qemu")
    robot_bytes = {label: b for label, b, _ in robot}
    qemu_bytes = {label: b for label, b, _ in qemu}
    lines = ["| context | robot B | QEMU B | deepest path (robot; QEMU where only QEMU has it) |",
             "| --- | --- | --- | --- |"]
    for label, _, path in robot + [r for r in qemu if r[0] not in robot_bytes]:
        lines.append(f"| {label} | {n(robot_bytes[label]) if label in robot_bytes else '—'} | "
                     f"{n(qemu_bytes[label]) if label in qemu_bytes else '—'} | `{path}` |")
    lines.append(f"| all nested (+104 B FP exception frame per level) | {n(robot_nested)} of "
                 f"{n(build.budget('ODOCAL_FW_STACK_BYTES'))} | {n(qemu_nested)} of "
                 f"{n(build.budget('ODOCAL_FW_QEMU_STACK_BYTES'))} | the report test fails "
                 "above the reserve |")
    return "\n".join(lines) + "\n"


def components_table(image):
    def render(build, _tick):
        rows = sorted(build.components(image), reverse=True)
        return ("| component | flash B | static RAM B |\n| --- | --- | --- |\n" +
                "".join(f"| {name} | {n(f)} | {n(r)} |\n" for f, r, name in rows if f or r))
    return render


BLOCKS = {
    "images": images_table,
    "stack": stack_table,
    "components-robot": components_table("odocal-fw"),
    "components-qemu": components_table("odocal-fw-qemu"),
}
TICK_BLOCKS = {"images"}  # the blocks that quote the control tick


def expected(name, old, build, where):
    """The block `name` as the build has it; the doc's tick figures (in `old`) are kept when they
    are within the tolerance, so that only they may differ from the measurement."""
    tick = None
    if name in TICK_BLOCKS:
        tick = build.tick()
        found = TICK.search(old)
        if found:
            doc_max, doc_avg = (int(g.replace(",", "")) for g in found.groups())
            ok = (abs(doc_max - tick[0]) <= TICK_MAX_TOLERANCE * tick[0] and
                  abs(doc_avg - tick[1]) <= TICK_AVG_TOLERANCE * tick[1])
            print(f"{where}: tick {doc_max}/{doc_avg} in the doc, measured {tick[0]}/{tick[1]}: "
                  + ("within" if ok else "OUTSIDE") + " the tolerance")
            if ok:
                tick = (doc_max, doc_avg)
    return BLOCKS[name](build, tick)


def self_test(build):
    """The check itself: a fresh block passes, a changed figure fails, the tick's tolerance holds."""
    failures = 0

    def case(what, doc_block, name, should_match):
        nonlocal failures
        matches = expected(name, doc_block, build, f"self-test {what}") == doc_block
        print(("PASS " if matches == should_match else "FAIL ") + what)
        failures += matches != should_match

    for name in BLOCKS:
        fresh = expected(name, "", build, name)
        case(f"[{name}] as generated matches", fresh, name, True)
        first = re.search(r"\d", fresh.split("\n", 2)[2])  # a figure in the first table row
        offset = len("\n".join(fresh.split("\n", 2)[:2])) + 1 + first.start()
        changed = fresh[:offset] + str((int(fresh[offset]) + 1) % 10) + fresh[offset + 1:]
        case(f"[{name}] with a figure changed fails", changed, name, False)
    fresh = expected("images", "", build, "images")
    tick_max, tick_avg = build.tick()
    inside, outside = 0.8, 1.2  # of the tolerance
    for factor, should_match in ((1 + inside * TICK_MAX_TOLERANCE, True),
                                 (1 - inside * TICK_MAX_TOLERANCE, True),
                                 (1 + outside * TICK_MAX_TOLERANCE, False),
                                 (1 - outside * TICK_MAX_TOLERANCE, False)):
        moved = TICK.sub(f"{n(round(tick_max * factor))} instructions max, {n(tick_avg)} average",
                         fresh)
        case(f"[images] tick max x{factor:.3f} " + ("passes" if should_match else "fails"), moved,
             "images", should_match)
    for factor, should_match in ((1 + inside * TICK_AVG_TOLERANCE, True),
                                 (1 - inside * TICK_AVG_TOLERANCE, True),
                                 (1 + outside * TICK_AVG_TOLERANCE, False),
                                 (1 - outside * TICK_AVG_TOLERANCE, False)):
        moved = TICK.sub(f"{n(tick_max)} instructions max, {n(round(tick_avg * factor))} average",
                         fresh)
        case(f"[images] tick average x{factor:.3f} " + ("passes" if should_match else "fails"), moved,
             "images", should_match)
    print(f"{failures} failure(s)")
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", default=str(ROOT / "build" / "stm32f4"))
    parser.add_argument("--write", action="store_true", help="rewrite the blocks")
    parser.add_argument("--self-test", action="store_true", help="test the check itself")
    parser.add_argument("docs", nargs="*", help="default: README.md and docs/*.md")
    args = parser.parse_args()
    build = Build(args.build_dir)
    if args.self_test:
        return self_test(build)
    docs = [pathlib.Path(d) for d in args.docs] or [ROOT / "README.md",
                                                    *sorted((ROOT / "docs").glob("*.md"))]
    stale = 0
    for doc in docs:
        text = doc.read_text()
        out, last = [], 0
        for m in BLOCK.finditer(text):
            name, old = m.group(2), m.group(3)
            if name not in BLOCKS:
                sys.exit(f"doc_figures: {doc.name}: unknown block {name} (known: {list(BLOCKS)})")
            new = expected(name, old, build, f"{doc.name} [{name}]")
            if new == old:
                print(f"{doc.name} [{name}]: matches the build")
            elif args.write:
                print(f"{doc.name} [{name}]: rewritten")
            else:
                stale += 1
                print(f"{doc.name} [{name}]: differs from the build:")
                sys.stdout.writelines(difflib.unified_diff(
                    old.splitlines(True), new.splitlines(True), "doc", "build"))
            out += [text[last:m.start(3)], new]
            last = m.end(3)
        out.append(text[last:])
        if args.write and last:
            doc.write_text("".join(out))
    if stale:
        print(f"{stale} block(s) stale: regenerate with `{REGENERATE}` "
              "(after `ctest --preset stm32f4 -R odocal_fw_qemu_console`)")
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
