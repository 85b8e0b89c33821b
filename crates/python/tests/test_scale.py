"""Python at scale: trials that pickle and copy, a process forked after c3dfix ran, the
path-level functions against the command line, and a real Dask run with worker processes.

Each test uses the real corpora (skipped without them, unless CI is set) and asserts bytes.
"""

import copy
import multiprocessing
import os
import pickle
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import c3dfix
from test_c3dfix import cli, corpus_files, fullbody, readable

# A trial whose point data is large enough that reading and repairing it go parallel.
BIG = "sample_00/Codamotion/codamotion_gaitwands_20150204.c3d"


def samples():
    fs = corpus_files()
    if not fs:
        pytest.skip("no corpus")
    return fs


def with_points():
    """Corpus files that read and have points to repair."""
    return [f for f, c in readable(samples()) if c.labels]


def big_file():
    fs = [f for f in samples() if f.as_posix().endswith(BIG)]
    if not fs:
        pytest.skip(f"{BIG} not in the corpus")
    return fs[0]


def run_cli(*args):
    r = subprocess.run([str(cli()), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


def same_points(a, b):
    pa, pb = a.points, b.points
    return pa.shape == pb.shape and np.array_equal(pa, pb, equal_nan=True)


# 1. Pickling and copying.


def test_a_pickled_trial_writes_exactly_the_bytes_of_the_original(tmp_path):
    n = 0
    for f, c in readable(samples()):
        back = pickle.loads(pickle.dumps(c))
        assert back == c, f
        assert repr(back) == repr(c), f  # the path travels with the trial
        back.write(tmp_path / "back.c3d")
        assert (tmp_path / "back.c3d").read_bytes() == f.read_bytes(), f
        n += 1
    assert n >= 85, n


def test_an_edit_to_points_survives_pickling(tmp_path):
    f = big_file()
    c = c3dfix.read(f)
    p = c.points
    valid = np.argwhere(~np.isnan(p[:, :, 0]))
    fr, i = valid[len(valid) // 2]
    p[fr, i] += [1.5, -2.0, 0.25]
    p[0, 0] = np.nan
    c.points = p
    back = pickle.loads(pickle.dumps(c, protocol=pickle.HIGHEST_PROTOCOL))
    assert same_points(back, c)
    np.testing.assert_array_equal(back.points[fr, i], p[fr, i])
    assert np.isnan(back.points[0, 0]).all()
    c.write(tmp_path / "edited.c3d")
    back.write(tmp_path / "back.c3d")
    assert (tmp_path / "back.c3d").read_bytes() == (tmp_path / "edited.c3d").read_bytes()
    assert (tmp_path / "back.c3d").read_bytes() != f.read_bytes()


@pytest.mark.parametrize("how", [copy.copy, copy.deepcopy])
def test_copies_are_independent_trials(tmp_path, how):
    f = big_file()
    c = c3dfix.read(f)
    d = how(c)
    assert d == c and d is not c
    p = d.points
    p[10, 3] += 7.0
    d.points = p
    # The original is as read, value for value and byte for byte.
    assert same_points(c, c3dfix.read(f))
    c.write(tmp_path / "c.c3d")
    assert (tmp_path / "c.c3d").read_bytes() == f.read_bytes()
    assert d != c
    np.testing.assert_array_equal(d.points[10, 3], c.points[10, 3] + 7.0)
    # And the other way round.
    q = c.points
    q[20, 1] = np.nan
    c.points = q
    fresh = c3dfix.read(f)
    np.testing.assert_array_equal(d.points[20, 1], fresh.points[20, 1])
    np.testing.assert_array_equal(d.points[10, 3], fresh.points[10, 3] + 7.0)


def test_a_trial_rebuilt_from_bad_bytes_names_it():
    with pytest.raises(c3dfix.C3dError, match="walk.c3d"):
        c3dfix.C3d(b"\x00" * 100, "walk.c3d")


# 2. Fork safety.


def _repair_in_child(args):
    src, out = args
    return c3dfix.repair_file(src, out)["summary"]["filled"]


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # Python 3.12+: fork with threads
def test_workers_forked_after_c3dfix_ran_repair_normally(tmp_path):
    files = with_points()[:12] + [big_file()]
    # The parent reads and repairs first, so the library's thread pool exists before the fork.
    c = c3dfix.read(big_file())
    fixed, _ = c3dfix.repair(c)
    assert fixed != c
    want = {}
    for k, f in enumerate(files):
        out = tmp_path / f"parent-{k}.c3d"
        c3dfix.repair_file(f, out)
        want[k] = out.read_bytes()
    jobs = [(f, tmp_path / f"child-{k}.c3d") for k, f in enumerate(files)]
    pool = multiprocessing.get_context("fork").Pool(2)
    try:
        # A hang (the parent's pool waited on in a child) fails here instead of stalling CI.
        pool.map_async(_repair_in_child, jobs).get(timeout=120)
    finally:
        pool.terminate()
        pool.join()
    for k, (_, out) in enumerate(jobs):
        assert out.read_bytes() == want[k], files[k]


# 3. Path-level functions, against the command line.


REPAIR_OPTIONS = [
    ({}, []),
    (
        {"lowpass": "butterworth:4:6", "spikes": "hampel:5:3", "max_expected_error": None},
        ["--lowpass", "butterworth:4:6", "--spikes", "hampel:5:3", "--max-expected-error", "off"],
    ),
]


@pytest.mark.parametrize("py_opts,cli_opts", REPAIR_OPTIONS)
def test_repair_file_writes_the_commands_bytes_and_report(tmp_path, py_opts, cli_opts):
    import json

    out, report = tmp_path / "out.c3d", tmp_path / "report.json"
    files = with_points()
    # The defaults on every file; the other options on every third (they share the code).
    files = files if not py_opts else files[::3]
    n = 0
    for f in files:
        run_cli("repair", f, "-o", out, "--report", report, "--force", *cli_opts)
        want, want_report = out.read_bytes(), json.loads(report.read_text())
        out.unlink()
        report.unlink()
        got = c3dfix.repair_file(f, out, report=report, **py_opts)
        assert out.read_bytes() == want, f
        assert got == want_report, f
        assert json.loads(report.read_text()) == want_report, f
        n += 1
    assert n >= (80 if not py_opts else 26), n


def test_repair_file_in_place_with_backup_is_the_commands(tmp_path):
    f = big_file()
    a, b = tmp_path / "a.c3d", tmp_path / "b.c3d"
    a.write_bytes(f.read_bytes())
    b.write_bytes(f.read_bytes())
    run_cli("repair", a, "--in-place", "--backup")
    r = c3dfix.repair_file(b, in_place=True, backup=True)
    assert b.read_bytes() == a.read_bytes() != f.read_bytes()
    assert Path(str(b) + ".bak").read_bytes() == f.read_bytes()
    assert r["summary"]["backup"] == str(b) + ".bak"
    # A second repair in place keeps the first backup: the true original.
    c3dfix.repair_file(b, in_place=True, backup=True)
    assert Path(str(b) + ".bak").read_bytes() == f.read_bytes()


def test_repair_file_refuses_as_the_command_does(tmp_path):
    f = big_file()
    out = tmp_path / "out.c3d"
    out.write_bytes(b"keep")
    with pytest.raises(c3dfix.C3dError, match="out.c3d exists"):
        c3dfix.repair_file(f, out)
    assert out.read_bytes() == b"keep"
    c3dfix.repair_file(f, out, force=True)
    assert out.read_bytes()[:2] != b"ke"
    with pytest.raises(c3dfix.C3dError, match="device"):
        c3dfix.repair_file(f, "/dev/null", force=True)
    src = tmp_path / "in.c3d"
    src.write_bytes(f.read_bytes())
    with pytest.raises(c3dfix.C3dError, match="is the input file"):
        c3dfix.repair_file(src, tmp_path / "o2.c3d", report=src, force=True)
    with pytest.raises(c3dfix.C3dError, match="in.c3d: backup goes with in-place"):
        c3dfix.repair_file(src, tmp_path / "o3.c3d", backup=True)
    with pytest.raises(c3dfix.C3dError, match="in.c3d: give either an output file or in-place"):
        c3dfix.repair_file(src, tmp_path / "o4.c3d", in_place=True)
    with pytest.raises(c3dfix.C3dError, match="in.c3d: give an output file or in-place"):
        c3dfix.repair_file(src)
    with pytest.raises(c3dfix.C3dError, match="in.c3d: .*unknown fill method|in.c3d: .*fill"):
        c3dfix.repair_file(src, tmp_path / "o5.c3d", fill="magic")
    with pytest.raises(c3dfix.C3dError, match="missing.c3d"):
        c3dfix.repair_file(tmp_path / "missing.c3d", tmp_path / "o6.c3d")
    bad = tmp_path / "bad.c3d"
    bad.write_bytes(b"\x02\x50" + b"\x00" * 300)
    with pytest.raises(c3dfix.C3dError, match="bad.c3d"):
        c3dfix.repair_file(bad, tmp_path / "o7.c3d")
    # Nothing was written by the refused calls, nor left behind.
    assert src.read_bytes() == f.read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.c3d", "in.c3d", "out.c3d"]


CONVERSIONS = [
    ({"processor": "dec", "format": "int"}, ["--processor", "dec", "--format", "int"]),
    ({"processor": "sgi", "format": "float"}, ["--processor", "sgi", "--format", "float"]),
    ({"format": "float"}, ["--format", "float"]),
]


@pytest.mark.parametrize("py_opts,cli_opts", CONVERSIONS)
def test_convert_file_writes_the_commands_bytes(tmp_path, py_opts, cli_opts):
    out = tmp_path / "out.c3d"
    n = 0
    for f, _ in readable(samples()):
        r = subprocess.run(
            [str(cli()), "convert", str(f), "-o", str(out), "--force", *cli_opts],
            capture_output=True,
            text=True,
        )
        if r.returncode != 0:
            # A file the command cannot convert is refused here too, naming it.
            with pytest.raises(c3dfix.C3dError, match=str(f.name)):
                c3dfix.convert_file(f, out, force=True, **py_opts)
            continue
        want = out.read_bytes()
        out.unlink()
        got = c3dfix.convert_file(f, out, **py_opts)
        assert out.read_bytes() == want, f
        assert got["bytes"] == len(want) and got["unchanged"] is False
        n += 1
    assert n >= 80, n


def test_convert_file_in_place_leaves_a_file_already_so(tmp_path):
    f = big_file()
    a = tmp_path / "a.c3d"
    a.write_bytes(f.read_bytes())
    before = a.stat().st_mtime_ns
    r = c3dfix.convert_file(a, in_place=True)
    assert r["unchanged"] is True and a.stat().st_mtime_ns == before
    r = c3dfix.convert_file(a, in_place=True, backup=True, processor="sgi")
    assert r["processor"] == "SGI/MIPS" and r["backup"] == str(a) + ".bak"
    assert Path(r["backup"]).read_bytes() == f.read_bytes()
    assert same_points(c3dfix.read(a), c3dfix.read(f))
    with pytest.raises(c3dfix.C3dError, match="a.c3d: unknown processor"):
        c3dfix.convert_file(a, in_place=True, processor="cray")
    with pytest.raises(c3dfix.C3dError, match="a.c3d: scale"):
        c3dfix.convert_file(a, tmp_path / "b.c3d", format="int", scale=-1.0)
    with pytest.raises(c3dfix.C3dError, match="exists"):
        c3dfix.convert_file(a, a.with_suffix(".c3d.bak"))


def test_repair_file_releases_the_gil(tmp_path):
    path = fullbody("03_rolling.c3d")
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    start = time.perf_counter()
    try:
        c3dfix.repair_file(path, tmp_path / "o.c3d", lowpass="butterworth:4:6")
    finally:
        took = time.perf_counter() - start
        done.set()
        t.join()
    gaps = np.diff(ticks)
    assert took > 0.05
    assert gaps.max() < took / 2, (took, gaps.max())


# 4. A real distributed run: Dask, worker processes.


def dask_client():
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        if os.environ.get("CI", "") not in ("", "0", "false"):
            raise AssertionError("CI needs dask[distributed] (tests/all.sh installs it)")
        pytest.skip("dask[distributed] is not installed (pip install 'dask[distributed]')")
    cluster = LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    )
    return cluster, Client(cluster, timeout=60)


def test_dask_workers_repair_the_corpus_as_the_command_does(tmp_path):
    files = with_points()
    cluster, client = dask_client()
    try:
        outs = [tmp_path / f"dask-{k}.c3d" for k in range(len(files))]
        futures = client.map(c3dfix.repair_file, files, outs, pure=False)
        reports = client.gather(futures, errors="raise")
        # A trial read in a worker comes back equal to a local read (and keeps its path).
        back = client.submit(c3dfix.read, big_file()).result(timeout=120)
        local = c3dfix.read(big_file())
        assert back == local and repr(back) == repr(local)
        assert same_points(back, local)
    finally:
        client.close()
        cluster.close()
    assert len(reports) == len(files)
    cli_out = tmp_path / "cli.c3d"
    for f, out, r in zip(files, outs, reports):
        run_cli("repair", f, "-o", cli_out, "--force")
        assert out.read_bytes() == cli_out.read_bytes(), f
        assert r["file"] == str(f)


# 5. The wheel.


def test_the_package_under_test_is_the_installed_abi3_wheel():
    import importlib.metadata as md
    import json

    d = md.distribution("c3dfix")
    assert "site-packages" in Path(c3dfix.__file__).parts, c3dfix.__file__
    assert "Tag: cp39-abi3-" in (d.read_text("WHEEL") or "")
    url = d.read_text("direct_url.json")
    if url:
        assert not json.loads(url).get("dir_info", {}).get("editable", False), url
