#!/usr/bin/env python3
"""Throughput: c3dfix.repair_file on a Dask LocalCluster of worker processes against
`c3dfix batch --jobs N`, on the same files in one run, with identical outputs checked.

Usage: python dask_vs_batch.py [--copies K] [--workers N] [--runs R] [--bin PATH]

The corpus (C3D_SAMPLES, C3D_EXTRA, C3D_FULLBODY as the tests find them) is copied K times
into a temporary folder, keeping the files that have points to repair. Each run repairs every
copy with the default options, batch into one output folder and Dask into another, alternating;
the best of R runs is printed as files/s. The cluster is started once, before the runs (its
start-up time is printed apart): workers are long-lived in a real deployment.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import c3dfix

ROOT = Path(__file__).resolve().parents[3]


def corpus():
    base = Path(os.environ.get("C3D_SAMPLES", ROOT / "../shared/c3d-samples"))
    dirs = [
        base,
        Path(os.environ.get("C3D_EXTRA", base / "../c3d-extra")),
        Path(os.environ.get("C3D_FULLBODY", base / "../c3d-fullbody")),
    ]
    files = []
    for d in dirs:
        if d.is_dir():
            files += sorted(p for p in d.rglob("*") if p.suffix.lower() == ".c3d")
    return files


def repairable(f):
    try:
        return bool(c3dfix.read(f).labels)
    except c3dfix.C3dError:
        return False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--bin", default=str(ROOT / "target/release/c3dfix"))
    a = ap.parse_args()
    from dask.distributed import Client, LocalCluster

    files = [f for f in corpus() if repairable(f)]
    if not files:
        sys.exit("no corpus found")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        src = tmp / "in"
        src.mkdir()
        inputs = []
        for k in range(a.copies):
            for i, f in enumerate(files):
                p = src / f"{k:03}-{i:03}-{f.name}"
                shutil.copyfile(f, p)
                inputs.append(p)
        mb = sum(p.stat().st_size for p in inputs) / 1e6
        print(f"{len(inputs)} files ({len(files)} corpus trials x {a.copies}), {mb:.0f} MB")
        start = time.perf_counter()
        cluster = LocalCluster(
            n_workers=a.workers, processes=True, threads_per_worker=1, dashboard_address=None
        )
        client = Client(cluster)
        print(f"Dask LocalCluster of {a.workers} processes started in {time.perf_counter() - start:.1f} s")
        best = {"batch": float("inf"), "dask": float("inf")}
        try:
            for r in range(a.runs):
                out = tmp / "batch"
                shutil.rmtree(out, ignore_errors=True)
                out.mkdir()
                t = time.perf_counter()
                subprocess.run(
                    [a.bin, "batch", str(src), "--out-dir", str(out), "--jobs", str(a.workers), "--json"],
                    check=True,
                    stdout=subprocess.DEVNULL,
                )
                best["batch"] = min(best["batch"], time.perf_counter() - t)
                dout = tmp / "dask"
                shutil.rmtree(dout, ignore_errors=True)
                dout.mkdir()
                outs = [dout / p.name for p in inputs]
                t = time.perf_counter()
                client.gather(client.map(c3dfix.repair_file, inputs, outs, pure=False))
                best["dask"] = min(best["dask"], time.perf_counter() - t)
            same = sum((out / p.name).read_bytes() == (dout / p.name).read_bytes() for p in inputs)
        finally:
            client.close()
            cluster.close()
    print(f"outputs byte-identical: {same} of {len(inputs)}")
    for k, label in [("batch", f"c3dfix batch --jobs {a.workers}"), ("dask", f"Dask {a.workers} processes, repair_file")]:
        print(f"{label:40} {best[k]:6.2f} s  {len(inputs) / best[k]:6.1f} files/s  (best of {a.runs})")


if __name__ == "__main__":
    main()
