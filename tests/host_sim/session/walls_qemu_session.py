#!/usr/bin/env python3
"""No tape measure on the firmware as it runs on the chip (issue 48): boots the QEMU mouse twin
(odocal-fw-qemu-mouse.elf: the usual mouse in the practice maze, its wall sensors simulated inside
the MCU) on a pty, tells it the mouse's nominal size as an owner would, and runs
`odocal session --port PTY --procedure auto --truth walls --yes` against it in real time (about
forty minutes: every look is a stepped turn there and back).

Checks: the session completes and saves with 0 tape readings and result.truth "walls"; the
verification along the unseen corridor was judged by the walls; and the geometry it found is the
twin's true one (hal/sim/include/odocal/sim/usual_mouse.hpp: 31.95 / 32.06 mm, 77.1 mm) within
what the walls can tell. The walls read a stop's heading to 0.19 deg (1 sigma; docs/maze.md): over
one 0.9 m line that is 0.03 % of E_d = D_R/D_L (E_d - 1 = heading x wheelbase / length), over six
turns in place 0.01 % of the wheelbase over the mean wheel diameter (what a turn shows). Allowed:
0.1 % each, three times a single run's error, though the session fits many.

Exit status 0: passed; 1: a check failed; 77: no image or no qemu-system-arm (skipped).

Usage: walls_qemu_session.py BIN_DIR [--elf PATH] [--qemu PATH] [--keep DIR]
"""
import argparse
import json
import os
import re
import select
import shutil
import subprocess
import sys
import tempfile
import termios
import time
import tty

TRUE_LEFT_MM, TRUE_RIGHT_MM, TRUE_BASE_MM = 31.95, 32.06, 77.1
NOMINAL_D_MM, NOMINAL_BASE_MM = 32.0, 76.0


def tell_size(pty):
    """The owner's first steps on a new mouse: its nominal size, saved."""
    fd = os.open(pty, os.O_RDWR | os.O_NOCTTY)
    tty.setraw(fd)
    got = b""
    try:
        # QEMU's USART drops what arrives before the firmware enables its receiver.
        deadline = time.monotonic() + 30.0
        while b"ok name=odocal" not in got and time.monotonic() < deadline:
            os.write(fd, b"version\n")
            while select.select([fd], [], [], 0.5)[0]:
                got += os.read(fd, 4096)
        for line in (f"set wheel_diameter_mm {NOMINAL_D_MM:g}", f"set wheelbase_mm {NOMINAL_BASE_MM:g}",
                     "save"):
            os.write(fd, (line + "\n").encode())
            time.sleep(0.3)
            while select.select([fd], [], [], 0.3)[0]:
                got += os.read(fd, 4096)
    finally:
        termios.tcflush(fd, termios.TCIOFLUSH)
        os.close(fd)
    return got.decode(errors="replace")


def fitted_geometry(doc):
    """(D_L, D_R, wheelbase) in mm from the saved factors: c_L, c_R scale the nominal diameter."""
    factors = doc["factors"]
    return (NOMINAL_D_MM * float(factors["c_l"]), NOMINAL_D_MM * float(factors["c_r"]),
            float(factors["wheelbase_mm"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("bindir")
    ap.add_argument("--elf", default=os.path.join(os.path.dirname(__file__), "..", "..", "..",
                                                  "build", "stm32f4", "bin",
                                                  "odocal-fw-qemu-mouse.elf"))
    ap.add_argument("--qemu", default="qemu-system-arm")
    ap.add_argument("--keep", help="write the session's files here (kept)")
    a = ap.parse_args()
    if not os.path.exists(a.elf) or shutil.which(a.qemu) is None:
        print(f"walls_qemu_session: skipped: no {a.elf} (cmake --build --preset stm32f4) or no "
              f"{a.qemu}")
        return 77
    work = a.keep or tempfile.mkdtemp(prefix="odocal-qemu-walls-")
    os.makedirs(work, exist_ok=True)
    out = os.path.join(work, "session")
    qemu = subprocess.Popen([a.qemu, "-M", "netduinoplus2", "-display", "none", "-monitor", "none",
                             "-serial", "pty", "-semihosting-config", "enable=on,target=native",
                             "-kernel", a.elf], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    failures = 0

    def check(ok, what, detail=""):
        nonlocal failures
        print(("PASS " if ok else "FAIL ") + what + (f"  [{detail}]" if detail else ""), flush=True)
        failures += 0 if ok else 1

    try:
        line = qemu.stdout.readline().decode(errors="replace")
        match = re.search(r"/dev/pts/\d+", line)
        if not match:
            print("walls_qemu_session: QEMU gave no pty: " + line)
            return 1
        pty = match.group(0)
        transcript = tell_size(pty)
        check("board=qemu-mouse" in transcript and "ok sequence=" in transcript,
              "the twin boots, takes the mouse's size and saves it")
        started = time.monotonic()
        with open(os.path.join(work, "session.log"), "w") as log:
            session = subprocess.run(
                [os.path.join(a.bindir, "odocal"), "session", "--port", pty, "--procedure", "auto",
                 "--truth", "walls", "--out", out, "--yes"],
                input="\n" * 8, text=True, stdout=log, stderr=subprocess.STDOUT, timeout=5000)
        minutes = (time.monotonic() - started) / 60.0
        check(session.returncode == 0, f"the session ends with status 0 ({minutes:.0f} min)",
              f"status {session.returncode}, log {work}/session.log")
        doc = json.load(open(os.path.join(out, "session.json")))
        result = doc.get("result") or {}
        check(doc.get("complete") is True and doc.get("saved") is True, "complete and saved")
        check(doc.get("measurements") == 0 and result.get("truth") == "walls",
              "no tape reading: measurements 0, result.truth walls",
              f"{doc.get('measurements')}, {result.get('truth')}")
        verify = result.get("verify") or {}
        check(verify.get("judged_by") == "walls", "the unseen corridor judged by the walls",
              f"rms {verify.get('rms_mm')} mm")
        d_l, d_r, base = fitted_geometry(doc)
        e_d = d_r / d_l
        true_e_d = TRUE_RIGHT_MM / TRUE_LEFT_MM
        check(abs(e_d / true_e_d - 1.0) < 0.001, "E_d within 0.1 % of the twin's",
              f"{e_d:.5f} against {true_e_d:.5f}")
        # A turn in place shows the wheelbase over the mean wheel diameter.
        ratio = base / (0.5 * (d_l + d_r))
        true_ratio = TRUE_BASE_MM / (0.5 * (TRUE_LEFT_MM + TRUE_RIGHT_MM))
        check(abs(ratio / true_ratio - 1.0) < 0.001,
              "wheelbase over mean wheel diameter within 0.1 % of the twin's",
              f"{ratio:.4f} against {true_ratio:.4f}")
    finally:
        qemu.kill()
        qemu.wait()
    print(f"walls_qemu_session: {failures} failure(s); files in {work}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
