"""gait_parameters on the Nexus trial that carries Nexus' own values in its ANALYSIS group
(c3d-samples/sample_11/2198928.c3d), from the file's events and from detected ones."""

import os
from pathlib import Path

import pytest

import c3dfix

ROOT = Path(__file__).resolve().parents[3]


def sample_11():
    d = Path(os.environ.get("C3D_SAMPLES", "../shared/c3d-samples"))
    if not d.is_absolute():
        d = ROOT / d
    if not d.is_dir():
        if os.environ.get("CI", "") not in ("", "0", "false"):
            raise AssertionError(f"corpus {d} is missing and CI requires it")
        pytest.skip("c3d-samples corpus not found")
    return d / "sample_11" / "2198928.c3d"


def nexus_values(c):
    a = c.parameters["ANALYSIS"]
    n = int(a["USED"][0])
    return {
        (a["CONTEXTS"][i].strip(), a["NAMES"][i].strip()): (float(a["VALUES"][i]), a["UNITS"][i].strip())
        for i in range(n)
    }


def test_gait_parameters_match_nexus():
    c = c3dfix.read(sample_11())
    got = c3dfix.gait_parameters(c)
    assert len(got) == 26
    assert set(got[0]) == {"context", "name", "value", "unit"}
    assert [g["name"] for g in got[:13]] == [
        "Cadence", "Walking Speed", "Stride Time", "Step Time", "Opposite Foot Off",
        "Opposite Foot Contact", "Foot Off", "Single Support", "Double Support",
        "Stride Length", "Step Length", "Step Width", "Limp Index",
    ]
    ours = {(g["context"], g["name"]): g for g in got}
    nexus = nexus_values(c)
    assert len(nexus) == 22
    for key, (value, unit) in nexus.items():
        g = ours[key]
        assert g["unit"] == unit
        tol = {"s": 1 / 60, "%": 1.0, "m": 0.005}.get(unit, 0.01 * abs(value))
        assert abs(g["value"] - value) <= tol, (key, g["value"], value)
    assert abs(ours[("Left", "Stride Time")]["value"] - 0.795) < 1e-5


def test_detected_events_and_errors():
    c = c3dfix.read(sample_11())
    got = c3dfix.gait_parameters(c, detect=True)
    cadence = [g["value"] for g in got if g["name"] == "Cadence"]
    assert cadence and all(140 < v < 165 for v in cadence), cadence
    walk = c3dfix.read(ROOT / "sample_c3d" / "walk_truth.c3d")
    with pytest.raises(c3dfix.C3dError, match="no complete cycle"):
        c3dfix.gait_parameters(walk)
