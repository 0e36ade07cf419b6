#!/usr/bin/env python3
"""No tape measure (issue 48): `odocal session --procedure auto --truth walls` on mice this script
generates at random (wheels 24-45 mm, wheelbase 60-100 mm, each true wheel within 0.5 % of the
nominal, the true wheelbase within 3 %, wall-sensor gains 1 +- 20 % drawn from a seed of their own,
slip from the default to 3 times it), each in the practice maze, with no tape reading at all. Then
the unseen path (judged by the simulator's truth: `odocal session --procedure verify`, the
robot file's tape noise set to 0) driven RUNS times with the factors it saved and RUNS times with
the true geometry in force (the oracle, the same seed).

Checks (--check):
- every session took 0 tape measurements and says result.truth "walls";
- the unseen path within MAX_MEDIAN (1.3x) of the oracle in the median over the mice, and
  MAX_WORST (1.6x) at worst;
- with --coverage: the stated precision covers what the factors leave: the mean end of the
  calibrated robot's runs minus the oracle's within 2 sqrt(sigma_sys^2 + (sd^2 + sd_o^2) / RUNS)
  in at least 90 % of the sessions (failed only when the count is below what 90 % coverage gives
  with probability 2.5 %, one-sided binomial), as coverage_study.py checks the tape's sessions.

It also reports the walls' own error against the simulator's truth per reading kind (each run's
stop, x along the run, y across it, heading; result.walls.against_simulator of each session).

With --no-ratio the ratio is reported, not checked (the smoke test: one mouse, the contract).

Usage: walls_study.py BIN_DIR [--mice N] [--seed S] [--runs N] [--coverage] [--no-ratio]
       [--check] [--json]
"""
import argparse
import concurrent.futures
import json
import math
import os
import random
import statistics
import sys
import tempfile

import coverage_study
import study_robots

MAX_MEDIAN = 1.3
MAX_WORST = 1.6


def generate_mouse(rng):
    """A mouse within the issue's ranges."""
    d = round(rng.uniform(24.0, 45.0), 1)
    b = round(rng.uniform(60.0, 100.0), 1)
    return {
        "wheel_diameter_mm": d,
        "wheelbase_mm": b,
        "counts_per_rev": rng.choice([512, 1024, 1440, 2048]),
        "true_left_diameter_mm": round(d * (1.0 + rng.uniform(-0.005, 0.005)), 3),
        "true_right_diameter_mm": round(d * (1.0 + rng.uniform(-0.005, 0.005)), 3),
        "true_wheelbase_mm": round(b * (1.0 + rng.uniform(-0.03, 0.03)), 2),
        "slip_sigma": round(0.0005 * math.exp(rng.uniform(0.0, math.log(3.0))), 6),
        "wall_sensor_seed": rng.randrange(1, 1 << 30),
        "measure_sigma_mm": 0,
    }


def study_one(a, work, k, doc):
    robot = os.path.join(work, "mouse-%d.json" % k)
    with open(robot, "w") as f:
        json.dump(doc, f)
    store = os.path.join(work, "mouse-%d.store" % k)
    oracle = os.path.join(work, "oracle-%d.store" % k)
    study_robots.oracle_store(a.bindir, doc, robot, oracle)
    best = coverage_study.stops(a.bindir, robot, oracle, a.runs, os.path.join(work, "o-%d" % k))
    mo, sd_o, rms_o = coverage_study.mean_and_scatter(best)
    out, _ = coverage_study.run([a.bindir + "/odocal", "session", "--sim", robot, "--store", store,
                                 "--seed", str(200 + k), "--procedure", "auto", "--truth", "walls",
                                 "--yes", "--json", "--out", os.path.join(work, "walls-%d" % k)]
                                + ([] if a.max_runs is None else
                                   ["--max-measurements", str(a.max_runs)]))
    session = json.loads(out)
    result = session["result"]
    last = result["precision"][-1]
    mine = coverage_study.stops(a.bindir, robot, store, a.runs, os.path.join(work, "v-%d" % k))
    m, sd, rms = coverage_study.mean_and_scatter(mine)
    systematic = math.hypot(m[0] - mo[0], m[1] - mo[1])
    allowed = 2.0 * math.sqrt(last["sigma_sys_mm"] ** 2 + (sd * sd + sd_o * sd_o) / a.runs)
    row = {
        "mouse": doc,
        "measurements": session["measurements"],
        "truth": result.get("truth"),
        "saved": session["saved"],
        "runs": len(session["runs"]),
        "sigma_sys_mm": last["sigma_sys_mm"],
        "systematic_mm": systematic,
        "systematic_allowed_mm": allowed,
        "systematic_ok": systematic <= allowed,
        "unseen_rms_mm": rms,
        "oracle_rms_mm": rms_o,
        "ratio": rms / rms_o,
        "walls_verify_rms_mm": (result.get("verify") or {}).get("rms_mm"),
        "against_simulator": result["walls"].get("against_simulator", {}),
        "errors": [l["simulator"] for l in result["walls"]["looks"] if "simulator" in l],
    }
    print("mouse %2d (d %.1f b %.1f slip %.5f): %d tape readings, %d runs, unseen %.2f mm "
          "(oracle %.2f): %.2fx; sys %.2f mm (said %.2f, allowed %.2f)%s"
          % (k, doc["wheel_diameter_mm"], doc["wheelbase_mm"], doc["slip_sigma"],
             row["measurements"], row["runs"], rms, rms_o, row["ratio"], systematic,
             row["sigma_sys_mm"], allowed, "" if row["systematic_ok"] else " MISS"),
          file=sys.stderr, flush=True)
    return row


def error_table(rows):
    """The walls' error against the simulator per reading kind, over every run of every mouse."""
    table = {}
    for kind, key in (("stop x (along the run)", "error_x_mm"),
                      ("stop y (across the run)", "error_y_mm"),
                      ("stop heading", "error_theta_deg")):
        values = [e[key] for r in rows for e in r["errors"]]
        n = len(values)
        mean = sum(values) / n
        table[kind] = {
            "unit": "deg" if key.endswith("deg") else "mm",
            "n": n,
            "mean": mean,
            "sd": math.sqrt(sum((v - mean) ** 2 for v in values) / max(n - 1, 1)),
            "max_abs": max(abs(v) for v in values),
        }
    return table


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--mice", type=int, default=3)
    ap.add_argument("--seed", type=int, default=48, help="the generator's seed")
    ap.add_argument("--runs", type=int, default=8, help="unseen-path runs per mouse and oracle")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--max-runs", type=int, default=None,
                    help="the sessions' --max-measurements (with the walls: runs; default auto's)")
    ap.add_argument("--coverage", action="store_true", help="check the stated precision's coverage")
    ap.add_argument("--no-ratio", action="store_true",
                    help="with --check, leave the unseen path's ratio to the oracle unchecked")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    mice = [generate_mouse(rng) for _ in range(a.mice)]
    with tempfile.TemporaryDirectory() as work:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            rows = list(pool.map(lambda k: study_one(a, work, k, mice[k]), range(a.mice)))
    ratios = [r["ratio"] for r in rows]
    n = len(rows)
    floor = coverage_study.binomial_floor(n, 0.9)
    covered = sum(r["systematic_ok"] for r in rows)
    table = error_table(rows)
    print("walls_study: %d mice, 0 tape readings in %d; unseen path %.2fx of the oracle in the "
          "median, worst %.2fx; stated precision covers the systematic error in %d/%d (at least "
          "%d for 90 %%)" % (n, sum(r["measurements"] == 0 for r in rows),
                             statistics.median(ratios), max(ratios), covered, n, floor),
          file=sys.stderr)
    for kind, t in table.items():
        print("  walls vs simulator, %s: n %d, mean %+.3f %s, sd %.3f, max %.3f"
              % (kind, t["n"], t["mean"], t["unit"], t["sd"], t["max_abs"]), file=sys.stderr)
    if a.json:
        print(json.dumps({"mice": rows, "error_per_kind": table}, indent=1))
    failures = []
    if any(r["measurements"] != 0 or r["truth"] != "walls" or not r["saved"] for r in rows):
        failures.append("a session took tape readings, did not say truth walls or did not save: "
                        "%s" % [(r["measurements"], r["truth"], r["saved"]) for r in rows])
    if not a.no_ratio and (statistics.median(ratios) > MAX_MEDIAN or max(ratios) > MAX_WORST):
        failures.append("unseen path %.2fx (median) / %.2fx (worst) of the oracle; %gx / %gx "
                        "allowed" % (statistics.median(ratios), max(ratios), MAX_MEDIAN,
                                     MAX_WORST))
    if a.coverage and covered < floor:
        failures.append("stated precision covers the systematic error in %d of %d sessions "
                        "(at least %d needed)" % (covered, n, floor))
    for f in failures:
        print("FAIL: " + f, file=sys.stderr)
    return 1 if a.check and failures else 0


if __name__ == "__main__":
    sys.exit(main())
