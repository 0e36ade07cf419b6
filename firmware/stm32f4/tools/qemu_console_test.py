#!/usr/bin/env python3
"""Boots odocal-fw-qemu.elf in QEMU (netduinoplus2), talks to its console and checks the answers.

Exit status: 0 when every check passed, 1 when one failed, 2 when QEMU could not be run.
The guest ends the session itself (Ctrl-D -> semihosting exit), and its exit status is checked.
"""

import argparse
import hashlib
import json
import math
import os
import re
import subprocess
import sys
import threading
import time


class Guest:
    """The QEMU process and a byte buffer of everything it printed."""

    def __init__(self, qemu, elf, icount, timeout_s):
        command = ["timeout", str(timeout_s), qemu, "-M", "netduinoplus2", "-display", "none",
                   "-monitor", "none", "-serial", "stdio",
                   "-semihosting-config", "enable=on,target=native", "-kernel", elf]
        if icount:
            # One instruction = 1 ns of virtual time while the guest runs (so the tick's duration
            # in ns is its instruction count); while it sleeps in WFI the virtual clock follows
            # the host's. (sleep=off would skip idle time, but then QEMU 7.2's SysTick and TIM2
            # disagree by a factor of two, so the rate check below would be meaningless.)
            command += ["-icount", "shift=0"]
        self.argv = command
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE)
        self.output = b""
        self.cursor = 0
        self.lock = threading.Lock()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        while True:
            chunk = self.process.stdout.read1(4096)
            if not chunk:
                return
            with self.lock:
                self.output += chunk

    def expect(self, pattern, timeout_s):
        """Waits for `pattern` (bytes regex) after the cursor; returns the match or None."""
        deadline = time.monotonic() + timeout_s
        regex = re.compile(pattern)
        while time.monotonic() < deadline:
            with self.lock:
                match = regex.search(self.output, self.cursor)
                if match:
                    self.cursor = match.end()
                    return match
            if self.process.poll() is not None and not self.reader.is_alive():
                return None
            time.sleep(0.01)
        return None

    def send(self, text):
        self.process.stdin.write(text.encode())
        self.process.stdin.flush()

    def end_session(self):
        """Ctrl-D: the guest exits through semihosting (status 0). Returns QEMU's exit status,
        -1 when it had not exited within 20 s (then killed)."""
        self.send("\x04")
        try:
            return self.process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.process.kill()
            return -1

    def command(self, line, timeout_s=10.0):
        """Types one command line (LF-terminated: a script, not a terminal); returns the reply."""
        self.send(line + "\n")
        match = self.expect(rb"(?m)^(ok|err)\b([^\r\n]*)\r?\n", timeout_s)
        if match is None:
            return None
        return (match.group(1) + match.group(2)).decode(errors="replace")


def fields(reply):
    """key=value pairs of an `ok` reply."""
    return dict(re.findall(r"(\w+)=(\S+)", reply or ""))


class Checks:
    def __init__(self):
        self.failures = 0

    def check(self, condition, what, detail=""):
        print(("PASS " if condition else "FAIL ") + what + (f"  [{detail}]" if detail else ""))
        if not condition:
            self.failures += 1
        return condition


def wait_idle(guest, timeout_s):
    """Polls `status` until the loop is idle; returns the last status fields."""
    deadline = time.monotonic() + timeout_s
    status = {}
    while time.monotonic() < deadline:
        status = fields(guest.command("status"))
        if status.get("mode") in ("idle", "fault"):
            return status
        time.sleep(0.2)
    return status


def bridge_exchange(guest, data, timeout_s=10.0):
    """Writes `data` as diffdrive_arduino's ArduinoComms does (one write, lines ended by a bare
    CR) and returns every byte the guest printed up to the next LF (None without one)."""
    start = guest.cursor
    guest.send(data)
    if guest.expect(rb"\n", timeout_s) is None:
        return None
    return guest.output[start:guest.cursor]


def wait_ticks(guest, n, timeout_s=30.0):
    """Waits until the robot has counted `n` more control ticks (1 kHz: its own time)."""
    start = int(fields(guest.command("status")).get("ticks", "0"))
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if int(fields(guest.command("status")).get("ticks", "0")) - start >= n:
            return
        time.sleep(0.05)


def bridge_counts(guest):
    """The two counts of an `e` (None when the reply is not two whole numbers)."""
    got = bridge_exchange(guest, "e\r")
    match = re.fullmatch(rb"(-?\d+) (-?\d+)\r\n", got or b"")
    return (int(match.group(1)), int(match.group(2))) if match else None


def bridge_checks(guest, checks):
    """ROSArduinoBridge's commands (docs/ros.md): one reply line each, never echoed."""
    for data, want in (("\r", b"Invalid Command\r\n"), ("u 30:20:0:100\r", b"OK\r\n"),
                       ("r\r", b"OK\r\n"), ("b\r", b"115200\r\n"), ("x 5 9\r", b"OK\r\n"),
                       ("a 3\r", b"0\r\n"), ("z\r", b"Invalid Command\r\n")):
        got = bridge_exchange(guest, data)
        checks.check(got == want, f"ROSArduinoBridge {data!r} answers {want!r}", repr(got))
    counts = bridge_counts(guest)  # since `r`: the wheels may still settle by a count
    checks.check(counts is not None and max(abs(c) for c in counts) <= 2,
                 "e after r answers counts near 0 0", repr(counts))
    # Time as the robot counts it (its ticks, 1 kHz): QEMU's virtual clock falls behind the
    # host's when the host is busy.
    got = bridge_exchange(guest, "m 20 20\r")
    start = int(fields(guest.command("status")).get("ticks", "0"))
    checks.check(got == b"OK\r\n", "ROSArduinoBridge m 20 20 answers OK", repr(got))
    status = {}
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline:
        status = fields(guest.command("status"))
        if int(status.get("ticks", "0")) - start >= 1000:
            break
        time.sleep(0.1)
    counts = bridge_counts(guest)
    checks.check(status.get("mode") == "drive" and counts is not None and min(counts) > 100,
                 "m 20 20 still drives both wheels forward after 1 s (past cmd_timeout_ms)",
                 f"mode={status.get('mode')} e={counts}")
    status = wait_idle(guest, 30.0)
    stopped_after = int(status.get("ticks", "0")) - start
    # 2000 ms after the `m` took effect, a few ticks before `start` was read.
    checks.check(status.get("mode") == "idle" and 1900 <= stopped_after <= 3000,
                 "no m for 2 s stopped the wheels", f"idle {stopped_after} ticks after m")
    # The wheels coast down after the loop stops them; then they stay. Robot time again: a busy
    # host slows QEMU's clock, and half a second of the host's can be a few ticks of the robot's.
    wait_ticks(guest, 500)
    first = bridge_counts(guest)
    wait_ticks(guest, 500)
    second = bridge_counts(guest)
    checks.check(first is not None and second is not None and
                 max(abs(a - b) for a, b in zip(first, second)) <= 2,
                 "the wheels stay stopped", f"{first} then {second}")
    got = bridge_exchange(guest, "m 0 0\r")
    checks.check(got == b"OK\r\n", "m 0 0 answers OK", repr(got))


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--qemu", default="qemu-system-arm")
    parser.add_argument("--elf", required=True)
    parser.add_argument("--timeout", type=int, default=240, help="whole session, s")
    parser.add_argument("--no-icount", action="store_true", help="real-time virtual clock")
    parser.add_argument("--tick-budget", type=int, default=1500,
                        help="max instructions of the control tick (with -icount)")
    parser.add_argument("--figures-out", help="write the tick's max/avg instructions here (JSON, "
                        "for doc_figures.py)")
    args = parser.parse_args()
    if not os.path.exists(args.elf):
        print(f"no image {args.elf}")
        return 2

    guest = Guest(args.qemu, args.elf, not args.no_icount, args.timeout)
    checks = Checks()
    # Nothing is printed at power-up (a ROSArduinoBridge client must read only its replies): the
    # start-up line comes before the reply to the first odocal command. QEMU's USART drops bytes
    # that arrive before the receiver is on, so `version` is asked until it is answered.
    banner = None
    deadline = time.monotonic() + 30.0
    while banner is None and time.monotonic() < deadline:
        guest.send("version\n")
        reply = guest.expect(rb"(?m)^ok name=odocal[^\r\n]*\r?\n", 1.0)
        if reply is not None:
            banner = re.search(rb"# odocal \S+ console [^\r\n]* board=qemu clock=\S+ reset=\S+\r?\n",
                               guest.output[:reply.start()])
    if not checks.check(banner is not None and guest.output.count(b"# odocal ") == 1,
                        "boots silent; the start-up line (with the board's pairs) before the "
                        "first reply, once"):
        print(guest.output.decode(errors="replace"))
        guest.process.kill()
        return 1
    print("banner:", banner.group(0).decode().strip())

    reply = guest.command("version")
    checks.check(reply is not None and reply.startswith("ok") and "version=" in reply,
                 "version answers ok version=...", reply)

    reply = guest.command("get wheelbase_mm")
    checks.check(reply is not None and reply.startswith("ok"), "get wheelbase_mm", reply)
    reply = guest.command("set c_l 7")
    checks.check(reply is not None and reply.startswith("err"), "set out of range refused",
                 reply)
    reply = guest.command("set kp 1x")
    checks.check(reply is not None and reply.startswith("err"), "set with junk refused", reply)
    reply = guest.command("get c_l")
    checks.check(reply is not None and reply.startswith("ok") and
                 abs(float(next(iter(v for k, v in fields(reply).items()
                                     if k in ("c_l", "value")), "nan")) - 1.0) < 1e-6,
                 "refused set changed nothing", reply)
    reply = guest.command("set kff 0.034")
    checks.check(reply is not None and reply.startswith("ok"), "set kff 0.034", reply)
    reply = guest.command("save")
    checks.check(reply is not None and reply.startswith("ok"), "save", reply)
    reply = guest.command("get kff")
    checks.check(reply is not None and "0.034" in reply, "get returns the saved value", reply)

    reply = guest.command("bogus")
    checks.check(reply is not None and reply.startswith("err"), "unknown command refused", reply)
    # No board has wall sensors yet (the images link the console without its target options).
    reply = guest.command("walls")
    checks.check(reply == "err no_sensors this robot has no wall sensors",
                 "walls: no wall sensors", reply)

    # The console keeps no receive ring of its own: input waits in the USART's (127 bytes), which
    # the main loop drains into the line editor on every pass. A whole 127-byte line and its line
    # end (128 bytes) get through, a 128-byte one is refused whole, and three lines sent in one
    # write get their three replies in order.
    reply = guest.command("get " + "x" * 123)
    checks.check(reply is not None and reply.startswith("err unknown_parameter"),
                 "a 127-byte line is read whole", reply)
    reply = guest.command("get " + "x" * 124)
    checks.check(reply is not None and reply.startswith("err line_too_long"),
                 "a 128-byte line is refused whole", reply)
    guest.send("get c_l\nget c_r\nget kp\n")
    burst = []
    for _ in range(3):
        match = guest.expect(rb"(?m)^(ok|err)\b([^\r\n]*)\r?\n", 10.0)
        burst.append((match.group(1) + match.group(2)).decode() if match else "")
    checks.check(burst[0] == "ok c_l=1.000000" and burst[1] == "ok c_r=1.000000" and
                 burst[2].startswith("ok kp="), "three lines in one write: three replies in order",
                 " | ".join(burst))

    # Wiring self-test (docs/wiring.md): the QEMU robot is wired right; a wrong wiring_fix (the
    # left encoder inverted) is a miswiring the self-test names; 0 puts it back.
    reply = guest.command("selftest", 30.0)
    checks.check(reply is not None and fields(reply).get("faults") == "none",
                 "selftest on a robot wired right: no fault", reply)
    guest.command("set wiring_fix 4")
    reply = guest.command("selftest", 30.0)
    checks.check(reply is not None and fields(reply).get("faults") == "left_reversed",
                 "selftest names an inverted left encoder", reply)
    reply = guest.command("set wiring_fix 0")
    checks.check(reply is not None and reply.startswith("ok"), "set wiring_fix 0", reply)
    wait_idle(guest, 60.0)

    # Straight line: 0.2 m/s for 1 s moves about 0.2 m forward (plus the ramps), no turn.
    guest.command("odom reset")
    reply = guest.command("drive 0.2 0 1000")
    checks.check(reply is not None and reply.startswith("ok"), "drive 0.2 0 1000", reply)
    status = wait_idle(guest, 60.0)
    pose = fields(guest.command("odom"))
    x, y, theta = (float(pose.get(k, "nan")) for k in ("x_mm", "y_mm", "theta_deg"))
    checks.check(150.0 <= x <= 260.0 and abs(y) < 5.0 and abs(theta) < 1.0,
                 "drive moved forward ~200 mm, straight", f"x={x} y={y} theta={theta}")

    # Turn in place: +1 rad/s for 1 s turns left (counter-clockwise), about 57 degrees.
    guest.command("odom reset")
    guest.command("drive 0 1 1000")
    wait_idle(guest, 60.0)
    pose = fields(guest.command("odom"))
    x, y, theta = (float(pose.get(k, "nan")) for k in ("x_mm", "y_mm", "theta_deg"))
    checks.check(40.0 <= theta <= 75.0 and math.hypot(x, y) < 5.0,
                 "drive 0 1 turned left in place", f"x={x} y={y} theta={theta}")

    bridge_checks(guest, checks)

    # The UMBmark ccw square of 1 m ends near the start, facing the start heading.
    guest.command("odom reset")
    reply = guest.command("run umbmark-ccw 1")
    checks.check(reply is not None and reply.startswith("ok"), "run umbmark-ccw 1", reply)
    running = fields(guest.command("status"))
    checks.check(running.get("mode") == "path", "status shows the path running",
                 " ".join(f"{k}={v}" for k, v in running.items() if k in ("mode", "path")))
    status = wait_idle(guest, 150.0)
    pose = fields(guest.command("odom"))
    x, y, theta = (float(pose.get(k, "nan")) for k in ("x_mm", "y_mm", "theta_deg"))
    wrapped = (theta + 180.0) % 360.0 - 180.0
    checks.check(status.get("mode") == "idle" and math.hypot(x, y) < 30.0 and abs(wrapped) < 3.0,
                 "umbmark-ccw 1 m square closes in odometry", f"x={x} y={y} theta={theta}")

    # An arc with an arc wheelbase (the blend in odometry and inverse kinematics): the tick's
    # longest path, measured by the tick maximum below. 0.2 m/s at 1 rad/s for 1 s turns ~57°.
    reply = guest.command("set wheelbase_arc_mm 151.5")
    checks.check(reply is not None and reply.startswith("ok"), "set wheelbase_arc_mm", reply)
    guest.command("odom reset")
    guest.command("drive 0.2 1 1000")
    wait_idle(guest, 60.0)
    pose = fields(guest.command("odom"))
    x, y, theta = (float(pose.get(k, "nan")) for k in ("x_mm", "y_mm", "theta_deg"))
    checks.check(40.0 <= theta <= 75.0 and x > 100.0 and y > 20.0,
                 "drive 0.2 1 with an arc wheelbase turned left on an arc",
                 f"x={x} y={y} theta={theta}")
    guest.command("set wheelbase_arc_mm 0")

    second = fields(guest.command("status"))
    checks.check(second.get("faults") == "none", "no faults", second.get("faults", "?"))
    if not args.no_icount:
        tick_us = float(second.get("tick_us_max", "nan"))
        instructions = tick_us * 1000.0  # -icount shift=0: 1 instruction = 1 ns
        print(f"measured: control tick max {instructions:.0f} instructions "
              f"(avg {float(second.get('tick_us_avg', 'nan')) * 1000.0:.0f})")
        checks.check(instructions <= args.tick_budget,
                     f"control tick <= {args.tick_budget} instructions", f"{instructions:.0f}")
        if args.figures_out and math.isfinite(instructions):
            os.makedirs(os.path.dirname(os.path.abspath(args.figures_out)), exist_ok=True)
            with open(args.elf, "rb") as elf, open(args.figures_out, "w") as out:
                json.dump({"tick_max": round(instructions),
                           "tick_avg": round(float(second.get("tick_us_avg", "nan")) * 1000.0),
                           "elf_sha256": hashlib.sha256(elf.read()).hexdigest()}, out)

    status_code = guest.end_session()
    checks.check(status_code == 0, "guest exits with status 0", str(status_code))
    # Tick rate: the QEMU board counts ticks against TIM2's counter (QEMU's virtual clock at
    # 1 GHz, independent of SysTick) and prints both when the session ends.
    session = guest.expect(rb"# qemu-session ticks=(\d+) timer_us=(\d+) clock_us=(\d+)", 5.0)
    if session:
        ticks, timer_us = int(session.group(1)), int(session.group(2))
        clock_us = int(session.group(3))
        # The application's µs clock (MicrosecondTimer on TIM5, the robot's clock class) over the
        # same ticks: both count QEMU's virtual time, so they agree to the µs the reads are apart.
        checks.check(timer_us > 1_000_000 and abs(clock_us - timer_us) <= 0.001 * timer_us,
                     "the µs clock (TIM5) counts microseconds",
                     f"clock {clock_us} us against TIM2 {timer_us} us")
        rate = ticks / (timer_us / 1e6) if timer_us else 0.0
        # QEMU drops SysTick periods when its virtual clock jumps after a host stall (0.2..6 %
        # measured on a 2-core host at load 2-3, more under heavier load), never adds any: the
        # band still catches a wrong reload or clock (x2, /2, 16 vs 168 MHz). A tick that
        # overruns its period is caught by the instruction budget above.
        checks.check(timer_us > 1_000_000 and 0.75 <= rate / 1000.0 <= 1.005,
                     "tick keeps 1 kHz against an independent timer",
                     f"{ticks} ticks in {timer_us} us = {rate:.2f} Hz")
    else:
        checks.check(False, "tick keeps 1 kHz and the µs clock counts µs", "no session line")
    if checks.failures:
        print("---- console transcript ----")
        print(guest.output.decode(errors="replace"))
        print(guest.process.stderr.read().decode(errors="replace"))
    print(f"{checks.failures} failure(s)")
    return 1 if checks.failures else 0


if __name__ == "__main__":
    sys.exit(main())
