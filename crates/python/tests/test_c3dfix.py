"""Tests of the installed c3dfix package on the shared corpora and the bundled samples.

The corpora are found as the Rust tests find them (C3D_SAMPLES, C3D_EXTRA, C3D_FULLBODY,
default ../shared/... beside the repository); without them those tests skip, unless CI is
set. The command-line binary (for comparisons with `c3dfix export`) is C3DFIX_BIN, default
target/release/c3dfix.
"""

import json
import os
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import c3dfix

ROOT = Path(__file__).resolve().parents[3]
SAMPLES = ROOT / "sample_c3d"


def corpus(var, default):
    d = Path(os.environ.get(var, default))
    if not d.is_absolute():
        d = ROOT / d
    if d.is_dir():
        return d
    if os.environ.get("CI", "") not in ("", "0", "false"):
        raise AssertionError(f"corpus {d} (from {var}) is missing and CI requires it")
    return None


def corpus_files():
    out = []
    samples = corpus("C3D_SAMPLES", "../shared/c3d-samples")
    base = samples.parent if samples else ROOT / "../shared"
    for d in (
        samples,
        corpus("C3D_EXTRA", str(base / "c3d-extra")),
        corpus("C3D_FULLBODY", str(base / "c3d-fullbody")),
    ):
        if d:
            out += sorted(p for p in d.rglob("*") if p.suffix.lower() == ".c3d")
    return out


def fullbody(name):
    d = corpus("C3D_FULLBODY", "../shared/c3d-fullbody")
    if d is None:
        pytest.skip("c3d-fullbody corpus not found")
    return d / name


def cli():
    b = Path(os.environ.get("C3DFIX_BIN", ROOT / "target/release/c3dfix"))
    if not b.exists():
        pytest.skip(f"{b} not built (cargo build --release)")
    return b


def readable(files):
    for f in files:
        try:
            yield f, c3dfix.read(f)
        except c3dfix.C3dError:
            assert f.stat().st_size == 0, f"{f} refused"


def test_points_and_missing_samples_match_the_command_line_export(tmp_path):
    files = corpus_files()
    if not files:
        pytest.skip("no corpus")
    out = tmp_path / "e.json"
    checked = 0
    for f, c in readable(files):
        if not c.labels:
            continue
        r = subprocess.run(
            [str(cli()), "export", str(f), "--format", "json", "-o", str(out), "--force"],
            capture_output=True,
            text=True,
        )
        assert r.returncode == 0, r.stderr
        e = json.loads(out.read_text())
        p = c.points
        assert p.shape == (e["frames"], len(e["markers"]), 3), f
        for i, m in enumerate(e["markers"]):
            assert m["label"] == c.labels[i]
            missing = np.array([v is None for v in m["xyz"]])
            assert (np.isnan(p[:, i, 0]) == missing).all(), f"{f}: {m['label']}"
            if (~missing).any():
                ref = np.array([v for v in m["xyz"] if v is not None], dtype=np.float32)
                assert (p[~missing, i, :].astype(np.float32) == ref).all(), f"{f}: {m['label']}"
            res = c.residuals[:, i]
            assert ((res < 0) == missing).all()
        rate = c.parameters.get("POINT", {}).get("RATE")
        if rate is not None and rate[0] > 0:
            assert rate[0] == pytest.approx(c.point_rate), f
        checked += 1
    assert checked >= 85, checked


def test_gaps_are_the_commands_and_the_missing_samples():
    files = corpus_files()
    if not files:
        pytest.skip("no corpus")
    checked = 0
    for f, c in readable(files):
        if not c.labels:
            continue
        gaps = c3dfix.gaps(f)
        r = subprocess.run([str(cli()), "gaps", "--json", str(f)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert gaps == json.loads(r.stdout)["gaps"], f
        # Each gap is a maximal run of NaN frames of its marker in the decoded points.
        p = c.points
        for g in gaps:
            if c.labels.count(g["label"]) != 1:
                continue
            i = c.labels.index(g["label"])
            a, b = g["first_frame"] - c.first_frame, g["last_frame"] - c.first_frame
            col = np.isnan(p[:, i, 0])
            assert col[a : b + 1].all(), f"{f}: {g}"
            assert a == 0 or not col[a - 1], f"{f}: {g}"
            assert b + 1 == len(col) or not col[b + 1], f"{f}: {g}"
            assert g["length"] == b - a + 1
        checked += 1
    assert checked >= 85, checked


def test_values_agree_with_ezc3d_where_it_reads_the_file_right():
    ezc3d = pytest.importorskip("ezc3d")
    files = [SAMPLES / "walk_int.c3d", SAMPLES / "walk_float.c3d"]
    samples = corpus("C3D_SAMPLES", "../shared/c3d-samples")
    if samples:
        files += [
            samples / "sample_01/Eb015pi.c3d",
            samples / "sample_01/Eb015pr.c3d",
            samples / "sample_06/newwalk.c3d",
            samples / "sample_09/PlugInC3D.c3d",
        ]
    for f in files:
        if not f.exists():
            continue
        ours = c3dfix.read(f)
        theirs = ezc3d.c3d(str(f))
        tp = np.transpose(theirs["data"]["points"][:3], (2, 1, 0))  # (frames, points, 3)
        assert tp.shape == ours.points.shape, f
        res = np.transpose(theirs["data"]["meta_points"]["residuals"][0], (1, 0))
        their_missing = res < 0
        our_missing = np.isnan(ours.points[:, :, 0])
        assert (their_missing == our_missing).all(), f
        ok = ~our_missing
        np.testing.assert_allclose(ours.points[ok], tp[ok], rtol=1e-6, atol=1e-4, err_msg=str(f))
        assert list(theirs["parameters"]["POINT"]["LABELS"]["value"])[: len(ours.labels)] == ours.labels
        assert theirs["parameters"]["POINT"]["RATE"]["value"][0] == pytest.approx(ours.point_rate)
        if ours.analog.size:
            ta = theirs["data"]["analogs"][0].T  # (samples, channels)
            np.testing.assert_allclose(ours.analog, ta, rtol=1e-5, atol=1e-6, err_msg=str(f))


def test_the_vicon_spelling_of_missing_reads_as_nan():
    c = c3dfix.read(fullbody("03_rolling.c3d"))
    assert np.isnan(c.points[:, :, 0]).sum() == 35965
    assert c.point_rate == 175.0
    assert c.parameters["POINT"]["RATE"][0] == 175.0
    assert len(c.labels) == 68


def test_unchanged_write_is_byte_identical(tmp_path):
    files = corpus_files() + [SAMPLES / "walk_int.c3d"]
    n = 0
    for f, c in readable(files):
        out = tmp_path / "same.c3d"
        c.write(out)
        assert out.read_bytes() == f.read_bytes(), f
        n += 1
    assert n >= 1


def _sample_bytes(c_path, frame, point):
    """The byte range of one point sample, from the header (float or int, Intel)."""
    b = Path(c_path).read_bytes()
    import struct

    npts = struct.unpack_from("<H", b, 2)[0]
    analog = struct.unpack_from("<H", b, 4)[0]
    scale = struct.unpack_from("<f", b, 12)[0]
    start = (struct.unpack_from("<H", b, 16)[0] - 1) * 512
    word = 4 if scale < 0 else 2
    frame_bytes = (4 * npts + analog) * word
    at = start + frame * frame_bytes + point * 4 * word
    return at, at + 4 * word


def test_editing_one_sample_changes_exactly_that_sample(tmp_path):
    src = SAMPLES / "walk_float.c3d"
    c = c3dfix.read(src)
    p = c.points
    f, i = 100, 3
    assert not np.isnan(p[f, i]).any()
    p[f, i] += [1.5, -2.0, 0.25]
    c.points = p
    out = tmp_path / "edited.c3d"
    c.write(out)
    a, b = src.read_bytes(), out.read_bytes()
    lo, hi = _sample_bytes(src, f, i)
    diff = [k for k in range(len(a)) if a[k] != b[k]]
    assert diff and all(lo <= k < hi for k in diff), (diff[:5], lo, hi)
    back = c3dfix.read(out)
    np.testing.assert_array_equal(np.isnan(back.points), np.isnan(c3dfix.read(src).points))
    assert back.residuals[f, i] == 0.0
    assert back.camera_masks[f, i] == 0
    np.testing.assert_allclose(back.points[f, i], p[f, i], rtol=1e-6)
    others = np.ones(back.residuals.shape, bool)
    others[f, i] = False
    np.testing.assert_array_equal(back.residuals[others], c3dfix.read(src).residuals[others])


def test_a_sample_set_to_nan_is_written_as_missing(tmp_path):
    c = c3dfix.read(SAMPLES / "walk_int.c3d")
    p = c.points
    p[10, 0] = np.nan
    c.points = p
    out = tmp_path / "nan.c3d"
    c.write(out)
    back = c3dfix.read(out)
    assert np.isnan(back.points[10, 0]).all()
    assert back.residuals[10, 0] == -1
    with pytest.raises(c3dfix.C3dError):
        c.points = p[:, :2]


def test_repair_fills_a_knocked_out_gap(tmp_path):
    truth = c3dfix.read(fullbody("85_02.c3d"))
    p = truth.points
    assert not np.isnan(p).any()
    m = truth.labels.index(truth.labels[5])
    holed = p.copy()
    holed[300:320, m] = np.nan
    c = c3dfix.read(fullbody("85_02.c3d"))
    c.points = holed
    fixed, report = c3dfix.repair(c, fill="auto")
    assert report["summary"]["gaps"] == 1 and report["summary"]["filled"] == 1
    got = fixed.points[300:320, m]
    assert not np.isnan(got).any()
    err = np.linalg.norm(got - p[300:320, m], axis=1).mean()
    assert err < 10.0, err  # mm
    assert (fixed.residuals[300:320, m] == 0).all()
    # The input is left as it was.
    assert np.isnan(c.points[300:320, m]).all()
    out = tmp_path / "fixed.c3d"
    fixed.write(out)
    assert not np.isnan(c3dfix.read(out).points[300:320, m]).any()


def test_repair_options_are_checked_as_on_the_command_line():
    c = c3dfix.read(SAMPLES / "walk_int.c3d")
    with pytest.raises(c3dfix.C3dError, match="unknown fill method"):
        c3dfix.repair(c, fill="magic")
    with pytest.raises(c3dfix.C3dError, match="half window"):
        c3dfix.repair(c, spikes="hampel:1000000000")
    with pytest.raises(c3dfix.C3dError, match="no marker"):
        c3dfix.repair(c, markers=["NOPE"])
    _, report = c3dfix.repair(c, fill="pca", lowpass="butterworth:4:6")
    assert report["summary"]["segments_filtered"] > 0


def test_swaps_finds_and_repair_undoes_an_injected_swap(tmp_path):
    path = SAMPLES / "walk_float.c3d"
    src = c3dfix.read(path)
    assert c3dfix.swaps(src)["swaps"] == []
    a, b = src.labels.index("LASI"), src.labels.index("LPSI")
    # The two markers' stored samples exchanged over frames 151-170 of the file, residual
    # words and camera masks with them (a sample edited through .points would be marked
    # computed, residual 0, and computed samples are no evidence).
    raw = bytearray(path.read_bytes())
    for f in range(150, 170):
        (pa, qa), (pb, qb) = _sample_bytes(path, f, a), _sample_bytes(path, f, b)
        raw[pa:qa], raw[pb:qb] = raw[pb:qb], raw[pa:qa]
    swapped = tmp_path / "swapped.c3d"
    swapped.write_bytes(bytes(raw))
    c = c3dfix.read(swapped)
    found = c3dfix.swaps(c)
    assert [(x["kind"], x["markers"], x["first_frame"], x["last_frame"], x["settled"])
            for x in found["swaps"]] == [("swap", ["LASI", "LPSI"], 151, 170, True)]
    # Reported by default, changed only with swaps="fix": exchanged back exactly.
    same, report = c3dfix.repair(c, fill="none")
    assert report["swaps"][0]["action"] == "reported"
    np.testing.assert_array_equal(same.points, c.points)
    fixed, report = c3dfix.repair(c, fill="none", swaps="fix")
    assert report["swaps"][0]["action"] == "undone"
    assert report["summary"]["swaps_undone"] == 1
    np.testing.assert_array_equal(fixed.points, src.points)
    np.testing.assert_array_equal(fixed.residuals, src.residuals)
    np.testing.assert_array_equal(fixed.camera_masks, src.camera_masks)
    with pytest.raises(c3dfix.C3dError, match="expected fix, report or off"):
        c3dfix.repair(c, swaps="undo")


def test_bad_input_raises_c3derror_with_file_section_and_offset(tmp_path):
    bad = tmp_path / "bad.c3d"
    good = (SAMPLES / "walk_int.c3d").read_bytes()
    bad.write_bytes(good[: len(good) // 2])
    with pytest.raises(c3dfix.C3dError) as e:
        c3dfix.read(bad)
    msg = str(e.value)
    assert "bad.c3d" in msg and "data section" in msg and "byte" in msg
    assert isinstance(e.value, ValueError)
    with pytest.raises(c3dfix.C3dError, match="no_such_file"):
        c3dfix.read(tmp_path / "no_such_file.c3d")
    (tmp_path / "junk.c3d").write_bytes(b"\x00" * 1000)
    with pytest.raises(c3dfix.C3dError, match="not a C3D file"):
        c3dfix.read(tmp_path / "junk.c3d")


def test_evaluate_is_the_commands():
    r = c3dfix.evaluate([SAMPLES / "walk_int.c3d"], gap_lengths=[10], methods=["linear", "pca"], gaps_per_length=5)
    assert {p["method"] for p in r["pooled"]} == {"linear", "pca"}
    assert r["files"][0]["units"] == "mm"


def _longest_pause_while(work):
    """Run `work` in a thread; return how long it took and the longest pause of this thread."""
    done = threading.Event()
    took = []

    def run():
        t = time.perf_counter()
        work()
        took.append(time.perf_counter() - t)
        done.set()

    th = threading.Thread(target=run)
    last = time.perf_counter()
    longest = 0.0
    th.start()
    while not done.is_set():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
        sum(range(200))
    th.join()
    return took[0], longest


def test_the_gil_is_released_while_repairing_and_reading():
    c = c3dfix.read(fullbody("03_rolling.c3d"))
    took, pause = _longest_pause_while(lambda: c3dfix.repair(c, fill="auto", lowpass="butterworth:4:6"))
    # Held for the whole repair, this thread would stall for about `took`.
    assert took > 0.05
    assert pause < took / 2, (took, pause)
    path = fullbody("03_rolling.c3d")
    took, pause = _longest_pause_while(lambda: [c3dfix.read(path) for _ in range(20)])
    assert pause < took / 2, (took, pause)


def test_repair_defaults_agree_everywhere():
    """repair and repair_file default to the library's RepairOptions::default() (read from
    the extension), in their signatures and in the stub, keyword by keyword."""
    import ast
    import inspect

    from c3dfix._c3dfix import _repair_defaults

    want = _repair_defaults()
    assert want["fill"] == "auto" and want["max_gap"] == 200
    stub = ast.parse((Path(c3dfix.__file__).parent / "__init__.pyi").read_text())
    stubbed = {}
    for node in stub.body:
        if isinstance(node, ast.FunctionDef) and node.name in ("repair", "repair_file"):
            a = node.args
            pos = a.posonlyargs + a.args
            named = list(zip(pos[len(pos) - len(a.defaults):], a.defaults))
            named += [(k, d) for k, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None]
            stubbed[node.name] = {k.arg: ast.literal_eval(d) for k, d in named}
    for f in (c3dfix.repair, c3dfix.repair_file):
        params = inspect.signature(f).parameters
        for key, value in want.items():
            assert params[key].default == value, (f.__name__, key, params[key].default, value)
            assert stubbed[f.__name__][key] == value, (f.__name__, "stub", key)


def test_reclaim_lists_what_repair_moves():
    """Issue 47: reclaim() lists the settled pieces; repair(..., reclaim="on") moves exactly
    those, the unlabelled points are counted apart, and a misspelt mode raises C3dError."""
    labs = corpus("C3D_LABS", "../shared/c3d-labs")
    if labs is None:
        pytest.skip("c3d-labs corpus not found")
    path = Path(labs) / "RehabEngGroup__MOtoNMS__Fast_Walking.c3d"
    c = c3dfix.read(str(path))
    listed = c3dfix.reclaim(c)
    assert (listed["markers"], listed["unlabelled"]) == (51, 29)
    assert listed["settled"] and all(b["action"] == "reported" for b in listed["settled"])
    _, report = c3dfix.repair(c, reclaim="on")
    moved = [(b["marker"], b["source"], b["first_frame"], b["last_frame"])
             for b in report["reclaim"]["settled"]]
    assert moved == [(b["marker"], b["source"], b["first_frame"], b["last_frame"])
                     for b in listed["settled"]]
    assert report["summary"]["unlabelled"]["points"] == 29
    # Issue 46 item 5: the summary carries counts; the lists stand beside it.
    assert report["summary"]["reclaimed"] == report["reclaim"]["samples_moved"] > 0
    assert not {"gap_list", "swap_list", "reclaim_list"} & report["summary"].keys()
    assert len(report["gaps"]) == report["summary"]["gaps"]
    with pytest.raises(c3dfix.C3dError):
        c3dfix.repair(c, reclaim="maybe")


def test_label_writes_what_the_command_writes_and_a_rerun_changes_nothing(tmp_path):
    """Issue 47 item 2: label() takes the same path as `c3dfix label --json` (same report,
    same bytes), a rerun of its output is already labelled and rewrites the same bytes, the
    output reads in ezc3d with every point kept, and a template of another marker set
    raises C3dError naming what does not match, writing nothing."""
    import subprocess

    import ezc3d

    labs = corpus("C3D_LABS", "../shared/c3d-labs")
    if labs is None:
        pytest.skip("c3d-labs corpus not found")
    trial = Path(labs) / "RehabEngGroup__MOtoNMS__Fast_Walking.c3d"
    out = tmp_path / "labelled.c3d"
    r = c3dfix.label(str(trial), str(trial), str(out))
    assert r["status"] == "labelled"
    assert (r["unlabelled_points"], r["in_common"]) == (29, 51)
    assert r["moved_samples"] == r["labelled_samples"] > 0
    by_cli = tmp_path / "cli.c3d"
    printed = subprocess.run(
        [str(cli()), "label", str(trial), "--template", str(trial), "-o", str(by_cli), "--json"],
        check=True, capture_output=True, text=True).stdout
    assert json.loads(printed)["moved_samples"] == r["moved_samples"]
    assert by_cli.read_bytes() == out.read_bytes()
    again = tmp_path / "again.c3d"
    r2 = c3dfix.label(str(out), str(trial), str(again))
    assert r2["status"] == "already_labelled"
    assert again.read_bytes() == out.read_bytes()
    e = ezc3d.c3d(str(out))
    assert e["data"]["points"].shape[1] == ezc3d.c3d(str(trial))["data"]["points"].shape[1]
    other = Path(labs) / "psbiomech__lasem-data-processing__FAILT01_SLDJ03.c3d"
    with pytest.raises(c3dfix.C3dError, match="another marker set"):
        c3dfix.label(str(trial), str(other), str(tmp_path / "no.c3d"))
    assert not (tmp_path / "no.c3d").exists()
