#!/usr/bin/env python3
"""auto tells the truth about what it leaves (issue 32): on robots this script generates at
random (sizes from a micromouse to a cart, slip from the default to 10 times it), one
`odocal session --procedure auto` each, then the unseen path driven RUNS times with the factors it
saved and RUNS times with the true geometry in force (the oracle, the same seed), and checks:

- systematic: the mean end of the calibrated robot's runs minus the oracle's is within
  2 sqrt(sigma_sys^2 + 2 sd^2 / RUNS) of zero (sigma_sys: what auto said its factors leave; the
  second term the two means' own scatter), in at least 90 % of the sessions: failed only when
  the count is below what 90 % coverage gives with probability 2.5 % (one-sided binomial);
- random drift: the scatter of the calibrated robot's runs about their mean (RMS radius) is within
  a factor of 2 of what auto predicted (sigma_random_mm), in at least 90 % of the sessions, the
  same binomial rule (a scatter from RUNS runs is itself unsure by about 1/sqrt(2 (RUNS - 1)));
- the sessions that met their target: unseen-path RMS within 1.3x of the oracle's in the median
  and 1.6x at worst;
- no reading of the simulator's tape (every one correct) is questioned by the reading check.

Usage: coverage_study.py BIN_DIR [--robots N] [--seed S] [--runs N] [--max-measurements N]
       [--check] [--json]
"""
import argparse
import concurrent.futures
import json
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile

import study_robots

VERIFY_SEED = 3000


def generate_robot(rng):
    """A robot within the documented ranges (study_robots.py), slip from the default (0.0005) to
    10 times it, uniform in its logarithm."""
    return study_robots.generate_robot(
        rng, lambda r: round(0.0005 * math.exp(r.uniform(0.0, math.log(10.0))), 6))


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr[-2000:])
    return p.stdout, p.stderr


def stops(bindir, robot, store, runs, out):
    """The unseen path's end errors (x, y mm) of `runs` runs with `store`'s factors."""
    run([bindir + "/odocal", "session", "--sim", robot, "--store", store, "--seed",
         str(VERIFY_SEED), "--procedure", "verify", "--runs", str(runs), "--json", "--out", out])
    errors = []
    with open(os.path.join(out, "accuracy.csv")) as f:
        for line in f.read().splitlines()[1:]:
            name, _, x, y = line.split(",")
            if name == "after":
                errors.append((float(x), float(y)))
    return errors


def mean_and_scatter(errors):
    n = len(errors)
    mx = sum(e[0] for e in errors) / n
    my = sum(e[1] for e in errors) / n
    sd = math.sqrt(sum((e[0] - mx) ** 2 + (e[1] - my) ** 2 for e in errors) / (n - 1))
    rms = math.sqrt(sum(e[0] ** 2 + e[1] ** 2 for e in errors) / n)
    return (mx, my), sd, rms


def binomial_floor(n, p, alpha=0.025):
    """The smallest count k with P(X < k) <= alpha for X ~ Binomial(n, p): fewer than k successes
    say the coverage is below p."""
    cdf = 0.0
    for k in range(n + 1):
        term = math.comb(n, k) * p ** k * (1.0 - p) ** (n - k)
        if cdf + term > alpha:
            return k
        cdf += term
    return n


def study_one(a, work, k, doc):
    """Robot k's auto session, its factors and the oracle's driven over the unseen path: a row."""
    robot = os.path.join(work, "robot-%d.json" % k)
    with open(robot, "w") as f:
        json.dump(doc, f)
    store = os.path.join(work, "robot-%d.store" % k)
    oracle = os.path.join(work, "oracle-%d.store" % k)
    study_robots.oracle_store(a.bindir, doc, robot, oracle)
    best = stops(a.bindir, robot, oracle, a.runs, os.path.join(work, "o-%d" % k))
    mo, sd_o, rms_o = mean_and_scatter(best)
    # An owner who knows the robot's drift and asks for a share of it (the study knows it from
    # the oracle's runs; a session reports its estimate as sigma_random_mm).
    target = [] if a.target_share is None else [
        "--target", "%.3f" % max(0.5, a.target_share * sd_o)]
    out, err = run([a.bindir + "/odocal", "session", "--sim", robot, "--store", store,
                    "--seed", str(100 + k), "--procedure", "auto", "--yes", "--json",
                    "--out", os.path.join(work, "auto-%d" % k)] + target +
                   ([] if a.max_measurements is None else
                    ["--max-measurements", str(a.max_measurements)]))
    session = json.loads(out)
    last = session["result"]["precision"][-1]
    mine = stops(a.bindir, robot, store, a.runs, os.path.join(work, "v-%d" % k))
    m, sd, rms = mean_and_scatter(mine)
    systematic = math.hypot(m[0] - mo[0], m[1] - mo[1])
    allowed = 2.0 * math.sqrt(last["sigma_sys_mm"] ** 2 + (sd * sd + sd_o * sd_o) / a.runs)
    predicted = last["sigma_random_mm"]
    row = {
        "robot": doc,
        "measurements": session["measurements"],
        "target_met": session["result"]["target_met"],
        "target_mm": session["result"]["target_mm"],
        "sigma_sys_mm": last["sigma_sys_mm"],
        "sigma_random_mm": predicted,
        "systematic_mm": systematic,
        "systematic_allowed_mm": allowed,
        "systematic_ok": systematic <= allowed,
        "scatter_mm": sd,
        "scatter_ok": predicted > 0.0 and 0.5 <= sd / predicted <= 2.0,
        "unseen_rms_mm": rms,
        "oracle_rms_mm": rms_o,
        "ratio": rms / rms_o,
        "questioned": err.count("reading check questions"),
    }
    print("robot %2d (d %.0f b %.0f slip %.4f): %d meas, target %.1f mm %s, sys %.1f mm (said "
          "%.1f, allowed %.1f)%s, scatter %.1f mm (said %.1f)%s, %.2fx oracle%s"
          % (k, doc["wheel_diameter_mm"], doc["wheelbase_mm"], doc["slip_sigma"],
             row["measurements"], row["target_mm"], "met" if row["target_met"] else "not met",
             systematic, row["sigma_sys_mm"], allowed, "" if row["systematic_ok"] else " MISS",
             sd, predicted, "" if row["scatter_ok"] else " MISS", row["ratio"],
             "" if not row["questioned"] else ", %d readings questioned" % row["questioned"]),
          file=sys.stderr, flush=True)
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--robots", type=int, default=30)
    ap.add_argument("--seed", type=int, default=32, help="the generator's seed")
    ap.add_argument("--runs", type=int, default=10, help="unseen-path runs per robot and oracle")
    ap.add_argument("--only", type=int, default=None, help="run only robot K (the others generated)")
    ap.add_argument("--keep", default=None, help="write the sessions here and keep them")
    ap.add_argument("--max-measurements", type=int, default=None,
                    help="the sessions' budget (default: auto's own)")
    ap.add_argument("--target-share", type=float, default=None,
                    help="give each session --target this share of the robot's true drift (the "
                         "oracle's scatter on the unseen path; default: auto's own target)")
    ap.add_argument("--min-met", type=int, default=0,
                    help="with --check, fail when fewer sessions met their target")
    ap.add_argument("--jobs", type=int, default=1, help="robots studied side by side")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    robots = [generate_robot(rng) for _ in range(a.robots)]
    chosen = [k for k in range(a.robots) if a.only is None or k == a.only]
    with tempfile.TemporaryDirectory() as scratch:
        work = a.keep or scratch
        os.makedirs(work, exist_ok=True)
        # Each robot's sessions are independent processes: run them side by side, report in order.
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            rows = list(pool.map(lambda k: study_one(a, work, k, robots[k]), chosen))
    n = len(rows)
    floor = binomial_floor(n, 0.9)
    sys_ok = sum(r["systematic_ok"] for r in rows)
    scatter_ok = sum(r["scatter_ok"] for r in rows)
    met = [r["ratio"] for r in rows if r["target_met"]]
    questioned = sum(r["questioned"] for r in rows)
    failures = []
    if sys_ok < floor:
        failures.append("systematic within 2 sigma_sys in %d of %d sessions (at least %d needed)"
                        % (sys_ok, n, floor))
    if scatter_ok < floor:
        failures.append("scatter within 2x of sigma_random in %d of %d sessions (at least %d "
                        "needed)" % (scatter_ok, n, floor))
    if met and (statistics.median(met) > 1.3 or max(met) > 1.6):
        failures.append("sessions that met the target: median %.2fx, worst %.2fx of the oracle "
                        "(1.3x, 1.6x allowed)" % (statistics.median(met), max(met)))
    if len(met) < a.min_met:
        failures.append("%d sessions met their target (at least %d needed)"
                        % (len(met), a.min_met))
    if questioned:
        failures.append("%d correct readings questioned by the reading check" % questioned)
    counts = sorted(r["measurements"] for r in rows)
    summary = ("coverage_study: %d robots; systematic within 2 sigma_sys %d/%d, scatter within 2x "
               "of the prediction %d/%d (at least %d each); target met %d/%d%s; measurements "
               "median %d, 90th percentile %d, most %d; all sessions %.2fx of the oracle in the "
               "median, worst %.2fx; readings questioned %d"
               % (n, sys_ok, n, scatter_ok, n, floor, len(met), n,
                  ", median %.2fx, worst %.2fx of the oracle"
                  % (statistics.median(met), max(met)) if met else "",
                  statistics.median(counts), counts[min(n - 1, math.ceil(0.9 * n) - 1)],
                  counts[-1], statistics.median(r["ratio"] for r in rows),
                  max(r["ratio"] for r in rows), questioned))
    print(summary, file=sys.stderr)
    for f in failures:
        print("  FAIL: " + f, file=sys.stderr)
    if a.json:
        print(json.dumps({"rows": rows, "failures": failures}, indent=1))
    return 1 if a.check and failures else 0


if __name__ == "__main__":
    sys.exit(main())
