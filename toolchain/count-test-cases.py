#!/usr/bin/env python3
"""Test cases of one ctest run, as a user would count them: each GoogleTest case of a program that
wrote its XML report (GTEST_OUTPUT) and each other ctest entry (or a GoogleTest program that
wrote none, e.g. one that crashed) as one case.

Usage: count-test-cases.py CTEST_LOG XML_DIR [XML_DIR...]   prints "PASSED FAILED"
"""
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET

ENTRY = re.compile(r"^\s*\d+/\d+ Test\s+#\d+: (\S+) \.*\s*(.*?)\s+[\d.]+ sec\s*$")


def gtest_cases(path):
    """(passed, failed) of a GoogleTest XML report; skipped and disabled cases count neither."""
    root = ET.parse(path).getroot()
    passed = failed = 0
    for case in root.iter("testcase"):
        if case.get("status", "run") != "run" or case.get("result") == "skipped":
            continue
        if case.find("failure") is not None or case.find("error") is not None:
            failed += 1
        else:
            passed += 1
    return passed, failed


def program_of(name, reports):
    """The program an entry ran: its own name, or for an entry of one GoogleTest case
    (gtest_discover_tests, named PROGRAM.Suite.Case) the name before the first dot."""
    if name in reports:
        return name
    head = name.split(".", 1)[0]
    return head if head in reports else name


def main():
    log, xml_dirs = sys.argv[1], sys.argv[2:]
    reports = {}
    for path in [p for d in xml_dirs for p in glob.glob(os.path.join(d, "*.xml"))]:
        name = re.sub(r"(_\d+)?\.xml$", "", os.path.basename(path))
        reports.setdefault(name, []).append(path)
    # Every report counted once, however many entries ran its program.
    totals = {}
    for name, paths in reports.items():
        p = q = 0
        for path in paths:
            try:
                a, b = gtest_cases(path)
            except ET.ParseError:
                continue
            p, q = p + a, q + b
        totals[name] = (p, q)
    passed = failed = 0
    counted = set()
    with open(log, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = ENTRY.match(line)
            if not m:
                continue
            name, status = m.group(1), m.group(2)
            if "Skipped" in status:
                continue
            ok = status == "Passed"
            program = program_of(name, reports)
            if program not in totals:
                passed, failed = (passed + 1, failed) if ok else (passed, failed + 1)
                continue
            if program not in counted:
                counted.add(program)
                passed, failed = passed + totals[program][0], failed + totals[program][1]
            if not ok and totals[program][1] == 0:
                failed += 1  # the program failed after its cases (a crash at exit, a leak check)
    print(passed, failed)


if __name__ == "__main__":
    main()
