#!/usr/bin/env python3
"""What an odocal firmware image costs: flash and RAM by component, worst-case stack per
interrupt and for the main loop, and the instruction counts of the edge interrupt.

Sizes come from the linker map (every input section is attributed to its object or library; the
images are linked with LTO, so code from the link-time objects is attributed by the namespace of
the function it ended up in: code inlined into a caller counts for the caller's component).
Stack frames come from each function's prologue in the linked image (push / vpush / sub sp) --
the same figure -fstack-usage reports for our own functions, and it also covers libgcc/libm/libc.
The call graph comes from bl / b.w; indirect calls are resolved by a table below (virtual HAL
calls -> every `do_*` override; function-pointer handlers -> the handlers the image installs).
The console's command table (pointers to member functions) is resolved to every `Console::cmd_*`
handler. Exit status 1 when the worst case exceeds the reserved stack.
"""

import argparse
import re
import subprocess
import sys
from collections import defaultdict

COMPONENTS = [
    (r"libodocal_console\.a", "core/console (console, text, line editor)"),
    (r"libodocal_params\.a", "core/params (table, A/B store, CRC)"),
    (r"libodocal_calib\.a", "core/calib (UMBmark solver)"),
    (r"libodocal_drive\.a", "core/drive (control loop, odometry, paths)"),
    (r"libodocal_hal_stm32f4\.a", "hal/stm32f4 (register-level backends)"),
    (r"libodocal_hal_sim\.a", "hal/sim (plant, RAM store: QEMU only)"),
    (r"odocal_fw_app\.dir|odocal-fw(-qemu)?\.dir", "firmware/stm32f4 (startup, boards, main)"),
    (r"libm\.a|libm_nano\.a", "libm (QEMU only: the plant's double sin/cos/exp)"),
    (r"libgcc\.a", "libgcc (QEMU: soft double for the plant)"),
    (r"libc_nano\.a|libc\.a|libg_nano\.a", "libc (QEMU only: errno for libm)"),
    (r"libstdc\+\+|libsupc\+\+", "libstdc++"),
]

# Indirect call resolution: function (demangled, prefix match) -> targets (regex on demangled).
HANDLER_TARGETS = {
    "dispatch_interrupt": r"on_interrupt|on_plant_timer|on_tick\(",
    "odocal::hal::stm32f4::SysTickTimer::on_interrupt": r"on_tick\(",
    "odocal::sim::EncoderLine::drive": r"EncoderWiring::on_edge",
    "odocal::sim::Plant": r"EncoderWiring::on_edge",
}
VIRTUAL_TARGETS = r"::do_[a-z_0-9]+\(|non-virtual thunk to .*::do_"
# Which HAL virtuals a caller can reach (by the caller's name prefix); others may reach any.
VIRTUAL_BY_CALLER = [
    ("odocal::sim::EncoderWiring", r"do_now_us|do_read\(\)"),
    ("odocal::drive::", r"do_set_duty|do_set\(|do_enter|do_exit"),
    ("odocal::params::", r"do_erase|do_program|do_read\(unsigned|do_sector|do_program_gran"),
    ("odocal::hal::BlockStore", r"do_erase|do_program|do_read\(unsigned|do_sector|do_program_gran"),
    ("odocal::hal::stm32f4::FlashStore", r"do_now_us"),
    ("odocal::console::", r"do_read\(unsigned char|do_write|do_enter|do_exit|do_read_counts|"
                          r"do_set_emitter|do_wait_settle"),
    ("odocal::firmware::SessionStream", r"do_read\(unsigned char|do_write"),
    ("odocal::hal::CriticalGuard", r"do_enter|do_exit"),
]

ROOTS = [
    ("main loop (reset_handler -> main)", r"^reset_handler$", None),
    ("SysTick: control tick", r"^dispatch_interrupt$", r"SysTickTimer::on_interrupt"),
    ("EXTI: encoder edge (robot)", r"^board_exti(01|23)_vector$", None),
    ("TIM2: plant (QEMU)", r"^dispatch_interrupt$", r"on_plant_timer"),
    ("USART: console bytes", r"^dispatch_interrupt$", r"UsartStream::on_interrupt"),
    ("faults", r"^fault_report$", None),
]


def run(*command):
    return subprocess.run(command, check=True, capture_output=True, text=True).stdout


# With link-time optimisation the code comes out of the linker's own objects (ccXXXX.ltrans0.o):
# those input sections are attributed by the (mangled) namespace in their section name instead.
LTO_COMPONENTS = [
    (r"odocal7console", "core/console (console, text, line editor)"),
    (r"odocal6params", "core/params (table, A/B store, CRC)"),
    (r"odocal5calib", "core/calib (UMBmark solver)"),
    (r"odocal5drive", "core/drive (control loop, odometry, paths)"),
    (r"odocal3hal7stm32f4", "hal/stm32f4 (register-level backends)"),
    (r"odocal3sim", "hal/sim (plant, RAM store: QEMU only)"),
    (r"odocal3hal|odocal8firmware|reset_handler|fault_|dispatch_interrupt|vector_table|main$",
     "firmware/stm32f4 (startup, boards, main)"),
    (r"\.rodata(\.str|\.cst|$)", "constants merged across files by LTO (strings, tables)"),
]


def component_of(path, section_name=""):
    if re.search(r"ltrans[0-9]*\.ltrans\.o|\.ltrans\.o", path):
        for pattern, name in LTO_COMPONENTS:
            if re.search(pattern, section_name):
                return name
        return "other (LTO: unattributed)"
    for pattern, name in COMPONENTS:
        if re.search(pattern, path):
            return name
    return "other (linker fill, veneers)"


def sizes_from_map(map_path):
    """(output section, component) -> bytes, from the map's input-section lines."""
    totals = defaultdict(int)
    section = None
    pending_name = None
    keep = {".isr_vector", ".text", ".rodata", ".ARM.exidx", ".init_array", ".data", ".bss"}
    with open(map_path) as f:
        for line in f:
            top = re.match(r"^(\.[A-Za-z_.]+)\s", line)
            if top:
                section = top.group(1) if top.group(1) in keep else None
                continue
            if section is None:
                continue
            m = re.match(r"^ (\S+)\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S+)", line)
            if m is None and pending_name is not None:
                m2 = re.match(r"^\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S+)", line)
                if m2:
                    totals[(section, component_of(m2.group(3), pending_name))] += int(
                        m2.group(2), 16)
                pending_name = None
                continue
            if m:
                totals[(section, component_of(m.group(4), m.group(1)))] += int(m.group(3), 16)
                pending_name = None
                continue
            if re.match(r"^ \.\S+\s*$", line):
                pending_name = line.strip()
            elif re.match(r"^ \*fill\*\s+0x[0-9a-f]+\s+0x([0-9a-f]+)", line):
                fill = re.match(r"^ \*fill\*\s+0x[0-9a-f]+\s+0x([0-9a-f]+)", line)
                totals[(section, "other (linker fill, veneers)")] += int(fill.group(1), 16)
    return totals


def parse_disassembly(objdump, elf):
    text = run(objdump, "-d", "--no-show-raw-insn", elf)
    functions = {}
    current = None
    for line in text.splitlines():
        head = re.match(r"^([0-9a-f]{8}) <(.+)>:$", line)
        if head:
            current = {"name": head.group(2), "insns": [], "addrs": [], "calls": set(),
                       "indirect": False}
            functions[head.group(2)] = current
            continue
        ins = re.match(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$", line)
        if ins and current is not None:
            op, args = ins.group(2), ins.group(3)
            current["insns"].append((op, args))
            current["addrs"].append(int(ins.group(1), 16))
            call = re.match(r"^[0-9a-f]+ <([^+>]+)>", args)
            if op in ("bl", "b.w", "b") and call and call.group(1) != current["name"]:
                if op == "bl" or (op in ("b.w", "b") and call.group(1) in functions or True):
                    # b/b.w to another function's start is a tail call
                    if op == "bl" or "+" not in args.split("<")[1]:
                        current["calls"].add(call.group(1))
            if op == "blx" or (op == "bx" and args.strip() != "lr"):
                current["indirect"] = True
    return functions


CONDITIONAL = re.compile(r"^(b(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le)|cbn?z)$")


def longest_run(function):
    """Instructions executed on the longest way from entry to return, following branches (for
    loop-free interrupt code; literal-pool words are not instructions). A tail call counts as
    its branch only."""
    code = [(a, op, args) for a, (op, args) in zip(function["addrs"], function["insns"])
            if not op.startswith(".")]
    index = {a: i for i, (a, _, _) in enumerate(code)}
    memo = {}

    def walk(i, depth):
        if i >= len(code) or depth > len(code):
            return 0
        if i in memo:
            return memo[i]
        _, op, args = code[i]
        base = op.split(".")[0]
        target = re.match(r"^([0-9a-f]+) <", args)
        inside = index.get(int(target.group(1), 16)) if target else None
        if base == "bx" or (base in ("pop", "ldmia") and "pc" in args):
            n = 1
        elif base == "b":
            n = 1 + (walk(inside, depth + 1) if inside is not None else 0)
        elif CONDITIONAL.match(base):
            n = 1 + max(walk(i + 1, depth + 1),
                        walk(inside, depth + 1) if inside is not None else 0)
        else:
            n = 1 + walk(i + 1, depth + 1)
        memo[i] = n
        return n

    return walk(0, 0)


def frame_bytes(function):
    total = 0
    for op, args in function["insns"][:8]:
        if op in ("push", "push.w", "stmdb"):
            if op == "stmdb" and not args.startswith("sp!"):
                continue
            regs = re.findall(r"\b(r\d+|lr|ip|fp)\b", args.split("{")[-1])
            ranges = re.findall(r"r(\d+)-r(\d+)", args)
            total += 4 * (len(regs) + sum(int(b) - int(a) - 1 for a, b in ranges))
        elif op in ("vpush", "vstmdb"):
            inner = args.split("{")[-1]
            singles = re.findall(r"\bs(\d+)\b", inner)
            doubles = re.findall(r"\bd(\d+)\b", inner)
            s_ranges = re.findall(r"s(\d+)-s(\d+)", inner)
            d_ranges = re.findall(r"d(\d+)-d(\d+)", inner)
            total += 4 * (len(singles) + sum(int(b) - int(a) - 1 for a, b in s_ranges))
            total += 8 * (len(doubles) + sum(int(b) - int(a) - 1 for a, b in d_ranges))
        elif op in ("sub", "sub.w", "subw") and args.startswith("sp,"):
            imm = re.search(r"#(\d+)", args)
            if imm:
                total += int(imm.group(1))
    return total


def demangle(names):
    out = run("c++filt", *names) if names else ""
    return dict(zip(names, out.splitlines()))


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--elf", required=True)
    parser.add_argument("--map", required=True)
    parser.add_argument("--objdump", default="arm-none-eabi-objdump")
    parser.add_argument("--edge-max", type=int, default=0,
                        help="fail when an edge vector runs more instructions than this (robot)")
    args = parser.parse_args()
    headers = run(args.objdump, "-h", args.elf)
    stack = re.search(r"\.stack\s+([0-9a-f]+)", headers)
    args.stack_reserved = int(stack.group(1), 16) if stack else 0

    print(f"== {args.elf.split('/')[-1]} ==")
    totals = sizes_from_map(args.map)
    flash_sections = {".isr_vector", ".text", ".rodata", ".ARM.exidx", ".init_array", ".data"}
    components = sorted({c for (_, c) in totals})
    rows = []
    for c in components:
        flash = sum(v for (s, cc), v in totals.items() if cc == c and s in flash_sections)
        ram = sum(v for (s, cc), v in totals.items() if cc == c and s in (".data", ".bss"))
        rows.append((flash, ram, c))
    print(f"{'flash B':>8} {'RAM B':>7}  component")
    for flash, ram, c in sorted(rows, reverse=True):
        if flash or ram:
            print(f"{flash:8d} {ram:7d}  {c}")
    print(f"{sum(r[0] for r in rows):8d} {sum(r[1] for r in rows):7d}  total (stack not included)")

    functions = parse_disassembly(args.objdump, args.elf)
    names = demangle(list(functions))
    by_demangled = {names[n]: n for n in functions}
    virtual = [n for n in functions if re.search(VIRTUAL_TARGETS, names[n])]

    def indirect_targets(name):
        d = names[name]
        for prefix, pattern in HANDLER_TARGETS.items():
            if d.startswith(prefix):
                return [n for n in functions if re.search(pattern, names[n])]
        # The console's stream and critical-section virtuals, and (`walls`, where an image
        # links the reading) the wall sensors'.
        streams = [n for n in virtual
                   if re.search(r"do_read\(unsigned char|do_write|do_enter|do_exit|"
                                r"do_read_counts|do_set_emitter|do_wait_settle", names[n])]
        if d.startswith("odocal::console::Console::cmd_"):
            return streams  # a handler writes replies; it dispatches nothing
        if (d.startswith("odocal::console::Console::") or
                d.startswith("odocal::firmware::(anonymous namespace)::run")):
            # The console dispatches through its command table (pointers to member functions;
            # with LTO the dispatch may be inlined into the main loop): any handler, and the
            # stream virtuals.
            return [n for n in functions if re.search(r"Console::cmd_", names[n])] + streams
        wrapper = re.match(r"odocal::hal::\w+::(\w+)\(", d)
        if wrapper and not wrapper.group(1).startswith("do_"):
            # A HAL interface's public method calls its own virtual: X::foo -> *::do_foo.
            return [n for n in virtual if re.search(rf"::do_{wrapper.group(1)}\(", names[n])]
        for prefix, pattern in VIRTUAL_BY_CALLER:
            if d.startswith(prefix):
                return [n for n in virtual if re.search(pattern, names[n])]
        return virtual

    memo = {}

    def worst(name, stack=()):
        if name in stack:
            return 0, [names[name] + " (recursion)"]
        if name in memo:
            return memo[name]
        f = functions.get(name)
        if f is None:
            return 0, []
        callees = set(f["calls"])
        if f["indirect"]:
            callees |= set(indirect_targets(name))
        best, path = 0, []
        for c in callees:
            depth, sub = worst(c, stack + (name,))
            if depth > best:
                best, path = depth, sub
        result = (frame_bytes(f) + best, [names[name]] + path)
        memo[name] = result
        return result

    print()
    print("worst-case stack (frames from prologues; exception entry adds 32 B, 104 B with FP)")
    levels = {}
    for label, root_pattern, via in ROOTS:
        roots = [n for n in functions if re.search(root_pattern, names[n])]
        if not roots:
            continue
        root = roots[0]
        if via:
            targets = [n for n in functions if re.search(via, names[n])]
            if not targets:
                continue
            depth_via, path_via = max((worst(t) for t in targets), key=lambda r: r[0])
            depth = frame_bytes(functions[root]) + depth_via
            path = [names[root]] + path_via
        else:
            depth, path = worst(root)
        levels[label] = depth
        chain = " > ".join(re.sub(r"\(.*", "", p.replace("(anonymous namespace)::", ""))
                           .replace("odocal::", "") for p in path)
        print(f"{depth:6d} B  {label}: {chain}")

    # Nesting: main loop, then console < tick < edges, each preempting with an FP frame.
    nested = levels.get("main loop (reset_handler -> main)", 0)
    for label in ("USART: console bytes", "SysTick: control tick"):
        nested += levels.get(label, 0) + 104
    nested += max(levels.get("EXTI: encoder edge (robot)", 0),
                  levels.get("TIM2: plant (QEMU)", 0)) + 104
    print(f"{nested:6d} B  all nested (main + console + tick + edge ISRs, FP frames), "
          f"reserved {args.stack_reserved} B")

    print()
    edge_over = False
    print("edge path: instructions of each EXTI vector the board serves itself (whole path: "
          "pending clear, pin sample, time stamp, decoder; executed = longest way through)")
    for n in functions:
        if re.search(r"^board_exti(01|23)_vector$", names[n]):
            code = [op for op, _ in functions[n]["insns"] if not op.startswith(".")]
            calls = len(functions[n]["calls"])
            executed = longest_run(functions[n])
            print(f"{executed:6d} executed, {len(code)} in all, {calls} calls  {names[n]}")
            if args.edge_max and (executed > args.edge_max or calls):
                print(f"edge path over its budget of {args.edge_max} instructions (or calls out)")
                edge_over = True
    return 1 if nested > args.stack_reserved or edge_over else 0


if __name__ == "__main__":
    sys.exit(main())
