#!/usr/bin/env python3
"""Reference vectors for the signal crate's filter tests.

Writes filters.json beside this script: (b, a) of scipy.signal.butter / cheby2 for several
orders, cutoffs and sample rates, and scipy.signal.filtfilt outputs (default arguments) on a
noisy sine, a step, a chirp and a segment just longer than padlen.
Run: python3 make_reference.py  (needs numpy and scipy)
"""
import json
import os

import numpy as np
import scipy
from scipy import signal

rng = np.random.default_rng(20240503)

designs = []
for fs in (100.0, 200.0, 1000.0):
    for order in (1, 2, 3, 4, 5, 6, 8):
        for cutoff in (6.0, 10.0, 0.3 * fs):
            b, a = signal.butter(order, cutoff, btype="low", fs=fs)
            designs.append(dict(kind="butter", order=order, cutoff_hz=cutoff, atten_db=None,
                                fs=fs, b=b.tolist(), a=a.tolist()))
            for atten in (20.0, 40.0):
                b, a = signal.cheby2(order, atten, cutoff, btype="low", fs=fs)
                designs.append(dict(kind="cheby2", order=order, cutoff_hz=cutoff,
                                    atten_db=atten, fs=fs, b=b.tolist(), a=a.tolist()))

fs = 100.0
t = np.arange(400) / fs
signals = {
    "noisy_sine": 50.0 * np.sin(2 * np.pi * 1.3 * t) + 200.0 + rng.normal(0.0, 2.0, t.size),
    "step": np.where(t < 2.0, -30.0, 70.0),
    "chirp": 10.0 * signal.chirp(t, f0=0.5, t1=t[-1], f1=30.0),
}
cases = []
for order in (2, 4, 6, 8):
    for kind, atten in (("butter", None), ("cheby2", 40.0)):
        if kind == "butter":
            b, a = signal.butter(order, 6.0, fs=fs)
        else:
            b, a = signal.cheby2(order, atten, 10.0, fs=fs)
        cutoff = 6.0 if kind == "butter" else 10.0
        padlen = 3 * max(len(a), len(b))
        sigs = dict(signals)
        sigs["short"] = signals["noisy_sine"][: padlen + 1]
        for name, x in sigs.items():
            y = signal.filtfilt(b, a, x)
            cases.append(dict(kind=kind, order=order, cutoff_hz=cutoff, atten_db=atten, fs=fs,
                              signal=name, x=x.tolist(), y=y.tolist()))

out = dict(scipy_version=scipy.__version__, numpy_version=np.__version__,
           designs=designs, filtfilt=cases)
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "filters.json")
with open(path, "w") as f:
    json.dump(out, f, separators=(",", ":"))
print(f"wrote {path}: {len(designs)} designs, {len(cases)} filtfilt cases")
