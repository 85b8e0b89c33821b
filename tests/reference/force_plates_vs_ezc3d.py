#!/usr/bin/env python3
"""Compare force_plates.py's outputs with ezc3d's platform extraction, file by file.

Usage (needs numpy and ezc3d): force_plates_vs_ezc3d.py DIR... > table.txt
For every plate of types 1-4 both readers compute, prints the max abs differences of force,
moment, COP and free moment over all analog samples (COP and free moment only where both are
finite), the samples where only one of them has a COP, and ezc3d's ORIGIN beside ours.
The findings are written up in force_plates_vs_ezc3d.md.
"""

import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import force_plates as fp  # noqa: E402

import ezc3d  # noqa: E402


def maxdiff(a, b, both_finite=False):
    if a.shape != b.shape:
        return f"shape {a.shape} vs {b.shape}"
    d = np.abs(a - b)
    if both_finite:
        d = d[np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)]
    if d.size == 0:
        return "-"
    return f"{np.nanmax(d):.3g}"


def main():
    warnings.simplefilter("ignore")
    for d in sys.argv[1:]:
        parent = os.path.dirname(os.path.abspath(d))
        for root, _, files in sorted(os.walk(d)):
            for name in sorted(files):
                if not name.lower().endswith(".c3d"):
                    continue
                path = os.path.join(root, name)
                rel = os.path.relpath(path, parent)
                try:
                    r = fp.compute_file(path, False, full=True)
                except Exception as e:  # noqa: BLE001
                    r = {"error": str(e)}
                if r is None:
                    continue
                if "error" in r:
                    print(f"{rel}\tours: error {r['error']}")
                    continue
                try:
                    c = ezc3d.c3d(path, extract_forceplat_data=True)
                    plats = c["data"]["platform"]
                except Exception as e:  # noqa: BLE001
                    print(f"{rel}\tezc3d: error {str(e)[:120]}")
                    continue
                for k, P in enumerate(r["plates"]):
                    tag = f"{rel}\tP{P['index']}\ttype {P['type']}"
                    if "_arrays" not in P:
                        print(f"{tag}\tours: {P.get('refused') or P.get('error')}")
                        continue
                    if k >= len(plats):
                        print(f"{tag}\tezc3d: no platform {k + 1}")
                        continue
                    A, E = P["_arrays"], plats[k]
                    ef = E["force"].T
                    em = E["moment"].T
                    ec = E["center_of_pressure"].T
                    et = E["Tz"].T
                    if ef.shape != A["force"].shape:
                        print(f"{tag}\tsamples ours {A['force'].shape[0]} ezc3d {ef.shape[0]}")
                        continue
                    ours_cop = np.isfinite(A["cop"]).all(axis=1)
                    loaded = np.abs(A["F_plate"][:, 2]) >= fp.LOADED_FZ
                    ez_cop = np.isfinite(ec).all(axis=1)
                    print(
                        f"{tag}\tforce {maxdiff(A['force'], ef)}"
                        f"\tmoment {maxdiff(A['moment'], em)}"
                        f"\tcop {maxdiff(A['cop'], ec, True)}"
                        f"\tcop@|Fz|>=100 {maxdiff(A['cop'][loaded], ec[loaded], True)}"
                        f"\tfree {maxdiff(A['free_moment'], et, True)}"
                        f"\tcop only ours {int((ours_cop & ~ez_cop).sum())}"
                        f" only ezc3d {int((~ours_cop & ez_cop).sum())}"
                        f"\tpeak|Fz| {P['peak_fz']}"
                        f"\torigin ours {np.round(A['origin'], 4).tolist()}"
                        f" ezc3d {np.round(np.asarray(E['origin'], float), 4).tolist()}"
                        f"\tunits ezc3d {E['unit_force']},{E['unit_moment']},{E['unit_position']}"
                    )


if __name__ == "__main__":
    main()
