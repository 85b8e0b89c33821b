#!/usr/bin/env python3
"""Where a costly candidate of `auto` pays (docs/price.md, issue 35): the cells of
`fill_eval` of a variant run against a base run of the same gaps, and the expected-error
calibration of the variant's gaps.

- BASE: records of `fill_eval --methods auto --records` with the shipped code;
- VARIANT: records of the same command with one candidate left out (the temporary
  `C3DFIX_KALMAN_FROM` / `C3DFIX_WIDE_FROM` switches of the ablation build, set past
  every length).

Gaps are paired by trial, marker run, length, marker and first frame (as
`scripts/cheap_rule.py` pairs them). A variant "from L frames" takes the variant's gaps
below L and the base's from L on, so every threshold follows from the two records.
Cells are `fill_eval`'s: set x markers (1, 2-3) x length, the mean of the gaps' mean errors.

Usage: scripts/ablation_cells.py BASE VARIANT tuned|held
"""
import collections
import sys


# One reading of the records, keyed to pair the same gaps across runs (a path or several,
# comma-separated).
from cheap_rule import calibration as cheap_calibration  # noqa: E402
from cheap_rule import load  # noqa: E402


def cells(rows):
    c = collections.defaultdict(list)
    for r in rows:
        c[(r["set"], r["group"], r["gap"]["gap_len"])].append(r["gap"]["mean"])
    return {k: (sum(v) / len(v), len(v)) for k, v in c.items()}


def calibration(rows):
    """`cheap_rule.calibration` over records: each gap's mean error against its estimate."""
    return cheap_calibration((r["gap"]["mean"], r["gap"].get("expected")) for r in rows)


def main():
    base, var = load(sys.argv[1]), load(sys.argv[2])
    part = sys.argv[3] if len(sys.argv) > 3 else "tuned"
    keys = sorted(k for k in var if k in base and base[k][part])
    lengths = sorted({k[2] for k in keys})
    b = cells(base[k] for k in keys)
    w, o = calibration(base[k] for k in keys)
    print(f"{part}: {len(keys)} paired gaps; base {w:.1f} % within 2x, {o:.1f} % over twice")
    for start in lengths + [None]:
        label = "never" if start is None else f"from {start}"
        rows = [var[k] if start is None or k[2] < start else base[k] for k in keys]
        v = cells(rows)
        w, o = calibration(rows)
        worst = max((v[c][0] / b[c][0] - 1) * 100 for c in b)
        print(f"\n{label}: worst cell {worst:+.1f} %, {w:.1f} % within 2x, {o:.1f} % over twice")
        for c in sorted(b):
            print(f"  {c[0]:9} {'one' if c[1] == 1 else '2-3':3} {c[2]:3}  n={b[c][1]:4}  "
                  f"{b[c][0]:7.3f} -> {v[c][0]:7.3f} mm  {(v[c][0] / b[c][0] - 1) * 100:+6.1f} %")


if __name__ == "__main__":
    main()
