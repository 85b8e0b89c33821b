#!/usr/bin/env python3
"""Rewrites the "Every source file" section of docs/architecture.md from the sources: each
crate's files in the order of the flow, each in one line with its module doc's first
sentence, so the page names every file and says what the file itself says. With --check,
changes nothing and exits 1 when the page is out of date (a file added, moved or removed).

Usage: scripts/architecture_files.py [--check]
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
page = root / "docs/architecture.md"
ORDER = ["c3d", "repair", "kinetics", "gait", "bvh", "c3dfix", "show", "cli", "python",
         "evals", "forkpool", "testkit"]
HEADING = "## Every source file\n"


def first_sentence(f):
    doc = []
    for line in f.read_text().splitlines():
        if line.startswith("//!"):
            t = line[3:].strip()
            if not t:
                break
            doc.append(t)
        elif doc or line.strip():
            break
    s = " ".join(doc)
    m = re.match(r"(.+?\.)(\s|$)", s)
    s = m.group(1) if m else s
    if len(s) > 220:
        s = s[:217].rsplit(" ", 1)[0] + " …"
    return s or "(no module doc)"


files = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard",
                        "crates/*/src/*.rs", "crates/*/src/**/*.rs"],
                       cwd=root, capture_output=True, text=True, check=True).stdout.split()
by = {}
for f in sorted(set(files)):
    by.setdefault(f.split("/")[1], []).append(f)
crates = [c for c in ORDER if c in by] + sorted(c for c in by if c not in ORDER)
out = [HEADING]
for c in crates:
    out.append(f"\n### `crates/{c}`\n\n")
    for f in by[c]:
        out.append(f"- `{f.split('/src/', 1)[1]}`: {first_sentence(root / f)}\n")
text = page.read_text()
head = text[: text.index(HEADING)] if HEADING in text else text.rstrip("\n") + "\n\n"
new = head + "".join(out)
if "--check" in sys.argv:
    if new != text:
        print("docs/architecture.md does not list the sources as they are: run scripts/architecture_files.py", file=sys.stderr)
        sys.exit(1)
    sys.exit(0)
page.write_text(new)
