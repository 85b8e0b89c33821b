"""The OpenSim export checked by OpenSim itself (4.6, `pip install opensim`).

On every c3d-more trial and every other corpus trial with force plates: `export_opensim`
writes NAME.trc and NAME.mot; OpenSim's TimeSeriesTableVec3 reads the TRC with the values
c3dfix reads (turned to OpenSim's frame) and NaN exactly where c3dfix says a sample is
missing; Storage and TimeSeriesTable read the MOT with the plates' values; an ExternalForce
on each plate returns the MOT's rows from getForceAtTime and getPointAtTime.

Skips with a message where `import opensim` fails, except under CI, where it fails.
"""

import os
import itertools
import warnings
from pathlib import Path

import numpy as np
import pytest

import c3dfix

from test_c3dfix import corpus, corpus_files

CI = os.environ.get("CI", "") not in ("", "0", "false")

try:
    import opensim as osim
except ImportError as e:  # pragma: no cover - depends on the machine
    if CI:
        raise AssertionError(f"CI needs OpenSim for these tests: import opensim failed: {e}")
    pytest.skip(f"OpenSim not installed (pip install opensim): {e}", allow_module_level=True)

# OpenSim logs to opensim.log in the working folder: not from a test run.
osim.Logger.removeFileSink()

MODEL_OUTPUT_PARAMS = ("ANGLES", "FORCES", "MOMENTS", "POWERS", "SCALARS", "REACTIONS")
MM = {"mm": 1.0, "m": 1000.0, "mete": 1000.0, "cm": 10.0}


def more_files():
    samples = corpus("C3D_SAMPLES", "../shared/c3d-samples")
    base = samples.parent if samples else Path(__file__).resolve().parents[3] / "../shared"
    d = corpus("C3D_MORE", str(base / "c3d-more"))
    return sorted(d.glob("*.c3d")) if d else []


def read(path):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return c3dfix.read(path)
    except c3dfix.C3dError:  # the corpora's broken files (btkdata_Empty, …)
        return None


def has_plates(c):
    return bool(c.parameters.get("FORCE_PLATFORM", {}).get("USED") is not None) and bool(
        np.any(np.asarray(c.parameters["FORCE_PLATFORM"]["USED"]) > 0)
    )


def trials():
    """c3d-more, and every other corpus trial with plates, that has markers to export."""
    out = []
    more = more_files()
    for p in more + [p for p in corpus_files() if p not in more]:
        c = read(p)
        if c is None or c.points.shape[0] == 0 or c.points.shape[1] == 0:
            continue
        if p in more or has_plates(c):
            out.append(p)
    return out


TRIALS = trials()


def rotation(spec):
    """The matrix of an axes string such as "x,z,-y": output k = sign × lab[axis]."""
    r = np.zeros((3, 3))
    for k, part in enumerate(spec.split(",")):
        sign = -1.0 if part.startswith("-") else 1.0
        r[k, "xyz".index(part.lstrip("+-"))] = sign
    return r


def marker_columns(c):
    outputs = set()
    point = c.parameters.get("POINT", {})
    for k in MODEL_OUTPUT_PARAMS:
        v = point.get(k)
        if isinstance(v, list):
            outputs |= {s for s in v if s}
        elif isinstance(v, str) and v:
            outputs.add(v)
    # Points stored after the first listed output are outputs too (Plug-in Gait's bones,
    # virtual points, centre of mass, muscle lengths), unless the first point is itself one.
    first = next((i for i, l in enumerate(c.labels) if l in outputs), None)
    axes = segment_axes(c)
    if first is not None and first > 0:
        return [i for i in range(first) if c.labels[i] not in outputs and i not in axes]
    return [i for i, l in enumerate(c.labels) if l not in outputs and i not in axes]


def segment_axes(c):
    """Points that form a segment's axes (an origin and three points at one distance from
    it, at right angles), wherever stored: model outputs too. Checked here on every frame
    where the four are recorded (the library reads 64 frames spread over the trial)."""
    scale = c.parameters.get("POINT", {}).get("SCALE")
    scale = None if scale is None else float(np.ravel(scale)[0])
    quantum = scale if scale is not None and scale > 0 else 0.0
    slack = 2.0 * np.sqrt(3.0) * quantum
    p = np.asarray(c.points, dtype=float)
    n = p.shape[1]
    found = set()
    for o in range(n):
        rows = np.nonzero(~np.isnan(p[:, o, 0]))[0]
        if len(rows) == 0:
            continue
        d = np.linalg.norm(p[rows[0]] - p[rows[0], o], axis=1)
        d[o] = np.nan
        cand = np.array([k for k in np.argsort(d) if np.isfinite(d[k]) and d[k] > max(slack, 0.0)], dtype=int)
        ds = d[cand]
        triples = set()
        for i, a in enumerate(cand):
            end = np.searchsorted(ds, ds[i] * (1 + 2e-4) + slack, side="right")
            near = [k for k in cand[i + 1 : end] if d[k] - d[a] <= 1e-4 * d[k] + slack]
            triples |= {(a, b, x) for b, x in itertools.combinations(near, 2)}
        u0 = p[rows[0]] - p[rows[0], o]
        for a, b, x in sorted(triples):
            first = [u0[k] / d[k] for k in (a, b, x)]
            if max(abs(first[i] @ first[j]) for i, j in [(0, 1), (0, 2), (1, 2)]) > 1e-4 + slack / d[a]:
                continue
            both = ~np.isnan(p[:, [o, a, b, x], 0]).any(axis=1)
            if not both.any():
                continue
            u = p[both][:, [a, b, x]] - p[both][:, [o]]
            length = np.linalg.norm(u, axis=2)
            if (length.max(axis=1) - length.min(axis=1) > 1e-4 * length.max(axis=1) + slack).any():
                continue
            if (length.min(axis=1) <= slack).any() or (length == 0).any():
                continue
            unit = u / length[..., None]
            cos = np.abs(np.stack([(unit[:, i] * unit[:, j]).sum(axis=1) for i, j in [(0, 1), (0, 2), (1, 2)]]))
            if (cos <= 1e-4 + slack / length.min(axis=1)).all():
                found |= {o, a, b, x}
    return found


def test_the_corpora_give_trials():
    if not TRIALS and not CI:
        pytest.skip("corpora not found")
    assert len(TRIALS) >= 20, TRIALS


@pytest.mark.parametrize("path", TRIALS, ids=lambda p: p.name)
def test_opensim_reads_the_export(path, tmp_path):
    c = read(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        done = c3dfix.export_opensim(c, tmp_path)
    rot = rotation(done["axes"])
    assert np.isclose(np.linalg.det(rot), 1.0), done["axes"]
    if done["up"] is not None:
        # The lab's up is OpenSim's +Y.
        up = np.zeros(3)
        up["xyz".index(done["up"][1])] = 1.0 if done["up"][0] == "+" else -1.0
        assert np.array_equal(rot @ up, [0.0, 1.0, 0.0]), done

    # TRC: every marker (no model outputs), on the file's frame numbers and time base.
    cols = marker_columns(c)
    table = osim.TimeSeriesTableVec3(str(done["trc"]))
    names = [c.labels[i].replace("\t", " ").replace("\n", " ") for i in cols]
    names = [n if n.strip() else f"Point{i + 1}" for n, i in zip(names, cols)]
    assert list(table.getColumnLabels()) == names
    frames = c.points.shape[0]
    assert table.getNumRows() == frames
    times = np.array(table.getIndependentColumn())
    expected_t = (c.first_frame - 1 + np.arange(frames)) / c.point_rate
    np.testing.assert_allclose(times, expected_t, atol=1e-6)
    # The flattened table must outlive its matrix view (a temporary is freed under it).
    flat = table.flatten()
    got = flat.getMatrix().to_numpy().reshape(frames, len(cols), 3)
    want = c.points[:, cols, :] @ rot.T
    missing = np.isnan(c.points[:, cols, 0])
    assert np.array_equal(np.isnan(got).any(axis=2), missing), path.name
    assert np.array_equal(np.isnan(got).all(axis=2), missing)
    ok = ~missing
    np.testing.assert_allclose(got[ok], want[ok], rtol=1e-6, atol=1e-6 * MM.get(c.point_units, 1.0))

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plates = c.force_platforms() if has_plates(c) else []
    if done["mot"] is None:
        assert not plates, path.name
        return
    # MOT: Storage and TimeSeriesTable read every row and column.
    storage = osim.Storage(str(done["mot"]))
    mot = osim.TimeSeriesTable(str(done["mot"]))
    n = len(plates[0]["force"])
    assert storage.getSize() == n and mot.getNumRows() == n
    assert storage.getColumnLabels().getSize() == 1 + 9 * len(plates)
    assert mot.getNumColumns() == 9 * len(plates)
    m = mot.getMatrix().to_numpy()
    t = np.array(mot.getIndependentColumn())
    analog_rate = plates[0]["rate"]
    np.testing.assert_allclose(t, (c.first_frame - 1) / c.point_rate + np.arange(n) / analog_rate, atol=1e-6)
    labels = list(mot.getColumnLabels())
    metres = MM[c.point_units.strip().lower()] / 1000.0
    model = osim.Model()
    forces = []
    for k, p in enumerate(plates):
        i = p["index"]
        base = labels.index(f"ground_force_{i}_vx")
        assert labels[base : base + 9] == [
            f"ground_force_{i}_vx", f"ground_force_{i}_vy", f"ground_force_{i}_vz",
            f"ground_force_{i}_px", f"ground_force_{i}_py", f"ground_force_{i}_pz",
            f"ground_torque_{i}_x", f"ground_torque_{i}_y", f"ground_torque_{i}_z",
        ]
        loaded = np.isfinite(p["cop"]).all(axis=1) & np.isfinite(p["force"]).all(axis=1) & np.isfinite(p["free_moment"]).all(axis=1)
        # Rows outside the plate's contacts are no load (a run above the threshold too short
        # for a footfall is noise, no foot).
        inside = np.zeros(len(loaded), dtype=bool)
        for contact in p["contacts"]:
            inside[contact["first_sample"] : contact["last_sample"] + 1] = True
        loaded &= inside
        force = np.where(loaded[:, None], p["force"], 0.0) @ rot.T
        point = np.where(loaded[:, None], p["cop"], p["centre"][None, :]) * metres @ rot.T
        torque = np.where(loaded[:, None], p["free_moment"], 0.0) * metres @ rot.T
        np.testing.assert_allclose(m[:, base : base + 3], force, atol=1e-6, rtol=1e-9)
        np.testing.assert_allclose(m[:, base + 3 : base + 6], point, atol=1e-6, rtol=1e-9)
        np.testing.assert_allclose(m[:, base + 6 : base + 9], torque, atol=1e-6, rtol=1e-9)
        ef = osim.ExternalForce(
            storage, f"ground_force_{i}_v", f"ground_force_{i}_p", f"ground_torque_{i}_",
            "ground", "ground", "ground",
        )
        ef.setName(f"plate{i}")
        model.addForce(ef)
        forces.append((base, ef, int(np.argmax(loaded)) if loaded.any() else 0))
    model.initSystem()
    for base, ef, first_loaded in forces:
        for row in sorted({0, first_loaded, n // 2, n - 1}):
            f = ef.getForceAtTime(t[row])
            q = ef.getPointAtTime(t[row])
            np.testing.assert_allclose([f.get(a) for a in range(3)], m[row, base : base + 3], atol=1e-9)
            np.testing.assert_allclose([q.get(a) for a in range(3)], m[row, base + 3 : base + 6], atol=1e-9)


def test_plate_defaults_agree_everywhere():
    """Every function that computes plates removes the unloaded level by default, as the
    library's ForceOptions::default() and the command line do; the stub says the same."""
    import inspect

    stub = (Path(c3dfix.__file__).parent / "__init__.pyi").read_text()
    for f in (c3dfix.export_mot, c3dfix.export_opensim, c3dfix.C3d.force_platforms):
        params = inspect.signature(f).parameters
        assert params["zero_baseline"].default is True, f.__name__
    assert "zero_baseline: bool = False" not in stub
