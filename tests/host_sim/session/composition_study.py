#!/usr/bin/env python3
"""Procedures compose: on robots this script generates at random within the documented ranges,
the documented order (umbmark, lateral, fit) and every ordered pair of those procedures, each on
a fresh store, never leave the unseen path worse than the step before, beyond the run scatter.

After every step the unseen path is driven (odocal session --procedure verify, fixed seeds) with
the factors that step saved; its RMS end error (tape minus odometry) is compared with the step
before's: a step fails when its RMS exceeds the previous one by more than 3 standard errors of
the difference of two RMS figures of n runs each (about sd·sqrt(2/n), sd the larger run scatter).
The first step is compared with the nominal robot (nothing calibrated).

Usage: composition_study.py BIN_DIR [--robots N] [--seed S] [--runs N] [--check] [--json]
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile

import study_robots

PROCEDURES = ("umbmark", "lateral", "fit")
ORDER = ("umbmark", "lateral", "fit")  # docs/calibration.md, "The recommended order"
VERIFY_SEED = 2000


def generate_robot(rng):
    """A robot within the documented ranges (study_robots.py), slip from the default to 6 times
    it."""
    return study_robots.generate_robot(rng, lambda r: round(0.0005 * r.uniform(1.0, 6.0), 5))


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr[-2000:])
    return p.stdout


class Study:
    def __init__(self, bindir, work, runs):
        self.bindir = bindir
        self.work = work
        self.runs = runs
        self.count = 0

    def out(self, tag):
        self.count += 1
        return os.path.join(self.work, "%03d-%s" % (self.count, tag))

    def step(self, robot, store, procedure, seed):
        doc = json.loads(run([self.bindir + "/odocal", "session", "--sim", robot, "--store", store,
                              "--seed", str(seed), "--procedure", procedure, "--yes", "--json",
                              "--out", self.out(procedure)]))
        return doc["factors"]

    def unseen(self, robot, store):
        """RMS and sample standard deviation (mm) of the unseen path's end errors."""
        out = self.out("verify")
        run([self.bindir + "/odocal", "session", "--sim", robot, "--store", store, "--seed",
             str(VERIFY_SEED), "--procedure", "verify", "--runs", str(self.runs), "--json",
             "--out", out])
        radii = []
        with open(os.path.join(out, "accuracy.csv")) as f:
            for line in f.read().splitlines()[1:]:
                name, _, x, y = line.split(",")
                if name == "after":
                    radii.append(math.hypot(float(x), float(y)))
        rms = math.sqrt(sum(r * r for r in radii) / len(radii))
        mean = sum(radii) / len(radii)
        sd = math.sqrt(sum((r - mean) ** 2 for r in radii) / (len(radii) - 1))
        return rms, sd

    def sequence(self, robot, steps, seed, baseline):
        """Runs `steps` on a fresh store; returns [(name, rms, sd, factors)], baseline first."""
        store = self.out("store")
        rows = [("nominal",) + baseline + (None,)]
        for i, procedure in enumerate(steps):
            factors = self.step(robot, store, procedure, seed + i)
            rows.append((procedure,) + self.unseen(robot, store) + (factors,))
        return rows


def judge(rows, runs):
    """The failures of a sequence: steps whose RMS exceeds the previous step's beyond scatter."""
    failures = []
    for before, after in zip(rows, rows[1:]):
        tol = 3.0 * max(before[2], after[2]) * math.sqrt(2.0 / runs)
        if after[1] > before[1] + tol:
            failures.append("%s -> %s: %.2f -> %.2f mm (allowed +%.2f)"
                            % (before[0], after[0], before[1], after[1], tol))
    return failures


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--robots", type=int, default=2, help="generated robots")
    ap.add_argument("--seed", type=int, default=31, help="the generator's seed")
    ap.add_argument("--runs", type=int, default=8, help="unseen-path runs per verification")
    ap.add_argument("--pairs", default="all", help="'all' ordered pairs, or 'none'")
    ap.add_argument("--check", action="store_true", help="exit 1 when a step makes it worse")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    report = []
    failures = []
    with tempfile.TemporaryDirectory() as work:
        study = Study(a.bindir, work, a.runs)
        for k in range(a.robots):
            doc = generate_robot(rng)
            robot = os.path.join(work, "robot-%d.json" % k)
            with open(robot, "w") as f:
                json.dump(doc, f)
            print("robot %d: %s" % (k, json.dumps(doc)), file=sys.stderr)
            baseline = study.unseen(robot, study.out("nominal-store"))
            sequences = [ORDER]
            if a.pairs == "all":
                sequences += [(p, q) for p in PROCEDURES for q in PROCEDURES
                              if p != q and (p, q) != ORDER[:2]]
            for steps in sequences:
                rows = study.sequence(robot, steps, 100 * (k + 1), baseline)
                bad = judge(rows, a.runs)
                line = " -> ".join("%s %.2f" % (r[0], r[1]) for r in rows)
                print("  %s%s" % (line, "   WORSE: " + "; ".join(bad) if bad else ""),
                      file=sys.stderr)
                failures += ["robot %d %s: %s" % (k, "+".join(steps), b) for b in bad]
                report.append({"robot": doc, "steps": list(steps),
                               "unseen": [{"after": r[0], "rms_mm": r[1], "sd_mm": r[2],
                                           "factors": r[3]} for r in rows]})
    if a.json:
        print(json.dumps({"sequences": report, "failures": failures}, indent=1))
    if failures:
        print("composition_study: %d step(s) made the unseen path worse:\n  %s"
              % (len(failures), "\n  ".join(failures)), file=sys.stderr)
    else:
        print("composition_study: no step made the unseen path worse (%d sequences)"
              % len(report), file=sys.stderr)
    return 1 if a.check and failures else 0


if __name__ == "__main__":
    sys.exit(main())
