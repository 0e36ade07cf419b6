#!/usr/bin/env python3
"""report.html as a person sees it: sessions on robots of this test's own, each page rendered by
Debian's Chromium (headless, every network address refused) to a PNG, and checked for what a
person would notice: something from the network, a figure without units, a legend over the data,
a page that renders blank or cut short.

Usage: report_browser_test.py BIN_DIR WORK_DIR. Prints 'N passed, M failed'; exit 1 on a failure.
Chromium missing is a failure (toolchain/install-deps.sh installs it), not a skip.
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
WIDTH, HEIGHT = 1400, 6000

ROBOTS = {
    # A small robot with a wheel ratio and wheelbase off, and a tape of 2 mm.
    "small": {"wheel_diameter_mm": 42, "wheelbase_mm": 80, "true_left_diameter_mm": 42.1,
              "true_right_diameter_mm": 41.85, "true_wheelbase_mm": 81.5},
    # A wide robot whose arcs turn about another wheelbase than its turns in place.
    "wide": {"wheel_diameter_mm": 120, "wheelbase_mm": 400, "counts_per_rev": 2048,
             "true_left_diameter_mm": 119.6, "true_right_diameter_mm": 120.3,
             "true_wheelbase_mm": 407, "true_wheelbase_arc_mm": 412},
}

SESSIONS = [
    ("small", ["--procedure", "auto"]),
    ("wide", ["--procedure", "auto", "--side-m", "2.5"]),
    ("small", ["--procedure", "umbmark", "--runs", "2", "--passes", "2", "--side-m", "2"]),
    ("wide", ["--procedure", "lateral", "--runs", "4"]),
]

results = []


def check(name, ok, why=""):
    results.append(ok)
    print(("PASS " if ok else "FAIL ") + name + ("" if ok else ": " + why))


def png_pixels(path):
    """(width, height, rows of RGB(A) bytes) of an 8-bit RGB or RGBA PNG."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width, height, ctype = 8, b"", 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, ctype = struct.unpack(">IIBB", chunk[:10])
            assert depth == 8 and ctype in (2, 6), "unexpected PNG format"
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + length
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, bpp, rows


def numbers(text):
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", text)]


def data_points(group):
    """Every coordinate a data element draws at (polyline points, path moves, circles, rects)."""
    points = []
    for m in re.finditer(r'points="([^"]*)"', group):
        v = numbers(m.group(1))
        points += list(zip(v[0::2], v[1::2]))
    for m in re.finditer(r'd="M(-?[\d.]+) (-?[\d.]+)', group):
        points.append((float(m.group(1)), float(m.group(2))))
    for m in re.finditer(r'cx="(-?[\d.]+)" cy="(-?[\d.]+)"', group):
        points.append((float(m.group(1)), float(m.group(2))))
    for m in re.finditer(r'<rect x="(-?[\d.]+)" y="(-?[\d.]+)" width="8"', group):
        points.append((float(m.group(1)) + 4, float(m.group(2)) + 4))
    return points


def legend_boxes(group):
    """Boxes (x0, y0, x1, y1) of each legend entry: its swatch and its text (11 px type)."""
    boxes = []
    for m in re.finditer(r'<text x="(-?[\d.]+)" y="(-?[\d.]+)" font-size="11">([^<]*)</text>',
                         group):
        x, y, text = float(m.group(1)), float(m.group(2)), m.group(3)
        boxes.append((x - 16, y - 10, x + 6.5 * len(text), y + 3))
    return boxes


def check_page(tag, html, out_dir):
    check(tag + ": no script, style sheet, font or picture from elsewhere",
          not re.search(r"<script|<link|@import|url\(|<img|<iframe|https?:|src=", html, re.I),
          "the page names something outside itself")
    svgs = re.findall(r"<svg.*?</svg>", html, re.S)
    check(tag + ": figures inline", len(svgs) >= 2, "%d <svg> elements" % len(svgs))
    for i, svg in enumerate(svgs):
        frames = len(re.findall(r'stroke="#444"/>', svg))
        units = len(re.findall(r">[^<]*\((?:mm|m|deg|s|mm/m)\)</text>", svg))
        check("%s: figure %d: every panel's axes say their unit" % (tag, i + 1),
              units >= 2 * frames, "%d panels, %d axis labels with a unit" % (frames, units))
        overlap = []
        # Panels are drawn one after the other: pair each panel's data with its legend.
        for data, legend in re.findall(
                r'<g class="data">(.*?)</g>\s*<g class="legend">(.*?)</g>', svg, re.S):
            pts = data_points(data)
            for box in legend_boxes(legend):
                overlap += [p for p in pts
                            if box[0] <= p[0] <= box[2] and box[1] <= p[1] <= box[3]]
        check("%s: figure %d: no legend over the data" % (tag, i + 1), not overlap,
              "%d data points under a legend, e.g. %s" % (len(overlap), overlap[:3]))
    # Chromium, offline: every host name resolves to nothing and no proxy is reachable.
    png = os.path.join(out_dir, "report.png")
    profile = os.path.join(out_dir, "chromium-profile")
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
           "--no-first-run", "--disable-background-networking", "--disable-component-update",
           "--disable-sync", "--user-data-dir=" + profile, "--hide-scrollbars",
           "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9",
           "--window-size=%d,%d" % (WIDTH, HEIGHT), "--screenshot=" + png,
           "file://" + os.path.join(out_dir, "report.html")]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    check(tag + ": Chromium renders the page to a PNG", p.returncode == 0 and os.path.exists(png),
          p.stderr[-500:])
    if not os.path.exists(png):
        return
    width, height, bpp, rows = png_pixels(png)
    check(tag + ": PNG of the window's size", (width, height) == (WIDTH, HEIGHT),
          "%dx%d" % (width, height))

    def inked(y0, y1):
        n = 0
        for row in rows[y0:y1]:
            for x in range(0, width * bpp, bpp * 4):
                if row[x] < 200 or row[x + 1] < 200 or row[x + 2] < 200:
                    n += 1
        return n / max(1, (y1 - y0) * width / 4)

    # A rendered page: ink in its first screen (title, table, first figure) and down to the
    # last figure, none of it a blank or an error page.
    bands = [inked(y, y + 400) for y in range(0, 1600, 400)]
    check(tag + ": the page's first 1600 px hold text and figures", min(bands) > 0.002,
          "ink per 400 px band: %s" % ["%.4f" % b for b in bands])
    shown = os.path.join(out_dir, "report.png")
    print("  (picture: %s)" % shown)


def check_evidence(tag, html, doc):
    """The readings' evidence: a row per calibration run with its measured and predicted stop,
    the headings of turns in place shown, and the unseen path before and after."""
    result = doc["result"]
    table = re.search(r'<table class="run-checks">(.*?)</table>', html, re.S)
    check(tag + ": the table of every run against the others", table is not None, "no table")
    if table is None:
        return
    rows = re.findall(r"<tr(?: class=\"warn\")?><td>(\d+)</td><td>([^<]*)</td>(.*?)</tr>",
                      table.group(1), re.S)
    calibration = [r for r in doc["runs"] if r["label"] in
                   ("line", "turns-ccw", "turns-cw", "arc-left", "arc-right")]
    check(tag + ": one row per calibration run", len(rows) == len(calibration),
          "%d rows, %d calibration runs" % (len(rows), len(calibration)))
    turns = [r for r in rows if r[1].startswith("turns")]
    shown = [r for r in turns if re.findall(r"<td>(-?[0-9.]+)</td>", r[2])[:1]]
    headings = [re.findall(r"<td>([^<]*)</td>", r[2]) for r in turns]
    check(tag + ": the turns in place show their measured and predicted headings",
          turns and all(len(h) >= 4 and h[1] not in ("", "&ndash;") and h[3] not in ("", "&ndash;")
                        for h in headings),
          "%d turns, cells %s" % (len(turns), headings[:2]))
    line = re.search(r'<p class="before-after">(.*?)</p>', html, re.S)
    check(tag + ": the unseen path before and after", line is not None, "no line")
    if line is not None:
        want = ["%.1f" % result["verify"]["before_rms_mm"], "%.1f" % result["verify"]["rms_mm"]]
        check(tag + ": the before/after line says the session's figures",
              all(w in line.group(1) for w in want), "%s not in %s" % (want, line.group(1)))


def main():
    bindir, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    check("Chromium is installed (toolchain/install-deps.sh)", CHROMIUM is not None,
          "no chromium on PATH")
    if CHROMIUM is None:
        print("report_browser_test: %d checks passed, %d failed" % (results.count(True), results.count(False)))
        return 1
    for n, (robot, args) in enumerate(SESSIONS):
        robot_file = os.path.join(work, robot + ".json")
        with open(robot_file, "w") as f:
            json.dump(ROBOTS[robot], f)
        out = os.path.join(work, "session-%d" % n)
        shutil.rmtree(out, ignore_errors=True)
        store = os.path.join(work, "store-%d" % n)
        if os.path.exists(store):
            os.remove(store)
        p = subprocess.run([os.path.join(bindir, "odocal"), "session", "--sim", robot_file,
                            "--store", store, "--seed", str(n + 3), "--yes", "--json", "--out",
                            out] + args, capture_output=True, text=True, timeout=600)
        tag = "%s %s" % (robot, " ".join(args))
        check(tag + ": session ends well", p.returncode == 0, p.stderr[-800:])
        page = os.path.join(out, "report.html")
        check(tag + ": report.html written", os.path.exists(page), "no " + page)
        if p.returncode != 0 or not os.path.exists(page):
            continue
        doc = json.loads(p.stdout)
        if args[1] == "auto":
            check(tag + ": at most 20 tape measurements (the default budget)",
                  doc["measurements"] <= 20,
                  "%d" % doc["measurements"])
        html = open(page, encoding="utf-8").read()
        if args[1] == "auto":
            check_evidence(tag, html, doc)
        check_page(tag, html, out)
    print("report_browser_test: %d checks passed, %d failed" % (results.count(True), results.count(False)))
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
