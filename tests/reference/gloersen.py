#!/usr/bin/env python3
"""Independent reference for Gløersen & Federolf's published PCA fill.

Gløersen Ø, Federolf P (2016) Predicting Missing Marker Trajectories in Human Motion Data
Using Marker Intercorrelations. PLOS ONE 11(3): e0152616 (strategy R2, the paper's defaults),
with the reconstruction of Federolf (2013), PLOS ONE 8(10): e78689, equation 1. Written from
the papers' text with numpy; no code is shared with c3dfix.

The algorithm, step by step (the names are the papers'):

1. The mean trajectory of the markers that have no gap anywhere is subtracted from every
   marker (a coordinate system moving with the subject).
2. Per marker with gaps (the target), its mean Euclidean distance to every marker is taken
   over the frames where both are recorded. Markers farther than DistalThreshold (0.5) times
   the mean of these distances (the target's own 0 included) and missing somewhere are set
   to zero; so is every marker missing on any frame where the target is missing.
3. The frames where no remaining marker is missing form N_no_gaps; N_zeros is the same with
   the target's columns set to zero, and M_zeros the frames to reconstruct with the target
   set to zero.
4. Each column is normalised by N_no_gaps's mean (N_zeros's mean for the zeroed matrices)
   and N_no_gaps's population standard deviation (1 where that is 0), and multiplied by the
   marker's weight exp(-d^2 / (2 sigma^2)), sigma = 200 mm, the target's weight being
   MMweight = 0.02.
5. PCA by the singular value decomposition of X / sqrt(n - 1) for both N_no_gaps and
   N_zeros; the number of components kept is the larger of the two counts at which the
   cumulative sum of singular values first reaches MinCumSV = 0.99 of their total.
6. T = PC_no_gaps' PC_zeros; reconstruction = M_zeros PC_zeros T PC_no_gaps'; the
   normalisation is undone with N_no_gaps's mean and deviation, and the mean trajectory is
   added back. This product, as published, changes with the signs of the singular vectors
   (T's off-diagonal terms), which an SVD leaves arbitrary; both here and in c3dfix each
   vector's largest component is made positive. On CMU and gait trials the sign choice
   moves a fill's mean error by under 0.2 mm. It also reads, through T, the vectors of
   zero singular values when the count reaches past a matrix's rank (N_zeros' target
   columns, an exact dependency among the kept markers), which are any within the null
   space: both here and in c3dfix those are set to 0.

Validity comes from `c3d_validity.py` beside this script (the manual's rule); coordinates
from ezc3d. Markers named by POINT:ANGLES, FORCES, MOMENTS, POWERS, SCALARS or REACTIONS
(model outputs) and markers never recorded are left out, as c3dfix's evaluation does.

Usage:
    gloersen.py > gloersen.json

Corpora are found through C3D_SAMPLES and C3D_FULLBODY (default ../shared/...). For every
case below it knocks the listed gaps out of the recorded data and prints the target's fill
on its knocked frames (mm, rounded to 1e-6) and the mean error against the recorded data.
"""

import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import c3d_validity  # noqa: E402

WEIGHT_SCALE = 200.0
MM_WEIGHT = 0.02
DISTAL_THRESHOLD = 0.5
MIN_CUM_SV = 0.99

# (corpus, file, target label, [(label, first frame, frames)...] knocked out; the first is
# the target's gap). Chosen where every knocked marker is recorded throughout its gap.
CASES = [
    ("fullbody", "85_02.c3d", "Male:RKNE", [("Male:RKNE", 300, 80), ("Male:RANK", 340, 30), ("Male:LKNE", 100, 50)]),
    ("fullbody", "85_02.c3d", "Male:LFWT", [("Male:LFWT", 500, 40)]),
    ("fullbody", "03_rolling.c3d", None, []),
    ("samples", "sample_00/Motion Analysis Corporation/Walk1.c3d", None, []),
]


def corpus_root(name):
    env = {"fullbody": "C3D_FULLBODY", "samples": "C3D_SAMPLES"}[name]
    here = os.path.dirname(os.path.abspath(__file__))
    default = os.path.join(here, "..", "..", "..", "shared", f"c3d-{name}")
    return os.environ.get(env, default)


def load(path):
    """(labels, xyz (frames, markers, 3) in mm, valid (frames, markers))."""
    import ezc3d

    c = ezc3d.c3d(path)
    pt = c["parameters"]["POINT"]
    labels = list(pt["LABELS"]["value"])
    outputs = set()
    for key in ("ANGLES", "FORCES", "MOMENTS", "POWERS", "SCALARS", "REACTIONS"):
        if key in pt:
            outputs.update(s.strip() for s in pt[key]["value"] if s.strip())
    units = pt["UNITS"]["value"][0].strip() if "UNITS" in pt else "mm"
    k = {"mm": 1.0, "cm": 10.0, "m": 1000.0}.get(units, 1.0)
    mask = np.array(c3d_validity.valid_mask(path)).T
    xyz = np.transpose(c["data"]["points"][:3], (2, 1, 0)).astype(np.float64) * k
    keep = [
        i
        for i, name in enumerate(labels)
        if name.strip() not in outputs and mask[:, i].any()
    ]
    return [labels[i].strip() for i in keep], xyz[:, keep, :], mask[:, keep]


def reconstruct(x, target, weights):
    """Fill the target's NaN rows of x (rows, 3*markers), target columns only."""
    cols = slice(3 * target, 3 * target + 3)
    gap_rows = np.isnan(x).any(axis=1)
    m_zeros = x.copy()
    m_zeros[:, cols] = 0.0
    n_no_gaps = x[~gap_rows]
    n_zeros = n_no_gaps.copy()
    n_zeros[:, cols] = 0.0
    mean_no = n_no_gaps.mean(axis=0)
    mean_zeros = n_zeros.mean(axis=0)
    sd = n_no_gaps.std(axis=0)
    sd[sd == 0] = 1.0
    w = np.repeat(weights, 3)
    m_zeros = (m_zeros - mean_zeros) / sd * w
    n_no_gaps = (n_no_gaps - mean_no) / sd * w
    n_zeros = (n_zeros - mean_zeros) / sd * w

    def pca(d):
        _, s, vt = np.linalg.svd(d / np.sqrt(d.shape[0] - 1), full_matrices=False)
        # The published product below depends on the singular vectors' signs (through T's
        # off-diagonal terms), which the SVD leaves arbitrary: each vector is turned so that
        # its largest component is positive, as c3dfix does, so that both compute the same.
        v = vt.T
        big = np.argmax(np.abs(v), axis=0)
        v = v * np.sign(v[big, np.arange(v.shape[1])])
        # Vectors of singular values at rounding level (eigenvalue s^2 under 1e-13 of the
        # largest) are any within the null space, and the product below reads them through
        # T: they are set to 0, as c3dfix does (docs/price.md, the rounding-sensitive gap).
        v[:, s**2 <= 1e-13 * s[0] ** 2] = 0.0
        return v, s

    pc_no, sv_no = pca(n_no_gaps)
    pc_z, sv_z = pca(n_zeros)
    count = max(
        int(np.argmax(np.cumsum(sv_no) >= MIN_CUM_SV * sv_no.sum())),
        int(np.argmax(np.cumsum(sv_z) >= MIN_CUM_SV * sv_z.sum())),
    ) + 1
    pc_no, pc_z = pc_no[:, :count], pc_z[:, :count]
    t = pc_no.T @ pc_z
    r = m_zeros @ pc_z @ t @ pc_no.T
    r = mean_no + r * sd / w
    return r[:, cols]


def fill_target(xyz, valid, target):
    """The target's fill on every frame where it is missing (frames x 3, NaN elsewhere)."""
    frames, markers, _ = xyz.shape
    data = xyz.copy()
    data[~valid] = np.nan
    complete = valid.all(axis=0)
    mean_trj = data[:, complete, :].mean(axis=1)
    b = data - mean_trj[:, None, :]
    diff = np.linalg.norm(b - b[:, target : target + 1, :], axis=2)
    dist = np.nanmean(diff, axis=0)
    thresh = DISTAL_THRESHOLD * np.mean(dist)
    zero = (dist > thresh) & ~complete
    missing = ~valid[:, target]
    zero |= (~valid[missing]).any(axis=0)
    zero[target] = False
    x = b.copy()
    x[:, zero, :] = 0.0
    x = x.reshape(frames, 3 * markers)
    rows_ok = ~np.isnan(x).any(axis=1)
    rows = np.concatenate([np.nonzero(rows_ok)[0], np.nonzero(missing)[0]])
    weights = np.exp(-(dist**2) / (2 * WEIGHT_SCALE**2))
    weights[target] = MM_WEIGHT
    rec = reconstruct(x[rows], target, weights)
    out = np.full((frames, 3), np.nan)
    out[np.nonzero(missing)[0]] = rec[rows_ok.sum() :] + mean_trj[missing]
    return out


def main():
    out = []
    for corpus, rel, target, knocks in CASES:
        path = os.path.join(corpus_root(corpus), rel)
        labels, xyz, valid = load(path)
        if target is None:
            # The marker with the most recorded frames among those with gaps of their own
            # (the markers recorded throughout make the mean trajectory), knocked out in
            # the middle of its longest recorded run.
            counts = np.where(valid.all(axis=0), -1, valid.sum(axis=0))
            t = int(np.argmax(counts))
            run, best, start = 0, (0, 0), 0
            for f in range(len(valid)):
                if valid[f, t]:
                    run += 1
                    if run > best[0]:
                        best = (run, f - run + 1)
                else:
                    run = 0
            length = min(40, best[0] // 3)
            start = best[1] + (best[0] - length) // 2
            target = labels[t]
            knocks = [(target, start, length)]
        knocked = valid.copy()
        for label, first, n in knocks:
            i = labels.index(label)
            assert valid[first : first + n, i].all(), (rel, label)
            knocked[first : first + n, i] = False
        ti = labels.index(target)
        fill = fill_target(xyz, knocked, ti)
        first, n = knocks[0][1], knocks[0][2]
        got = fill[first : first + n]
        err = np.linalg.norm(got - xyz[first : first + n, ti], axis=1).mean()
        out.append(
            {
                "corpus": corpus,
                "file": rel,
                "target": target,
                "knocked": [list(k) for k in knocks],
                "fill": [[round(float(v), 6) for v in p] for p in got],
                "mean_error_mm": round(float(err), 6),
            }
        )
    json.dump(out, sys.stdout, indent=0)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
