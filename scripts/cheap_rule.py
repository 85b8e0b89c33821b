#!/usr/bin/env python3
"""How the tried and not adopted `auto::CHEAP_ENOUGH_MM` rule was weighed (docs/price.md, "Tried and not adopted"): the cells of `fill_eval` under the
rule "the costly candidates are not weighed where the cheap ones' choice expects under TAU
mm", for a range of TAU, from two sets of records of the same gaps, without another run:

- FULL: records of a run that weighs every candidate (`fill_eval --records`, main's code);
- CHEAP: records of a run that never weighs the costly ones (a build with
  `CHEAP_ENOUGH_MM = f64::INFINITY`, `fill_eval --methods auto --records`).

Where the rule skips (the cheap run scored the gap and expected under TAU) the gap's record
is CHEAP's, elsewhere FULL's. Gaps are matched by trial, marker run, length, marker and
first frame (the gaps of `--gaps 10` are the first of `--gaps 30`, so runs of different
sizes match on the smaller). Cells are `fill_eval`'s: set x markers (1, 2-3) x length, the
mean of the gaps' mean errors; "within 2x" and "over twice" compare each gap's error with
its expected error.

Usage: scripts/cheap_rule.py FULL[,FULL...] CHEAP [tuned|held]
"""
import collections
import json
import sys


def load(paths):
    recs = {}
    for p in paths.split(","):
        for line in open(p):
            r = json.loads(line)
            g = r["gap"]
            if g["method"] == "auto":
                recs[(r["file"], r["run"], g["gap_len"], g["marker"], g["first"])] = r
    return recs


def cells(rows):
    c = collections.defaultdict(list)
    for r, err in rows:
        c[(r["set"], r["group"], r["gap"]["gap_len"])].append(err)
    return {k: sum(v) / len(v) for k, v in c.items()}


def calibration(pairs):
    n = within = over = 0
    for err, exp in pairs:
        if exp:
            n += 1
            within += 0.5 <= err / exp <= 2
            over += err / exp > 2
    return 100 * within / max(n, 1), 100 * over / max(n, 1)


def main():
    full, cheap = load(sys.argv[1]), load(sys.argv[2])
    part = sys.argv[3] if len(sys.argv) > 3 else "tuned"
    keys = [k for k in cheap if k in full and full[k][part]]
    base = cells([(full[k], full[k]["gap"]["mean"]) for k in keys])
    w, o = calibration([(full[k]["gap"]["mean"], full[k]["gap"].get("expected")) for k in keys])
    print(f"{part}: {len(keys)} gaps; every candidate: {w:.1f} % within 2x, {o:.1f} % over twice")
    for tau in [0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 1, 1.5, 2, 3, 5, float("inf")]:
        def used(k):
            g = cheap[k]["gap"]
            skip = g.get("scored") is not None and (g.get("expected") or 0) < tau
            return cheap[k] if skip else full[k]

        now = cells([(full[k], used(k)["gap"]["mean"]) for k in keys])
        worst = max((now[c] / base[c] - 1, c) for c in base)
        w, o = calibration([(used(k)["gap"]["mean"], used(k)["gap"].get("expected")) for k in keys])
        skipped = sum(used(k) is cheap[k] for k in keys)
        print(
            f"tau {tau:>5} mm: worst cell {100 * worst[0]:+5.1f} % {worst[1]}, "
            f"{w:.1f} % within 2x, {o:.1f} % over twice, costly skipped on "
            f"{100 * skipped / len(keys):.0f} % of the gaps"
        )


if __name__ == "__main__":
    main()
