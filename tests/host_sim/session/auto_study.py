#!/usr/bin/env python3
"""How close `odocal session --procedure auto` brings the unseen path to what the robot's true
geometry reaches, beside UMBmark and the fit session, with the tape measurements each took.

For each robot and seed: a calibration session on a fresh store, then the unseen path driven
--eval-runs times (odocal session --procedure verify, other seeds) with the factors it saved, and
with the true geometry in force (the oracle). Prints a Markdown table and, with --json, the
figures, each session's among them (host_sim/tools/auto-results.py makes docs/results.md's section
of them). Usage: auto_study.py BIN_DIR [--seeds N] [--procedures auto,umbmark,fit]
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

import study_robots

ROBOTS = {
    "micromouse": {"wheel_diameter_mm": 48, "wheelbase_mm": 92, "true_left_diameter_mm": 47.85,
                   "true_right_diameter_mm": 48.15, "true_wheelbase_mm": 94.2},
    "lab": {"wheel_diameter_mm": 100, "wheelbase_mm": 300, "counts_per_rev": 2048,
            "true_left_diameter_mm": 100.3, "true_right_diameter_mm": 99.8,
            "true_wheelbase_mm": 306, "slip_sigma": 0.002},
    "cart": {"wheel_diameter_mm": 150, "wheelbase_mm": 480, "counts_per_rev": 4096,
             "true_left_diameter_mm": 150.6, "true_right_diameter_mm": 149.7,
             "true_wheelbase_mm": 489, "true_wheelbase_arc_mm": 495, "slip_sigma": 0.003},
}


# What --check (ctest odocal_auto_study) holds auto to; host_sim/tools/auto-results.py cites them.
MAX_MEASUREMENTS = 20     # tape measurements per session (the default budget), all included
MAX_MEDIAN_ALL = 1.3      # the median over all sessions of all robots, unseen path / oracle
MAX_MEDIAN_ROBOT = 1.6    # each robot's median
UNSEEN_RUNS = 16          # unseen-path runs per verify session
EVAL_SEED = 1000          # the verify sessions' seeds: EVAL_SEED, EVAL_SEED + 1, ...
EVAL_SESSIONS = 2         # verify sessions per calibration (and for the oracle)


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr[-2000:])
    return p.stdout


def unseen_rms(bindir, robot, store, seeds, work):
    """RMS end error (mm) of the unseen path over len(seeds) x UNSEEN_RUNS runs with `store`'s
    factors."""
    errors = []
    for s in seeds:
        out = tempfile.mkdtemp(prefix="verify-%d-" % s, dir=work)
        doc = json.loads(run([bindir + "/odocal", "session", "--sim", robot, "--store", store,
                              "--seed", str(s), "--procedure", "verify",
                              "--runs", str(UNSEEN_RUNS), "--json", "--out", out + "/v"]))
        with open(os.path.join(out, "v", "accuracy.csv")) as f:
            for line in f.read().splitlines()[1:]:
                name, _, x, y = line.split(",")
                if name == "after":
                    errors.append(float(x) ** 2 + float(y) ** 2)
    return math.sqrt(sum(errors) / len(errors))


def oracle_store(bindir, robot_doc, robot, work):
    return study_robots.oracle_store(
        bindir, robot_doc, robot, os.path.join(work, os.path.basename(robot) + ".oracle.store"))


def session_figures(seed, session, rms):
    """What a calibration session left: the factors it saved, the runs it measured (label and
    command) and, for auto and fit, the model the fit chose and each candidate's held-out path
    RMS."""
    result = session.get("result") if isinstance(session.get("result"), dict) else {}
    fit = result.get("fit") if isinstance(result.get("fit"), dict) else {}
    model = fit.get("model") if isinstance(fit.get("model"), dict) else {}
    return {
        "seed": seed,
        "measurements": session["measurements"],
        "unseen_rms_mm": rms,
        "factors": session.get("factors"),
        "model": model.get("name"),
        "heldout_mm": {c["name"]: c["heldout_path_rms_mm"]
                       for c in model.get("candidates", []) if c.get("tried")},
        "runs": [{"label": r.get("label"), "command": r.get("command")}
                 for r in session.get("runs", [])],
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--seed-list", default="", help="these seeds instead of 1..--seeds")
    ap.add_argument("--procedures", default="auto,umbmark,fit")
    ap.add_argument("--robots", default=",".join(ROBOTS))
    ap.add_argument("--eval-sessions", type=int, default=EVAL_SESSIONS)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--check", action="store_true",
                    help="a test: auto takes at most %d measurements, the median over all its "
                         "sessions is within %gx of the oracle and no robot's median past %gx"
                         % (MAX_MEASUREMENTS, MAX_MEDIAN_ALL, MAX_MEDIAN_ROBOT))
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name in a.robots.split(","):
            doc = ROBOTS[name]
            robot = os.path.join(work, name + ".json")
            with open(robot, "w") as f:
                json.dump(doc, f)
            eval_seeds = [EVAL_SEED + i for i in range(a.eval_sessions)]
            oracle = unseen_rms(a.bindir, robot, oracle_store(a.bindir, doc, robot, work),
                                eval_seeds, work)
            for procedure in a.procedures.split(","):
                ratios, counts, sessions = [], [], []
                seeds = ([int(v) for v in a.seed_list.split(",")] if a.seed_list
                         else range(1, a.seeds + 1))
                for seed in seeds:
                    store = os.path.join(work, "%s-%s-%d.store" % (name, procedure, seed))
                    out = os.path.join(work, "%s-%s-%d" % (name, procedure, seed))
                    session = json.loads(run([a.bindir + "/odocal", "session", "--sim", robot,
                                              "--store", store, "--seed", str(seed),
                                              "--procedure", procedure, "--yes", "--json",
                                              "--out", out]))
                    counts.append(session["measurements"])
                    rms = unseen_rms(a.bindir, robot, store, eval_seeds, work)
                    ratios.append(rms / oracle)
                    sessions.append(session_figures(seed, session, rms))
                    print("%s %s seed %d: %d measurements, unseen %.2f mm (oracle %.2f): %.2fx"
                          % (name, procedure, seed, counts[-1], rms, oracle, ratios[-1]),
                          file=sys.stderr)
                rows.append({"robot": name, "procedure": procedure, "oracle_mm": oracle,
                             "ratios": ratios, "measurements": counts, "sessions": sessions,
                             "median": statistics.median(ratios), "worst": max(ratios)})
    if a.check:
        failures = []
        autos = [r for r in rows if r["procedure"] == "auto"]
        every = [x for r in autos for x in r["ratios"]]
        if any(m > MAX_MEASUREMENTS for r in autos for m in r["measurements"]):
            failures.append("more than %d measurements: %s"
                            % (MAX_MEASUREMENTS, [r["measurements"] for r in autos]))
        if every and statistics.median(every) > MAX_MEDIAN_ALL:
            failures.append("median over all auto sessions %.2fx > %gx"
                            % (statistics.median(every), MAX_MEDIAN_ALL))
        for r in autos:
            if r["median"] > MAX_MEDIAN_ROBOT:
                failures.append("%s: median %.2fx > %gx"
                                % (r["robot"], r["median"], MAX_MEDIAN_ROBOT))
        for f in failures:
            print("FAIL " + f)
        print("auto_study: %d checks passed, %d failed" % (3 - min(3, len(failures)),
                                                          len(failures)))
        return 1 if failures else 0
    if a.json:
        print(json.dumps(rows, indent=2))
        return 0
    print("| robot | procedure | tape measurements | unseen path / oracle, median | worst |"
          " oracle RMS mm |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %s | %.2f | %.2f | %.1f |" % (
            r["robot"], r["procedure"],
            "%d-%d" % (min(r["measurements"]), max(r["measurements"]))
            if min(r["measurements"]) != max(r["measurements"]) else str(r["measurements"][0]),
            r["median"], r["worst"], r["oracle_mm"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
