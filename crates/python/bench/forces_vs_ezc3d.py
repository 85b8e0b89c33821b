#!/usr/bin/env python3
"""Force platforms: c3dfix.read(path).force_platforms() against
ezc3d.c3d(path, extract_forceplat_data=True), on the same trials in one run.

Both read the file and compute every plate's force, moment and centre of pressure.

Usage: python forces_vs_ezc3d.py FILE... (default: the corpus trials with plates of ../shared)
Prints, per file, the best of several runs of each and the ratio ezc3d / c3dfix.
"""

import sys
import time
import warnings
from pathlib import Path

import c3dfix
import ezc3d

DEFAULT = [
    "c3d-more/opensim-org__opensim-core__walking2.c3d",
    "c3d-more/keenon__nimblephysics__JA1Gait35.c3d",
    "c3d-more/qualisys__cgm2-web-report-uploader__FunctionalKnee_GaitFB2.c3d",
    "c3d-more/tsalemink__C3D-parser__AUC_CB_Dynamic0003.c3d",
    "c3d-extra/btkdata_Gait.c3d",
    "c3d-samples/sample_10/TYPE-4a.c3d",
]


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
        files = [root / f for f in DEFAULT if (root / f).exists()]
    warnings.simplefilter("ignore")  # plate warnings are not what is timed
    print(f"{'file':62} {'c3dfix ms':>10} {'ezc3d ms':>10} {'ratio':>7}")
    for f in files:
        c3dfix.read(f).force_platforms()
        ezc3d.c3d(str(f), extract_forceplat_data=True)
    for f in files:
        ours = best(lambda: c3dfix.read(f).force_platforms(), 20)
        theirs = best(lambda: ezc3d.c3d(str(f), extract_forceplat_data=True), 3)
        print(f"{f.name:62} {ours * 1e3:10.2f} {theirs * 1e3:10.1f} {theirs / ours:7.1f}")


if __name__ == "__main__":
    main()
