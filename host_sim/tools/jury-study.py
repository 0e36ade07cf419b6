#!/usr/bin/env python3
"""Readings judged by all the runs, as owners meet them (issue 45's study; a benchmark, not a CI
test: about half a minute a session).

For each generated robot: a clean auto session through odocal-sim on a pty, the tape's readings
typed at every prompt; then one session per kind of slip, typed at the *first* run of its kind
(and, with --later, at a later one), the owner answering the session's question by typing the
reading again. Each session's transcript says whether the slip was asked about (at typing time
or by the runs after it), whether a right reading was ever questioned, and the unseen path's end
error against the clean session's.

  python3 host_sim/tools/jury-study.py BUILD/bin WORKDIR [--robots N] [--later | --only-later]
                                        [--jobs N] [--markdown]

--only-later types the slips at the later run only; --jobs N studies N robots side by side.

With --markdown only docs/results.md's section is printed (make-results.sh).
"""
import concurrent.futures
import json
import os
import pty
import re
import select
import subprocess
import sys
import time
import tty

ROBOTS = {
    # name: robot file (told geometry, true geometry, slip)
    "mouse-31": {"wheel_diameter_mm": 31, "wheelbase_mm": 68, "counts_per_rev": 360,
                 "true_left_diameter_mm": 31.08, "true_right_diameter_mm": 30.95,
                 "true_wheelbase_mm": 69.1, "slip_sigma": 0.0005, "bump_height_mm": 0},
    "small-48": {"wheel_diameter_mm": 48, "wheelbase_mm": 110, "counts_per_rev": 1200,
                 "true_left_diameter_mm": 47.85, "true_right_diameter_mm": 48.1,
                 "true_wheelbase_mm": 111.5, "true_wheelbase_arc_mm": 112.4,
                 "slip_sigma": 0.0025, "bump_height_mm": 0},
    "lab-84": {"wheel_diameter_mm": 84, "wheelbase_mm": 212, "counts_per_rev": 2048,
               "true_left_diameter_mm": 83.7, "true_right_diameter_mm": 84.2,
               "true_wheelbase_mm": 214.0, "slip_sigma": 0.001, "bump_height_mm": 0},
    "lab-100": {"wheel_diameter_mm": 100, "wheelbase_mm": 300, "counts_per_rev": 2048,
                "true_left_diameter_mm": 99.7, "true_right_diameter_mm": 100.35,
                "true_wheelbase_mm": 303.0, "true_wheelbase_arc_mm": 305.5,
                "slip_sigma": 0.001, "bump_height_mm": 0},
    "cart-150": {"wheel_diameter_mm": 150, "wheelbase_mm": 420, "counts_per_rev": 4096,
                 "true_left_diameter_mm": 150.6, "true_right_diameter_mm": 149.8,
                 "true_wheelbase_mm": 416.0, "true_wheelbase_arc_mm": 419.0,
                 "slip_sigma": 0.005, "bump_height_mm": 0},
}

# Each slip: the run kind it is typed at, and what it does to the tape's (x, y, heading).
SLIPS = {
    "heading sign": ("turns-ccw", lambda x, y, t: (x, y, -t)),
    "x sign": ("line", lambda x, y, t: (-x, y, t)),
    "y sign": ("arc-left", lambda x, y, t: (x, -y, t)),
    "x and y swapped": ("line", lambda x, y, t: (y, x, t)),
    "metres": ("line", lambda x, y, t: (x / 1000.0, y / 1000.0, t)),
    "centimetres": ("arc-right", lambda x, y, t: (x / 10.0, y / 10.0, t)),
    "heading a turn off": ("arc-left", lambda x, y, t: (x, y, t + 360.0)),
    "digit dropped": ("line", lambda x, y, t: (float(str(int(round(x)))[:-1] or "0"), y, t)),
    "digit doubled": ("arc-right", lambda x, y, t: (x, float(str(int(round(y))) + "0"), t)),
    "2 m off": ("line", lambda x, y, t: (x + 2000.0, y, t)),
}


def tape(port):
    """The simulator's tape, asked on the robot's pty twice until two answers agree."""
    for _ in range(20):
        answers = []
        for _ in range(2):
            fd = os.open(port, os.O_RDWR | os.O_NOCTTY)
            tty.setraw(fd)
            os.write(fd, b"measure\n")
            got = b""
            start = time.time()
            while b"theta_deg=" not in got or b"\n" not in got.split(b"theta_deg=")[-1]:
                ready, _, _ = select.select([fd], [], [], 0.5)
                if ready:
                    got += os.read(fd, 4096)
                if time.time() - start > 10:
                    break
            os.close(fd)
            text = got.decode(errors="replace")
            try:
                answers.append(tuple(float(re.findall(k + r"=(-?[0-9.]+)", text)[-1])
                                     for k in ("x_mm", "y_mm", "theta_deg")))
            except IndexError:
                answers.append(None)
        if answers[0] is not None and answers[0] == answers[1]:
            return answers[0]
    raise RuntimeError("no tape reading")


def session(bindir, robot_file, seed, out, slip=None, at="first"):
    """One auto session typed by an owner; returns a dict of what happened."""
    sim = subprocess.Popen([os.path.join(bindir, "odocal-sim"), "--pty", "--speed", "0",
                            "--robot", robot_file, "--seed", str(seed)],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    port = sim.stdout.readline().split()[-1]
    pid, fd = pty.fork()
    if pid == 0:
        os.execv(os.path.join(bindir, "odocal"),
                 ["odocal", "session", "--port", port, "--no-wait", "--procedure", "auto",
                  "--out", out])
    buf, pos = "", 0
    seen_kind, slipped_run, right = 0, None, None
    asked_typing, asked_after, questioned_right = False, False, 0
    while True:
        ready, _, _ = select.select([fd], [], [], 2.0)
        if ready:
            try:
                data = os.read(fd, 65536).decode(errors="replace")
            except OSError:
                break
            buf += data
        tail = buf[pos:].rstrip()
        if not tail.endswith(":") and not tail.endswith("]:"):
            continue
        if "What now?" in tail:
            pos = len(buf)
            named = slipped_run is not None and re.search(
                r"Check run %s[ :]|and run %s:" % (slipped_run, slipped_run), tail)
            if named:
                asked_after = True
                os.write(fd, ("r %s\n" % slipped_run).encode())
            else:
                questioned_right += 1
                os.write(fd, b"k\n")
        elif "its reading again" in tail:
            pos = len(buf)
            os.write(fd, (right + "\n").encode())
        elif "Save these factors" in tail:
            pos = len(buf)
            os.write(fd, b"y\n")
        elif "Type the reading again" in tail:
            pos = len(buf)
            last = re.findall(r"\nRun (\d+)/\d+ \(", buf)[-1]
            if slipped_run == last:
                asked_typing = True
                os.write(fd, (right + "\n").encode())
            else:
                questioned_right += 1
                os.write(fd, b"y\n")
        elif "Measured stop point" in tail:
            pos = len(buf)
            number, kind = re.findall(r"\nRun (\d+)/\d+ \(([a-z-]+), trial", buf)[-1]
            x, y, t = tape(port)
            text = "%.1f %.1f %.1f" % (x, y, t)
            if slip and kind == SLIPS[slip][0] and slipped_run is None:
                seen_kind += 1
                if at == "first" or seen_kind == 3:
                    slipped_run, right = number, text
                    text = "%g %g %.1f" % SLIPS[slip][1](x, y, t)
            os.write(fd, (text + "\n").encode())
    _, status = os.waitpid(pid, 0)
    sim.terminate()
    result = {"exit": os.waitstatus_to_exitcode(status), "slipped_run": slipped_run,
              "asked_typing": asked_typing, "asked_after": asked_after,
              "questioned_right": questioned_right}
    try:
        doc = json.load(open(os.path.join(out, "session.json")))
        result["verify_rms_mm"] = doc["result"]["verify"]["rms_mm"]
        result["before_rms_mm"] = doc["result"]["verify"]["before_rms_mm"]
    except (OSError, KeyError, ValueError):
        pass
    return result


def main():
    bindir, work = sys.argv[1], sys.argv[2]
    robots = list(ROBOTS)[:int(sys.argv[sys.argv.index("--robots") + 1])] \
        if "--robots" in sys.argv else list(ROBOTS)
    places = (["later"] if "--only-later" in sys.argv
              else ["first", "later"] if "--later" in sys.argv else ["first"])
    jobs = int(sys.argv[sys.argv.index("--jobs") + 1]) if "--jobs" in sys.argv else 1
    os.makedirs(work, exist_ok=True)

    def study(n, name):
        robot_file = os.path.join(work, name + ".json")
        json.dump(ROBOTS[name], open(robot_file, "w"))
        seed = 40 + n
        clean = session(bindir, robot_file, seed, os.path.join(work, name + "-clean"))
        mine = [(name, "clean", "-", clean)]
        if "--markdown" not in sys.argv:
            print(name, "clean", clean, flush=True)
        for slip in SLIPS:
            for at in places:
                out = os.path.join(work, "%s-%s-%s" % (name, slip.replace(" ", "_"), at))
                r = session(bindir, robot_file, seed, out, slip, at)
                mine.append((name, slip, at, r))
                if "--markdown" not in sys.argv:
                    print(name, slip, at, r, flush=True)
        return mine

    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        rows = [row for mine in pool.map(lambda a: study(*a), enumerate(robots)) for row in mine]
    print("\n## Readings judged by all the runs (`host_sim/tools/jury-study.py`)\n")
    print("Generated by `host_sim/tools/jury-study.py` (called by make-results.sh): on each "
          "generated robot a clean auto session through odocal-sim on a pty, the simulator's tape "
          "typed at every prompt, then one session per slip typed at the first run of its kind; the "
          "owner types the reading again when the session names the run. *asked*: at typing time "
          "(`Check this reading`) / by the runs after it (`Check run N ... disagree`). *right "
          "readings questioned*: questions about any other reading (kept). The unseen path's RMS "
          "is the verification's, against the clean session's.\n")
    print("| robot | slip | at | run | asked (typing / after) | right readings questioned | "
          "unseen path RMS mm (clean) |")
    print("|---|---|---|---|---|---|---|")
    clean_rms = {name: r.get("verify_rms_mm") for name, slip, at, r in rows if slip == "clean"}
    for name, slip, at, r in rows:
        asked = "clean" if slip == "clean" else "%s / %s" % (
            "yes" if r["asked_typing"] else "no", "yes" if r["asked_after"] else "no")
        print("| %s | %s | %s | %s | %s | %d | %s (%s) |" % (
            name, slip, at, r["slipped_run"] or "-", asked, r["questioned_right"],
            "%.1f" % r["verify_rms_mm"] if "verify_rms_mm" in r else "exit %d" % r["exit"],
            "%.1f" % clean_rms[name] if clean_rms.get(name) is not None else "-"))


if __name__ == "__main__":
    main()
