#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Fail when a function defined at namespace scope in a .cpp file under ROOT runs over LIMIT lines
(issue 27: "No function in solver/ is over 150 lines"; ../shared/STYLE.md: functions a reader can
hold in their head).

Usage: function_length.py ROOT [LIMIT]   (LIMIT default 150)

A light scanner, not a C++ parser: it strips comments and string literals, follows the braces, and
takes a brace opened at namespace depth after a closing parenthesis (a signature, with const,
noexcept, override, a trailing return type or a constructor's initialiser list) as a function
body. Lambdas and classes inside a function count toward the function. Prints each function over
the limit with its file, line and length; exits 1 if there is one.
"""
import os
import re
import sys

SIGNATURE_END = re.compile(r"\)\s*(const)?\s*(noexcept)?\s*(override)?\s*(->\s*[\w:<>,\s]+)?\s*$")


def clean(line):
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])'", "''", line)
    return re.sub(r"//.*", "", line)


def functions(path):
    """(first line, length, name) of each namespace-scope function body in the file."""
    lines = open(path, errors="ignore").read().split("\n")
    stack = []  # 'ns', 'fn' or 'block' per open brace
    start = None
    in_comment = False
    pending = ""  # code since the last ; { or } at namespace depth: the signature
    for i, raw in enumerate(lines):
        code = clean(raw)
        if in_comment:
            if "*/" not in code:
                continue
            code = code.split("*/", 1)[1]
            in_comment = False
        code = re.sub(r"/\*.*?\*/", "", code)
        if "/*" in code:
            code, in_comment = code.split("/*", 1)[0], True
        for ch in code:
            at_namespace = all(k == "ns" for k in stack)
            if ch == "{":
                head = pending.strip()
                if re.search(r"\bnamespace\b[^;{]*$", head) or re.search(r'extern\s+""\s*$', head):
                    kind = "ns"
                elif at_namespace and (SIGNATURE_END.search(head) or re.search(r"\)\s*:\s*.*$", head, re.S)):
                    kind = "fn"
                else:
                    kind = "block"
                if kind == "fn" and at_namespace:
                    start = i
                    m = re.findall(r"([\w:~]+)\s*\(", head)
                    name = m[0] if m else "?"
                stack.append(kind)
                pending = ""
            elif ch == "}":
                if stack:
                    kind = stack.pop()
                    if kind == "fn" and all(k == "ns" for k in stack) and start is not None:
                        yield start + 1, i - start + 1, name
                        start = None
                pending = ""
            elif ch == ";" and at_namespace:
                pending = ""
            elif at_namespace:
                pending += ch
        if all(k == "ns" for k in stack):
            pending += "\n"


def main():
    root = sys.argv[1]
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else 150
    long_ones = []
    for folder, _, files in os.walk(root):
        for f in sorted(files):
            if f.endswith(".cpp"):
                path = os.path.join(folder, f)
                long_ones += [(n, path, line, name) for line, n, name in functions(path) if n > limit]
    for n, path, line, name in sorted(long_ones, reverse=True):
        print(f"{path}:{line}: {name} runs {n} lines (limit {limit}): split it into named steps")
    if long_ones:
        return 1
    print(f"every function under {root} is at most {limit} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
