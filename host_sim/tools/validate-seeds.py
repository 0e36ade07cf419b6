#!/usr/bin/env python3
"""Runs `odocal sim validate` over many seeds on the default robot and on a perfect one, and
prints, as a Markdown section of docs/results.md ("CL, CB, CF and OR"), per-floor medians of the
unseen-path RMS of NC, CL, CB, OR and CF and how well CF's fit found the true geometry; then the
fit's interval coverage and the split-data check, from the tests FitCoverage and FitSplit
(odocal_test_host_sim in BIN_DIR, about 5 minutes).
Usage: validate-seeds.py [BIN_DIR] [SEEDS] [EXTRA validate ARGS ...]"""
import json, math, os, re, statistics, subprocess, sys, tempfile

bin_dir = sys.argv[1] if len(sys.argv) > 1 else "build/host/bin"
seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 20
extra = sys.argv[3:]
odocal = os.path.join(bin_dir, "odocal")
perfect = {"true_left_diameter_mm": 60, "true_right_diameter_mm": 60, "true_wheelbase_mm": 150}
robots = [("default robot", None), ("perfect robot (true = nominal)", perfect)]
names = ("NC", "CL", "CB", "OR", "CF")
print(f"## CL, CB, CF and OR (`odocal sim validate`, seeds 1-{seeds})\n")
print("NC: nothing corrected (the firmware told the E_b-corrected wheelbase, as eq. 7 assumes); "
      "CL / CB: the paper's F_lat, F_lon (regression / bootstrap); OR: the firmware told the true "
      "wheel diameters and wheelbase; CF: `odocal fit` of the floor's 20 straight trials, 2 + 2 "
      "squares of 1 m and 4 + 4 turns in place of 5 turns, each measured only where it stopped. "
      "Five unseen-path runs per scenario and seed; the median over seeds of each scenario's RMS, "
      "with the 10th-90th percentile; CF/OR and CF/NC are medians of the per-seed ratios.\n")


def reflow(text, width=98):
    """Re-wraps the prose paragraphs and list items of `text` at `width` (numbers put in change
    the lines' lengths); headings, tables and code blocks are left as they are."""
    out = []
    for block in text.split("\n\n"):
        first = block.lstrip("\n")
        if first.startswith(("#", "|", "```")) or not first.strip():
            out.append(block)
            continue
        items, item = [], []
        for line in block.splitlines():
            if line.startswith("- ") and item:
                items.append(item)
                item = []
            item.append(line.strip())
        items.append(item)
        wrapped = []
        for words in (" ".join(i).replace(" %", "\u00a0%").split(" ") for i in items):
            indent = "  " if words[0] == "-" else ""
            line = ""
            for w in words:
                if line and len(line) + 1 + len(w) > width:
                    wrapped.append(line)
                    line = indent + w
                else:
                    line = w if not line else line + " " + w
            wrapped.append(line)
        lead = block[:len(block) - len(block.lstrip("\n"))]
        out.append(lead + "\n".join(wrapped).replace("\u00a0", " "))
    return "\n\n".join(out) + ("\n" if text.endswith("\n") else "")


def e1(x, digits=1):
    """2.4e-3, not 2.4e-03."""
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


fit_errors = []
all_rms, ratios = {}, {}
bump_seeds = []  # the default robot's bumps floor, seed by seed (bump_row)


def bump_row(seed, floor):
    """One seed of the bumps floor: per scenario the RMS, the mean end's distance from the goal
    (what a correction could still remove) and the runs' scatter about that mean (what it cannot)."""
    out = {"seed": seed}
    for s in floor["scenarios"]:
        runs = s["runs"]
        mx = statistics.mean(r["x_mm"] for r in runs)
        my = statistics.mean(r["y_mm"] for r in runs)
        sd = math.sqrt(sum((r["x_mm"] - mx) ** 2 + (r["y_mm"] - my) ** 2 for r in runs) /
                       (len(runs) - 1))
        out[s["name"]] = (s["rms_mm"], math.hypot(mx, my), sd, len(runs))
    return out

# The default robot (host_sim/src/sim/robot_file.cpp): D_L 59.91, D_R 60.03, b 151.5 mm.
true_left, true_right, true_b = 59.91, 60.03, 151.5
mismatch_pct = 100 * (true_right / true_left - 1)
bump_loss_fraction = None
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
            if robot is None:
                bump_seeds.append(bump_row(seed, v["bumps"]))
                cf = v["systematic"]["cf"]
                e_d = cf["wheel_diameter_right_mm"] / cf["wheel_diameter_left_mm"]
                fit_errors.append((abs(e_d / (true_right / true_left) - 1),
                                   abs(cf["wheelbase_mm"] / true_b - 1)))
                if bump_loss_fraction is None:  # ground travel a cable costs a wheel (make-results.sh)
                    r = 0.25 * (true_left + true_right)
                    c = 0.5 * v["bumps"]["bump_height_mm"]
                    lost = 2 * (r + c) * math.acos((r - c) / (r + c)) - 4 * math.sqrt(r * c)
                    bump_loss_fraction = lost / (v["bumps"]["bump_spacing_mm"] + lost)
        all_rms[label] = rms
        ratios[label] = {}
        print(f"### {label}: unseen-path RMS, mm, median (p10-p90)\n")
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
            ratios[label][floor] = (ratio_or, ratio_nc, wins)
            print(f"| {floor} | " + " | ".join(cells) +
                  f" | {ratio_or:.2f} | {ratio_nc:.2f} | {wins}/{seeds} |")
        print()
ed = sorted(e for e, _ in fit_errors)
wb = sorted(b for _, b in fit_errors)
print(f"CF's fit on the smooth floor, default robot: E_d = D_R/D_L within {statistics.median(ed):.1e} "
      f"(median; worst {ed[-1]:.1e}) and the wheelbase within {statistics.median(wb):.1e} "
      f"(worst {wb[-1]:.1e}) of the truth, relative.\n")

# The prose below cites the medians above; each claim is checked against them.
med = {label: {floor: {n: statistics.median(v) for n, v in by.items()} for floor, by in r.items()}
       for label, r in all_rms.items()}
d_sys, d_bumps = med["default robot"]["systematic"], med["default robot"]["bumps"]
p_sys, p_bumps = (med["perfect robot (true = nominal)"]["systematic"],
                  med["perfect robot (true = nominal)"]["bumps"])
cf_or = ratios["default robot"]["systematic"][0]
cf_nc_perfect = ratios["perfect robot (true = nominal)"]["systematic"][1]
bump_wins = ratios["default robot"]["bumps"][2]
loss = bump_loss_fraction
low, high = sorted((d_sys["CL"], d_sys["CB"]))
keep = f"about {low:.0f}" if round(low) == round(high) else f"{low:.0f}-{high:.0f}"
print(reflow(f"""### Why CF and OR land where they do

- **Smooth floor, robot with errors.** NC's error is the default robot's {mismatch_pct:.1f} % wheel mismatch
  bending every leg. CL and CB learn F_lat and F_lon from straight trials only, and eq. 7 applies
  F_lon to every turn too: F_lon, read from where straight trials stop (their stopping behaviour
  and noise), scales all of the unseen path's turning, so CL/CB keep {keep} mm (medians). CF estimates the geometry itself (the wheels' sizes and ratio from the lines, the
  wheelbase from the squares and the turns in place) so lines and turns each get their own
  correction: it lands at {d_sys['CF']:.1f} mm, {cf_or:.2f} times OR's {d_sys['OR']:.1f} mm (median of the per-seed ratios), OR being the best
  any geometric calibration can do.
- **Perfect robot.** There is nothing to correct, and CL/CB make it {p_sys['CL'] / p_sys['NC']:.1f} and {p_sys['CB'] / p_sys['NC']:.1f} times
  {"worse" if min(p_sys['CL'], p_sys['CB']) > p_sys['NC'] else "worse or better"} (medians; the F_lon effect above). CF's own error is what its fit leaves: the
  wheelbase to about {e1(statistics.median(wb), 0)} (the turns' measured headings, ±0.4° over 8 × 5 turns, and slip),
  a few tenths of a degree over the unseen path, hence CF/NC {cf_nc_perfect:.2f}.
- **Bumps.** Every cable costs each wheel {100 * loss:.1f} % of its ground travel, on lines and in turns
  alike. OR knows the wheels but not the floor, so it falls short everywhere ({d_bumps['OR']:.0f} mm); CF, fitted
  on the same floor, learns the floor-included (effective) diameters, {100 * loss:.1f} % smaller, as F_lon
  does. What is left is the random heading kick of each crossing, which no factor removes: CF
  ({d_bumps['CF']:.0f} mm) and CL/CB ({d_bumps['CL']:.0f} / {d_bumps['CB']:.0f} mm) {"are alike there" if max(d_bumps['CF'], d_bumps['CL'], d_bumps['CB']) < 1.3 * min(d_bumps['CF'], d_bumps['CL'], d_bumps['CB']) else "differ there"} (CF no worse than CL in {bump_wins} of
  {seeds} seeds).
- **Why this procedure.** Straight lines alone cannot give the wheelbase and closed loops alone
  cannot give the size (`odocal fit` refuses both); turns in place, measured by the heading they
  end at, give the wheelbase best for the robot time spent (0.4° over 1800° is 2e-4). Measured
  alternatives (24 seeds, before the path executor planned headings from the path's start, not
  regenerated): with squares only (2 + 2 of 2 m, no turns in place) CF/OR was 1.31 and CF/NC on
  the perfect robot 1.26, at the edge of the targets, where the turns in place gave about 1.1 for
  both then (now {cf_or:.2f} and {cf_nc_perfect:.2f}, the tables above).
"""))



def bumps_section(rows):
    """CF against CL on the bumps floor, seed by seed (issue 32: why the recommended fit lost to CL
    there after the path executor changed), and how far a median over 15 seeds moves by chance."""
    ratio = [r["CF"][0] / r["CL"][0] for r in rows]
    runs = rows[0]["CF"][3]
    print("### The bumps floor: CF against CL, seed by seed\n")
    print(f"Default robot, {len(rows)} seeds, {runs} unseen-path runs per scenario and seed. "
          "*Offset*: the mean end's distance from the goal (what a better correction could "
          "remove, plus the mean's own scatter, about scatter/sqrt(runs)); *scatter*: the runs' "
          "spread about their mean (RMS radius), which no factor removes.\n")
    print("| seed | CL RMS | CF RMS | CF/CL | CL offset | CF offset | OR offset | CL scatter | CF scatter |")
    print("| --- " * 9 + "|")
    for r, q in zip(rows, ratio):
        print(f"| {r['seed']} | {r['CL'][0]:.0f} | {r['CF'][0]:.0f} | {q:.2f} | {r['CL'][1]:.0f} | "
              f"{r['CF'][1]:.0f} | {r['OR'][1]:.0f} | {r['CL'][2]:.0f} | {r['CF'][2]:.0f} |")
    print()
    import random
    rng = random.Random(15)
    medians = sorted(statistics.median(rng.choices(ratio, k=15)) for _ in range(20000))
    lo, hi = medians[len(medians) // 20], medians[-len(medians) // 20]
    above = sum(m >= 1.14 for m in medians) / len(medians)
    log_sd = statistics.stdev(math.log(q) for q in ratio)
    off = {n: statistics.median(r[n][1] for r in rows) for n in ("CL", "CF", "OR", "NC")}
    sc = {n: statistics.median(r[n][2] for r in rows) for n in ("CL", "CF", "OR", "NC")}
    share = statistics.median((r["CF"][2] ** 2 * (runs - 1) / runs) / r["CF"][0] ** 2 for r in rows)
    noise_offset = sc["CF"] / math.sqrt(runs)
    print(reflow(f"""What the table shows: on the bumps floor every scenario, OR included, scatters by about
the same amount ({sc['CL']:.0f} mm CL, {sc['CF']:.0f} mm CF, {sc['OR']:.0f} mm OR, {sc['NC']:.0f} mm NC: medians), the random
heading kick of each cable crossing; scatter makes up {100 * share:.0f} % of CF's mean squared end error
(median over seeds). What a correction can still remove, the offset of the mean end, is {off['CF']:.0f} mm
for CF and {off['CL']:.0f} mm for CL (medians; OR {off['OR']:.0f} mm, NC {off['NC']:.0f} mm), and {runs} runs leave that mean unsure by
about {noise_offset:.0f} mm by themselves. So a seed's CF/CL compares two draws of the same scatter: it
spreads from {min(ratio):.2f} to {max(ratio):.2f} (the standard deviation of its logarithm {log_sd:.2f}), its median over
these {len(rows)} seeds is {statistics.median(ratio):.2f}, and the median of 15 seeds drawn from them lands between {lo:.2f} and
{hi:.2f} nine times in ten ({100 * above:.0f} % of such medians are 1.14 or more). The 1.14x reported for 15
seeds after the path executor began to plan headings from the path's start (commit 991959b),
against 0.96x before it, {"are both within that range" if lo <= 0.96 and 1.14 <= hi else "lie at or near the ends of that range"}: a difference the count of seeds makes, not the executor. Measured before
and after that commit on the same 40 seeds (a one-off experiment, not regenerated; `odocal sim
validate --seed 1..40`, the builds of d4378d3 and 3ad16b4): the median CF/CL was 0.94 before and
0.96 after (its first 15 seeds: 1.10 and 0.99), the seed-by-seed change of ln(CF/CL) averaged
+0.001 ± 0.052 (standard error), CF's median RMS went from 83.5 to 80.8 mm and CL's from 87.2
to 84.9 mm: no change beyond chance. What the bumps floor leaves is physics: the random heading
kick of each crossing, the same for every scenario, against which the corrections' own
differences are smaller than five runs can show.
"""))


bumps_section(bump_seeds)


def coverage(env, robots=None):
    """Runs FitCoverage (tests/host_sim/fit/fit_coverage_test.cpp) and returns its printed figures:
    per parameter (covered, n, mean half-width, RMS error, mean dof, median half-width), pooled."""
    run_env = dict(os.environ, **env)
    if robots is not None:
        run_env["ODOCAL_FIT_ROBOTS"] = str(robots)
    out = subprocess.run([os.path.join(bin_dir, "odocal_test_host_sim"),
                          "--gtest_filter=FitCoverage.*"], env=run_env, capture_output=True,
                         text=True).stdout
    per = {}
    for m in re.finditer(r"fit coverage: (\w+) +(\d+)/(\d+) = [0-9.]+; mean half-width ([0-9.e+-]+), "
                         r"RMS error ([0-9.e+-]+), mean dof ([0-9.]+); median half-width "
                         r"([0-9.e+-]+)", out):
        per[m.group(1)] = (int(m.group(2)), int(m.group(3)), float(m.group(4)), float(m.group(5)),
                           float(m.group(6)), float(m.group(7)))
    pooled = re.search(r"fit coverage: pooled (\d+)/(\d+)", out)
    if len(per) != 3 or pooled is None:
        sys.exit("validate-seeds.py: FitCoverage printed no figures (env %s):\n%s" % (env, out))
    return per, (int(pooled.group(1)), int(pooled.group(2)))


PARAMS = ("wheel_diameter_left_mm", "wheel_diameter_right_mm", "wheelbase_mm")
PARAM_NAMES = {"wheel_diameter_left_mm": "D_L", "wheel_diameter_right_mm": "D_R",
               "wheelbase_mm": "b"}


def pct(c, n):
    return 100.0 * c / n


def cell(c, n):
    p = c / n
    return f"{100 * p:.1f} % ± {100 * 1.96 * math.sqrt(p * (1 - p) / n):.1f}"


def row(label, figures):
    per, (all_c, all_n) = figures
    n = per[PARAMS[0]][1]
    return (f"| {label} | {n} | " + " | ".join(cell(per[k][0], per[k][1]) for k in PARAMS)
            + f" | {pct(all_c, all_n):.1f} % ({all_c}/{all_n}) |")


def three(figures):
    per, _ = figures
    return ", ".join(f"{pct(per[k][0], per[k][1]):.1f} %" for k in PARAMS)


default = coverage({}, 1000)
student = coverage({"ODOCAL_FIT_INTERVAL": "student-t"}, 1000)
percentile = coverage({"ODOCAL_FIT_INTERVAL": "percentile"}, 300)
cf_design = coverage({"ODOCAL_FIT_DESIGN_CF": "1"})
path_truth = coverage({"ODOCAL_FIT_PATH_TRUTH": "1"})
path_student = coverage({"ODOCAL_FIT_PATH_TRUTH": "1", "ODOCAL_FIT_INTERVAL": "student-t"})
n_test = cf_design[0][PARAMS[0]][1]
dp, bp = default[0], default[0]["wheelbase_mm"]
p_pooled = default[1][0] / default[1][1]
diam_hw = statistics.mean([dp[k][2] for k in PARAMS[:2]])
diam_rms = statistics.mean([dp[k][3] for k in PARAMS[:2]])
diam_dof = statistics.mean([dp[k][4] for k in PARAMS[:2]])
cfp = cf_design[0]
ptp, pts = path_truth[0], path_student[0]
pt_diam_hw = statistics.mean([ptp[k][2] for k in PARAMS[:2]])
pt_diam_rms = statistics.mean([ptp[k][3] for k in PARAMS[:2]])
pt_fails = [k for k in PARAMS if not ptp[k][2] < 2 * 1.96 * ptp[k][3]]
st_wider = all(ptp[k][0] >= pts[k][0] for k in PARAMS)
print(reflow(f"""### The fit's intervals

Test `FitCoverage.NinetyFivePercentIntervalsCoverTheTruthOfSimulatedRobots`
(tests/host_sim/fit/fit_coverage_test.cpp). Robot k (seeds k = 1 … N; simulator seed 1000003·k):
true diameters uniform within ±0.5 % of 60 mm, wheelbase within ±2 % of 150 mm, slip σ
2.5e-4 … 1e-3, measurement σ 1 … 3 mm and 0.2 … 0.6°, smooth floor. Each robot drives 4 lines of
1.5 m and 2 + 2 squares of 1 m, measured only where they stopped (8 runs: few runs, where a
bootstrap over runs is at its weakest), and is fitted with the defaults (B = 500, level 0.95).
Coverage of the three 95 % intervals, with the binomial 95 % confidence interval of each estimate
(± 1.96·sqrt(p(1 − p)/n)):

| intervals | robots | D_L | D_R | b | all three pooled |
| --- | --- | --- | --- | --- | --- |
{row("**default** (wild bootstrap-t, ends at least the Student-t's)", default)}
{row("Student t, CR2 standard error, Bell-McCaffrey dof", student)}
{row("percentile of refits, widened by sqrt(n/(n − 3)) (before)", percentile)}

(The pooled figures count three intervals per robot, which share its data: their binomial error is
between ±{100 * 1.96 * math.sqrt(p_pooled * (1 - p_pooled) / default[1][1]):.1f} % as {default[1][1]} independent intervals and ±{100 * 1.96 * math.sqrt(p_pooled * (1 - p_pooled) / dp[PARAMS[0]][1]):.1f} % as {dp[PARAMS[0]][1]}.) The mean half-width of the
default intervals was {e1(diam_hw)} (diameters) and {e1(bp[2])} (wheelbase) of each parameter against an RMS
error of {e1(diam_rms)} and {e1(bp[3])}: {"wider than ±1.96 RMS, as a Student t with about " + f"{diam_dof:.0f}" + " degrees of freedom (the mean Bell-McCaffrey dof: " + f"{diam_dof:.1f}" + " for the diameters, " + f"{bp[4]:.1f}" + " for the wheelbase) must be" if diam_hw > 1.96 * diam_rms else "not wider than ±1.96 RMS"}.
`ODOCAL_FIT_ROBOTS=1000 ODOCAL_FIT_INTERVAL=student-t|percentile odocal_test_host_sim
--gtest_filter='FitCoverage.*'` reproduces a row; the test itself runs {n_test} robots (10–20 s)
and fails if any parameter's coverage, or the pooled one, is more than three binomial standard
errors (as {n_test} intervals: {100 * 3 * math.sqrt(0.95 * 0.05 / n_test):.1f} %) from 95 %.

With the recommended procedure instead (`ODOCAL_FIT_DESIGN_CF=1`: 20 lines of 1.5 m, 2 + 2
squares of 1 m, 4 + 4 turns in place of 5 turns, all measured where they stopped; the first
{n_test} robots), the default intervals covered D_L, D_R, b {three(cf_design)} (pooled
{pct(*cf_design[1]):.1f} %, {cf_design[1][0]}/{cf_design[1][1]}; ± {100 * 1.96 * math.sqrt(0.95 * 0.05 / n_test):.1f} % per parameter), with about {statistics.mean(cfp[k][4] for k in PARAMS):.0f} degrees of freedom. The mean
half-widths, {e1(cfp[PARAMS[0]][2])}, {e1(cfp[PARAMS[1]][2])} and {e1(cfp[PARAMS[2]][2])} of each parameter, against RMS errors of {e1(cfp[PARAMS[0]][3])}, {e1(cfp[PARAMS[1]][3])} and {e1(cfp[PARAMS[2]][3])}, are
{", ".join(f"±{cfp[k][2] / cfp[k][3]:.1f}" for k in PARAMS)} RMS{": with enough runs the intervals are as narrow as the truth allows" if all(1.5 < cfp[k][2] / cfp[k][3] < 2.5 for k in PARAMS) else "; " + ", ".join(PARAM_NAMES[k] for k in PARAMS if cfp[k][2] / cfp[k][3] <= 1.5) + " narrower than ±1.96 RMS while still covering about 95 %: its errors have long tails (a few robots far off), which an RMS weighs heavily" if any(cfp[k][2] / cfp[k][3] <= 1.5 for k in PARAMS) else ""}.

With the exact truth along the path instead (motion capture, `ODOCAL_FIT_PATH_TRUTH=1`, the same
{n_test} robots, 8 whole runs as clusters), the default intervals covered D_L, D_R, b {three(path_truth)}
(pooled {pct(*path_truth[1]):.1f} %, {path_truth[1][0]}/{path_truth[1][1]}), the Student-t alone {three(path_student)} (pooled
{pct(*path_student[1]):.1f} %){": there the bootstrap-t's tails are the wider end, with the tape measure the Student t's, which is why the default takes the wider of the two" if st_wider else ""}. The wheelbase with motion capture: its mean half-width
is {e1(ptp['wheelbase_mm'][2])} (median {e1(ptp['wheelbase_mm'][5])}) against an RMS error of {e1(ptp['wheelbase_mm'][3])} (the Student t's {e1(pts['wheelbase_mm'][2])}), so the
test's "not twice ±1.96 RMS" check {("fails in that mode for " + ", ".join(PARAM_NAMES[k] for k in pt_fails)) if pt_fails else "holds in that mode too"}; the diameters' intervals ({e1(pt_diam_hw)}
against {e1(pt_diam_rms)}) {"are fine" if pt_diam_hw < 2 * 1.96 * pt_diam_rms else "are too wide as well"}.

Why the old intervals fell short: the wheel size is informed almost only by the 4 straight runs.
Resampling 8 runs gives a spread that matches the true one on average (RMS 4.3e-4 against 4.3e-4
in a diagnostic run of 100 robots with 2 m lines and 1.5 m squares, not regenerated) but that
varies from robot to robot like a variance estimated from 4 numbers: the estimate's error divided
by that spread had a standard deviation of 2.3–3.1 instead of 1, so a fixed ±1.96 (or any constant
widening) misses on the robots whose lines happen to agree. The wheelbase, informed by all the
squares, was covered {pct(percentile[0]['wheelbase_mm'][0], percentile[0]['wheelbase_mm'][1]):.0f} % of the time by those intervals. A studentized interval refers
the error to its own standard error, whose uncertainty the Bell-McCaffrey degrees of freedom
measure per parameter ({diam_dof:.1f} for the diameters here, {bp[4]:.1f} for the wheelbase); the runs are the
clusters (slip makes the rows of one run dependent). The unrestricted wild bootstrap-t alone is
known to be a little narrow with so few clusters (MacKinnon & Webb), hence the Student-t floor.
"""))

# Separate data sets of one robot (tests/host_sim/fit/fit_split_test.cpp).
out = subprocess.run([os.path.join(bin_dir, "odocal_test_host_sim"), "--gtest_filter=FitSplit.*"],
                     capture_output=True, text=True).stdout
split = {}
for m in re.finditer(r"fit split: (\w+) +([0-9.]+) / ([0-9.]+) mm \(truth ([0-9.]+)\): differ by "
                     r"([0-9.e+-]+); intervals \[([0-9.]+), ([0-9.]+)\] and \[([0-9.]+), "
                     r"([0-9.]+)\]", out):
    split[m.group(1)] = [float(m.group(i)) for i in range(2, 10)]
if len(split) != 3:
    sys.exit("validate-seeds.py: FitSplit printed no figures:\n" + out)
worst_split = max(abs(v[3]) for v in split.values())
print("""### Separate data sets of one robot

Test `FitSplit.SeparateMotionCaptureDataSetsOfOneRobotAgree`
(tests/host_sim/fit/fit_split_test.cpp): the default robot (seed 4242) drives 6 lines of 2 m, 4 +
4 squares of 1.5 m and 2 unseen paths, logged as a motion-capture system would: its own frame
(rotated 37°, shifted 1.3 m), UNIX time, 0.5 mm and 0.2° scatter on every row, 3 % of the rows and
one 2 s stretch per run without truth, the heading wrapped to ±180°, a second at rest before each
run. The runs alternate between two halves of 8, fitted apart (each scored on the other as
holdout):

| | half A | half B | A/B − 1 | truth |
| --- | --- | --- | --- | --- |""")
for key, label in (("wheel_diameter_left_mm", "D_L, mm"), ("wheel_diameter_right_mm", "D_R, mm"),
                   ("wheelbase_mm", "b, mm")):
    a, b, truth, diff, alo, ahi, blo, bhi = split[key]
    digits = 4 if key != "wheelbase_mm" else 3
    print(f"| {label} | {a:.{digits}f} [{alo:.{digits - 1}f}, {ahi:.{digits - 1}f}] | "
          f"{b:.{digits}f} [{blo:.{digits - 1}f}, {bhi:.{digits - 1}f}] | "
          f"{'+' if diff >= 0 else '-'}{e1(abs(diff))} | {truth:.{digits}f} |")
print(reflow(f"""
The halves agree within {e1(worst_split)}, {0.01 / worst_split:.0f} times inside the issue's 1 %; the test asserts 1 % and 2e-3
(each half within the issue's 1e-3 of the truth), and that the intervals of the two halves
overlap. With the capture's truth one row (20 ms) late in every run, the halves still agreed
within 5e-4, but both fitted the diameters about 1.1e-3 small (D_L 59.846 and 59.866 mm) and the
intervals no longer held the truth: a clock offset is a bias that splitting the data cannot show
(a one-off experiment before the path executor planned headings from the path's start, not a
test). On real logs expect more: a capture clock that lags the counts, markers off the wheel axis
or a floor that is not flat are not in the model (docs/calibration.md, *What to record*).

With motion capture of a hidden simulated robot (two lines and a square), the fit finds E_d within
1e-4 and the wheelbase within 1e-3 (test `FitSimulated.MotionCaptureOfAHiddenRobot...`).
"""))
