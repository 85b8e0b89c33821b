#!/usr/bin/env python3
"""Lists the functions of the workspace's Rust sources longer than a limit (default 120
lines), longest first, outside test modules and generated files: what issue 46 asks to keep
short enough to hold in the head.

Usage: scripts/long_functions.py [LIMIT] [PATH...]   (PATH default: crates)
"""
import pathlib
import re
import sys

limit = int(sys.argv[1]) if len(sys.argv) > 1 else 120
roots = [pathlib.Path(p) for p in sys.argv[2:]] or [pathlib.Path("crates")]
GENERATED = ("coefficients.rs",)
fn_re = re.compile(r"^(\s*)(?:pub(?:\([^)]*\))?\s+)?(?:const\s+)?(?:async\s+)?(?:unsafe\s+)?fn\s+(\w+)")

found = []
for root in roots:
    for f in sorted(root.rglob("*.rs")):
        if "target" in f.parts or f.name in GENERATED:
            continue
        lines = f.read_text().splitlines()
        in_test = None
        i = 0
        while i < len(lines):
            line = lines[i]
            if re.match(r"\s*#\[cfg\(test\)\]", line):
                in_test = True
            m = fn_re.match(line)
            if m and not in_test:
                # The body runs from the first '{' to its matching '}' (strings and comments
                # are rare enough in signatures to ignore).
                depth, start, j, opened = 0, i, i, False
                while j < len(lines):
                    code = lines[j].split("//")[0]
                    depth += code.count("{") - code.count("}")
                    opened = opened or "{" in code
                    if opened and depth <= 0:
                        break
                    if not opened and code.rstrip().endswith(";"):
                        break
                    j += 1
                n = j - start + 1
                if opened and n > limit:
                    found.append((n, f"{f}:{start + 1}", m.group(2)))
                i = j + 1 if opened else i + 1
                continue
            if in_test and re.match(r"\s*mod\s+\w+\s*\{", line):
                # Skip the whole test module.
                depth, j = 0, i
                while j < len(lines):
                    code = lines[j].split("//")[0]
                    depth += code.count("{") - code.count("}")
                    if depth <= 0 and "{" in "".join(lines[i : j + 1]):
                        break
                    j += 1
                i = j + 1
                in_test = None
                continue
            if line.strip() and not line.strip().startswith("#") and not line.strip().startswith("//"):
                in_test = None if in_test and not re.match(r"\s*(pub\s+)?mod\b", line) else in_test
            i += 1

for n, where, name in sorted(found, reverse=True):
    print(f"{n:5d}  {name:32s} {where}")
print(f"{len(found)} functions over {limit} lines", file=sys.stderr)
