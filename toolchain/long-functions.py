#!/usr/bin/env python3
"""Lists C++ functions longer than a limit (default 100 lines) and source files longer than
another (default 500 lines) in the project's own folders. A function is a brace block that opens
after a parameter list `)` (with const, override, noexcept, a trailing return type or a
constructor's initialiser list between) outside any other function. Exit 1 when any is found
(`--check`). Usage: long-functions.py [--functions N] [--files N] [--check] [DIR...]
"""
import argparse
import os
import re
import sys

FOLDERS = ["core", "hal", "firmware", "host_sim", "tests"]
EXTS = (".cpp", ".hpp", ".h", ".cc")


def strip(text):
    """Comments and string/char literals blanked, newlines kept."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            if m:
                end = text.find(")" + m.group(1) + '"', i)
                end = n if end < 0 else end + len(m.group(1)) + 2
                out.append(re.sub(r"[^\n]", " ", text[i:end]))
                i = end
            else:
                out.append(c)
                i += 1
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * (j - i - 1) + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


OPENER = re.compile(r"\)\s*(const|override|final|noexcept|mutable|&|\s)*(->[^{;]*)?\s*$|"
                    r"\)\s*:\s*[\w:<>,\s(){}.*&]*$")


def functions(path, text):
    s = strip(text)
    stack = []  # (is_function, start_line)
    found = []
    line = 1
    last = 0
    for i, c in enumerate(s):
        if c == "\n":
            line += 1
        elif c == "{":
            inside = any(f for f, _ in stack)
            head = s[last:i]
            is_fn = not inside and bool(OPENER.search(head)) and not re.search(
                r"\b(if|for|while|switch|catch)\s*\(", head.split(";")[-1].split("}")[-1])
            stack.append((is_fn, line))
            last = i + 1
        elif c == "}":
            if stack:
                is_fn, start = stack.pop()
                if is_fn:
                    name = re.findall(r"([~\w:]+)\s*\(", s[max(0, s.rfind(";", 0, i)):i])
                    found.append((line - start + 1, start, path))
            last = i + 1
        elif c == ";":
            last = i + 1
    return found


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dirs", nargs="*", default=FOLDERS)
    ap.add_argument("--functions", type=int, default=100)
    ap.add_argument("--files", type=int, default=500)
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    bad = 0
    for d in a.dirs:
        for dirpath, _, names in os.walk(os.path.join(root, d)):
            for name in sorted(names):
                if not name.endswith(EXTS):
                    continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root)
                text = open(path, encoding="utf-8", errors="replace").read()
                lines = text.count("\n")
                if lines > a.files:
                    print("%s: %d lines (file limit %d)" % (rel, lines, a.files))
                    bad += 1
                for length, start, _ in functions(rel, text):
                    if length > a.functions:
                        print("%s:%d: function of %d lines (limit %d)"
                              % (rel, start, length, a.functions))
                        bad += 1
    return 1 if a.check and bad else 0


if __name__ == "__main__":
    sys.exit(main())
