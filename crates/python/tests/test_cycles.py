"""Gait events and cycles from Python: C3d.events, detect_events and cycles, on trials
whose labs marked their foot strikes (c3d-more's FMC_MH0222_BP15: 100 Hz from frame 260,
four plates; c3d-samples' sample_11/2198928.c3d: 60 Hz with Plug-in Gait angles), checked
against the command line and against the rule written in numpy.
"""

import csv
import json
import subprocess
import warnings

import numpy as np
import pytest

import c3dfix
from test_c3dfix import cli, corpus


def more(name):
    d = corpus("C3D_MORE", "../shared/c3d-more")
    if d is None:
        pytest.skip("c3d-more corpus not found")
    return d / name


FMC = "tsalemink__C3D-parser__FMC_MH0222_BP15.c3d"


def fmc():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return c3dfix.read(more(FMC))


def strikes(c, side):
    return sorted(
        e["time"] for e in c.events if e["label"] == "Foot Strike" and e["context"] == side
    )


def test_events_carry_the_frame_in_the_files_numbering():
    c = fmc()
    ev = [e for e in c.events if e["context"] == "Left" and e["label"] == "Foot Strike"]
    # In the group's own order (Nexus does not sort it).
    assert [e["frame"] for e in ev] == [378, 280, 475]
    assert [e["time"] for e in ev] == pytest.approx([3.773, 2.79, 4.74], abs=1e-6)
    # Frame 280 of a trial whose first frame is 260 is its 21st stored frame.
    assert c.first_frame == 260


def test_detect_events_matches_the_command_line():
    path = more(FMC)
    c = fmc()
    for source in ("auto", "plates", "kinematics"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            got = c3dfix.detect_events(c, source=source)
        out = subprocess.run(
            [str(cli()), "events", "--json", "--from", source, str(path)],
            capture_output=True,
            check=True,
        )
        want = json.loads(out.stdout)["events"]
        assert len(got) == len(want) > 0, source
        for g, w in zip(got, want):
            assert g["context"] == w["context"] and g["label"] == w["label"]
            assert g["frame"] == w["frame"] and g["source"] == w["source"]
            assert g["time"] == pytest.approx(w["time"], abs=1e-9)
            assert g["plate"] == w.get("plate")
    # Plate events land within 10 ms of the lab's own strikes.
    plates = [e for e in c3dfix.detect_events(c, source="plates") if e["label"] == "Foot Strike"]
    for e in plates:
        lab = strikes(c, e["context"])
        assert min(abs(t - e["time"]) for t in lab) < 0.010, e
    with pytest.raises(c3dfix.C3dError, match="expected plates, kinematics or auto"):
        c3dfix.detect_events(c, source="vibes")


def oracle(c, label, axis, t0, t1):
    """The rule in numpy: linear interpolation at 101 times from t0 to t1 inclusive of the
    marker's samples (frame i at (first_frame - 1 + i) / rate), NaN next to a missing one."""
    i = c.labels.index(label)
    v = c.points[:, i, axis]
    t = (c.first_frame - 1 + np.arange(len(v))) / c.point_rate
    at = np.linspace(t0, t1, 101)
    u = (at - t[0]) * c.point_rate
    lo = np.floor(u + 1e-3).astype(int)
    frac = u - lo
    hi = np.minimum(lo + 1, len(v) - 1)
    on = np.abs(frac) < 1e-3
    out = np.where(on, v[lo], v[lo] * (1 - frac) + v[hi] * frac)
    return out


def test_cycles_are_the_rule_and_the_command_lines_csv(tmp_path):
    c = fmc()
    r = c3dfix.cycles(c, markers=["LHEE", "RTOE"])
    assert r["data"].shape == (4, 101, 6)
    assert r["columns"] == ["LHEE_x", "LHEE_y", "LHEE_z", "RTOE_x", "RTOE_y", "RTOE_z"]
    assert r["units"] == ["mm"] * 6
    assert list(r["percent"]) == list(range(101))
    assert r["side"] == ["Left", "Left", "Right", "Right"]
    assert r["number"] == [1, 2, 1, 2]
    assert r["start_frame"] == [280, 378, 328, 426]
    assert r["events"] == "file"
    for k, side in enumerate(r["side"]):
        st = strikes(c, side)
        n = r["number"][k]
        assert r["start_time"][k] == pytest.approx(st[n - 1], abs=1e-9)
        assert r["end_time"][k] == pytest.approx(st[n], abs=1e-9)
        for col, (label, axis) in enumerate(
            [(m, a) for m in ("LHEE", "RTOE") for a in range(3)]
        ):
            want = oracle(c, label, axis, r["start_time"][k], r["end_time"][k])
            got = r["data"][k, :, col]
            np.testing.assert_allclose(got, want, atol=1e-3, equal_nan=True)
    # The first 100 samples are Kinetics Toolkit's time_normalize (n_points=100), which
    # resamples at linspace(start, end, 101) and keeps all but the last.
    k0 = r["data"][0, :, 2]
    t = np.linspace(r["start_time"][0], r["end_time"][0], 101)[:100]
    z = c.points[:, c.labels.index("LHEE"), 2]
    tt = (c.first_frame - 1 + np.arange(len(z))) / c.point_rate
    np.testing.assert_allclose(k0[:100], np.interp(t, tt, z), atol=1e-3)
    # The same numbers as `c3dfix cycles`' CSV.
    out = tmp_path / "c.csv"
    subprocess.run(
        [str(cli()), "cycles", str(more(FMC)), "--markers", "LHEE,RTOE", "-o", str(out)],
        capture_output=True,
        check=True,
    )
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 4 * 101
    for j, row in enumerate(rows):
        k, p = divmod(j, 101)
        assert int(row["percent"]) == p
        for col, name in enumerate(r["columns"]):
            cell = row[f"{name} (mm)"]
            v = r["data"][k, p, col]
            if cell == "":
                assert np.isnan(v)
            else:
                assert float(cell) == pytest.approx(v, abs=1e-9)


def test_forces_analog_and_angles_in_their_units():
    c = fmc()
    r = c3dfix.cycles(c, side="left", forces=True, analog=["Force.Fz2"])
    assert r["data"].shape == (2, 101, 1 + 4 * 3)
    assert r["columns"][:4] == ["Force.Fz2", "FP1_Fx", "FP1_Fy", "FP1_Fz"]
    fz = r["data"][1, :, r["columns"].index("FP2_Fz")]
    # Plate 2 carries the left foot from its strike (3.773 s) to the lab's Foot Off
    # (4.365 s, 61.2 % of the cycle), then nothing.
    loaded = np.nonzero(np.abs(fz) > 10)[0]
    assert loaded[0] <= 1 and abs(loaded[-1] - 61.2) <= 1.5
    assert 600 < np.abs(fz).max() < 1200
    np.testing.assert_allclose(r["data"][:, :, 0], -r["data"][:, :, r["columns"].index("FP2_Fz")], atol=1e-3)
    d = corpus("C3D_SAMPLES", "../shared/c3d-samples")
    if d is None:
        pytest.skip("c3d-samples corpus not found")
    s11 = c3dfix.read(d / "sample_11" / "2198928.c3d")
    a = c3dfix.cycles(s11, side="right", markers=["RKneeAngles"])
    assert a["units"] == ["deg"] * 3 and a["data"].shape == (1, 101, 3)
    flex = a["data"][0, :, 0]
    assert abs(flex[0]) < 15 and 40 < flex.max() < 75


def test_detected_cycles_and_clear_errors():
    c = fmc()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = c3dfix.cycles(c, markers=["LHEE"], detect=True)
    assert r["events"] == "detected" and r["data"].shape[0] >= 3
    for k, side in enumerate(r["side"]):
        assert min(abs(t - r["start_time"][k]) for t in strikes(c, side)) <= 0.025
    with pytest.raises(c3dfix.C3dError, match="expected left, right or both"):
        c3dfix.cycles(c, side="middle")
    with pytest.raises(c3dfix.C3dError, match="no analog channel"):
        c3dfix.cycles(c, analog=["EMG9"])
    squat = c3dfix.read(more("keenon__nimblephysics__squat.c3d"))
    with pytest.raises(c3dfix.C3dError, match="no complete gait cycle.*Left 0, Right 0"):
        c3dfix.cycles(squat)


def test_detect_events_calibrated_from_the_sessions_other_trial():
    """calibrate_from as `c3dfix events --calibrate-from`: qualisys' ClinicalGait_Gait1
    (c3d-more) shifted by the lags FunctionalKnee_GaitFB2's markers showed at its own plates
    (strikes +6.7 ms, offs -1.8 ms since offs are shifted by the trial's stride; -1.7 before
    extremes at a trial's edge counted in FB2's stride estimate), the same events as the command line's, each carrying
    the shift it got."""
    gait1 = more("qualisys__cgm2-web-report-uploader__ClinicalGait_Gait1.c3d")
    fb2 = more("qualisys__cgm2-web-report-uploader__FunctionalKnee_GaitFB2.c3d")
    c = c3dfix.read(gait1)
    raw = c3dfix.detect_events(c, source="kinematics")
    assert all("shift_ms" not in e for e in raw)
    # The trial itself among the references never counts.
    got = c3dfix.detect_events(c, source="kinematics", calibrate_from=[fb2, gait1])
    out = subprocess.run(
        [str(cli()), "events", "--json", "--from", "kinematics", str(gait1),
         "--calibrate-from", str(fb2)],
        capture_output=True,
        check=True,
    )
    want = json.loads(out.stdout)["events"]
    # 14 since the left off 0.14 s before the trial's last frame is found (docs/events.md).
    assert len(got) == len(want) == len(raw) == 14
    for b, g, w in zip(raw, got, want):
        assert (g["context"], g["label"], g["frame"]) == (w["context"], w["label"], w["frame"])
        assert g["time"] == pytest.approx(w["time"], abs=1e-9)
        shift = 6.74 if g["label"] == "Foot Strike" else -1.84
        assert g["shift_ms"] == pytest.approx(shift, abs=0.05)
        assert (g["time"] - b["time"]) * 1000 == pytest.approx(shift, abs=0.05)
    # In auto the trial's own plates calibrate both kinds: nothing is shifted by the session.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        auto = c3dfix.detect_events(c, calibrate_from=[fb2])
    assert all(e["shift_ms"] is None for e in auto)
    with pytest.raises(c3dfix.C3dError, match="no such file or folder"):
        c3dfix.detect_events(c, source="kinematics", calibrate_from=[gait1.parent / "nope"])
    with pytest.raises(c3dfix.C3dError, match="calibrate_from shifts kinematic events"):
        c3dfix.detect_events(c, source="plates", calibrate_from=[fb2])
