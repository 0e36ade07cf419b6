#!/usr/bin/env python3
"""Runs `odocal sim validate` over many seeds on the default robot and on a perfect one, and
prints per-floor medians of the unseen-path RMS of NC, CL, CB, OR and CF (docs/results.md,
"CL, CB, CF and OR").  Usage: validate-seeds.py [BIN_DIR] [SEEDS] [--robot FILE ...]"""
import json, os, statistics, subprocess, sys, tempfile

bin_dir = sys.argv[1] if len(sys.argv) > 1 else "build/host/bin"
seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 20
extra = sys.argv[3:]
odocal = os.path.join(bin_dir, "odocal")
perfect = {"true_left_diameter_mm": 60, "true_right_diameter_mm": 60, "true_wheelbase_mm": 150}
robots = [("default robot", None), ("perfect robot (true = nominal)", perfect)]
names = ("NC", "CL", "CB", "OR", "CF")
with tempfile.TemporaryDirectory() as tmp:
    for label, robot in robots:
        args = []
        if robot is not None:
            path = os.path.join(tmp, "robot.json")
            with open(path, "w") as f:
                json.dump(robot, f)
            args = ["--robot", path]
        rms = {floor: {n: [] for n in names} for floor in ("systematic", "bumps")}
        for seed in range(1, seeds + 1):
            out = subprocess.run([odocal, "sim", "validate", "--json", "--seed", str(seed)] + args + extra,
                                 capture_output=True, text=True, check=True).stdout
            v = json.loads(out)
            for floor in rms:
                for s in v[floor]["scenarios"]:
                    rms[floor][s["name"]].append(s["rms_mm"])
        print(f"## {label}, seeds 1-{seeds}: median unseen-path RMS, mm (p10-p90)")
        print("| floor | " + " | ".join(names) + " | CF/OR | CF/NC | CF<=CL seeds |")
        print("| --- " * (len(names) + 4) + "|")
        for floor, by in rms.items():
            cells = []
            for n in names:
                q = statistics.quantiles(by[n], n=10)
                cells.append(f"{statistics.median(by[n]):.1f} ({q[0]:.1f}-{q[-1]:.1f})")
            ratio_or = statistics.median([c / o for c, o in zip(by["CF"], by["OR"])])
            ratio_nc = statistics.median([c / o for c, o in zip(by["CF"], by["NC"])])
            wins = sum(c <= l for c, l in zip(by["CF"], by["CL"]))
            print(f"| {floor} | " + " | ".join(cells) +
                  f" | {ratio_or:.2f} | {ratio_nc:.2f} | {wins}/{seeds} |")
        print()
