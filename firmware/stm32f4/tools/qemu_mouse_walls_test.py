#!/usr/bin/env python3
"""Boots odocal-fw-qemu-mouse.elf (the usual mouse in the practice maze, simulated inside the MCU)
in QEMU and checks that `walls` reads the maze through the firmware's wall-sensor path.

The bounds come from the sensor model of docs/simulation.md, not from a run: a sensor of gain g
(uniform in 1 +/- 20 %) whose axis meets a wall of reflectivity r (1 +/- 5 %) at distance d and
incidence phi reads g r k cos(phi) / d^2 counts above ambient, k = 6e6 counts mm^2; each
conversion has noise sigma 6 counts, so a lit reading (two conversions) about 8.5.

Exit status: 0 when every check passed, 1 when one failed, 2 when QEMU could not be run.
"""

import argparse
import math
import os
import sys
import time

from qemu_console_test import Checks, Guest, fields, wait_idle

K_COUNTS_MM2 = 6.0e6
GAIN = (0.8, 1.2)
REFLECTIVITY = (0.95, 1.05)
LIT_NOISE = 6.0 * math.sqrt(2.0)
FULL_SCALE_LIT = 4095 - 100  # the ADC's full scale above the ambient reading
KEYS = ("left_front", "left_diagonal", "right_diagonal", "right_front")


def lit_bounds(distances_mm, incidences_deg):
    """Smallest and largest lit reading over the gain and reflectivity spreads, for a distance in
    `distances_mm` and an incidence in `incidences_deg` (each low, high), with 5 sigma of noise on
    each side."""
    cos_low, cos_high = (math.cos(math.radians(a)) for a in reversed(incidences_deg))
    low = GAIN[0] * REFLECTIVITY[0] * K_COUNTS_MM2 * cos_low / distances_mm[1] ** 2
    high = GAIN[1] * REFLECTIVITY[1] * K_COUNTS_MM2 * cos_high / distances_mm[0] ** 2
    return low - 5.0 * LIT_NOISE, min(high + 5.0 * LIT_NOISE, FULL_SCALE_LIT)


def walls(guest):
    """The four readings of one `walls`, or None when the reply is not `ok` with the four keys."""
    reply = guest.command("walls")
    got = fields(reply)
    if reply is None or not reply.startswith("ok") or any(k not in got for k in KEYS):
        return None
    return {k: int(got[k]) for k in KEYS}


def turn(guest, w_radps, ms):
    """A turn in place, then idle and 0.3 s for the wheels to coast to rest."""
    reply = guest.command(f"drive 0 {w_radps} {ms}")
    status = wait_idle(guest, 10.0)
    time.sleep(0.3)
    return reply is not None and reply.startswith("ok") and status.get("mode") == "idle"


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--qemu", default="qemu-system-arm")
    parser.add_argument("--elf", required=True)
    parser.add_argument("--timeout", type=int, default=100, help="whole session, s")
    args = parser.parse_args()
    if not os.path.exists(args.elf):
        print(f"no image {args.elf}")
        return 2

    guest = Guest(args.qemu, args.elf, False, args.timeout)
    checks = Checks()
    booted = False
    deadline = time.monotonic() + 30.0
    while not booted and time.monotonic() < deadline:
        guest.send("version\n")
        booted = guest.expect(rb"(?m)^ok name=odocal[^\r\n]*\r?\n", 1.0) is not None
    if not checks.check(booted and b" board=qemu-mouse " in guest.output,
                        "boots; the start-up line names the mouse twin"):
        print(guest.output.decode(errors="replace"))
        guest.process.kill()
        return 1

    # The owner tells the firmware the mouse's nominal size (docs/maze.md).
    for line in ("set wheel_diameter_mm 32", "set wheelbase_mm 76"):
        reply = guest.command(line)
        checks.check(reply is not None and reply.startswith("ok"), line, reply)

    # Start: cell (0, 0)'s centre facing north, up the west corridor (six cells). The front
    # sensors (40 mm ahead of the wheels) see nothing within their 400 mm range; the diagonals
    # (35 mm ahead, 20 mm aside, 50 deg out) meet the corridor's side faces, 84 mm from the centre
    # line, at (84 - 20) / cos(40 deg) = 83.6 mm and 40 deg incidence.
    start = walls(guest)
    checks.check(start is not None, "walls answers ok with the four sensors' keys", str(start))
    if start is not None:
        for key in ("left_front", "right_front"):
            checks.check(start[key] <= 5.0 * LIT_NOISE,
                         f"{key} up an open corridor reads noise alone", str(start[key]))
        low, high = lit_bounds((82.0, 85.0), (38.0, 42.0))
        for key in ("left_diagonal", "right_diagonal"):
            checks.check(low <= start[key] <= high,
                         f"{key} sees the corridor's side wall at 84 mm, 40 deg",
                         f"{start[key]} in [{low:.0f}, {high:.0f}]")
        again = walls(guest)
        checks.check(again is not None and
                     all(abs(again[k] - start[k]) <= 6.0 * LIT_NOISE for k in KEYS),
                     "a robot at rest reads the same again (within 6 sigma of two readings' "
                     "noise)", str(again))

    # A quarter turn to the left: the front sensors now face the west wall, whose face lies
    # 84 mm from the centre and 44 mm from the sensors; the turn is off by the true wheelbase
    # (77.1 mm against 76: 1.4 %) and the coasting, a few degrees, which moves each front sensor
    # (30 mm off the axis) by under 2 mm.
    checks.check(turn(guest, 1.5, 1047), "a quarter turn to the left (drive 0 1.5 1047)")
    facing_wall = walls(guest)
    low, high = lit_bounds((42.0, 46.0), (0.0, 5.0))
    checks.check(facing_wall is not None and
                 all(low <= facing_wall[k] <= high for k in ("left_front", "right_front")),
                 "facing the west wall 44 mm away, both front sensors see it",
                 f"{facing_wall} in [{low:.0f}, {high:.0f}]")
    # Turning back (clockwise): 0.5 s in, the robot has turned 30 to 45 deg from facing the wall
    # (1.5 rad/s, less the first tenth of a second to spin up; the turn ends after 90). The right
    # front sensor (30 mm to the north of the axis) swings away: at 30 deg its axis meets the wall
    # 74 mm away at 30 deg incidence, g r k cos(30 deg) / 74^2, a third of what it read square on
    # at 44 mm, and less further round. (The left front one swings nearer and reads about the
    # same: 40 mm at 30 deg.)
    reply = guest.command("drive 0 -1.5 1047")
    checks.check(reply is not None and reply.startswith("ok"), "drive 0 -1.5 1047", reply)
    time.sleep(0.5)
    moving = walls(guest)
    checks.check(moving is not None and facing_wall is not None and
                 moving["right_front"] < 0.6 * facing_wall["right_front"],
                 "walls answers while the robot turns, and the right front reading falls as it "
                 "turns away", f"{moving} after {facing_wall}")
    wait_idle(guest, 10.0)
    time.sleep(0.3)
    back = walls(guest)
    checks.check(back is not None and back["left_front"] <= 5.0 * LIT_NOISE and
                 back["right_front"] <= 5.0 * LIT_NOISE,
                 "turned back up the corridor, the front sensors see nothing again", str(back))

    status_code = guest.end_session()
    checks.check(status_code == 0, "guest exits with status 0", str(status_code))
    if checks.failures:
        print("---- console transcript ----")
        print(guest.output.decode(errors="replace"))
    print(f"{checks.failures} failure(s)")
    return 1 if checks.failures else 0


if __name__ == "__main__":
    sys.exit(main())
