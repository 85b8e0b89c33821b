"""info and view from Python: the report `c3dfix info --json` prints and the page `c3dfix view`
writes, from the same library functions, compared with the command on corpus trials (every
C3D file for info; for view, c3d-more's FMC_MH0222_BP15 with four plates and twelve events,
HansUniVie's MuscleLength test whose plates give warnings, and c3d-fullbody's 85_02).
"""

import json
import subprocess

import pytest

import c3dfix
from test_c3dfix import cli, corpus, corpus_files, fullbody


def more(name):
    d = corpus("C3D_MORE", "../shared/c3d-more")
    if d is None:
        pytest.skip("c3d-more corpus not found")
    return d / name


def run(*args):
    return subprocess.run([str(cli()), *map(str, args)], capture_output=True, text=True)


def command_page(tmp_path, *args):
    out = tmp_path / "cli.html"
    r = run("view", *args, "-o", out, "--force")
    assert r.returncode == 0, r.stderr
    return out.read_bytes(), r.stderr


def test_info_is_what_the_command_prints_as_json():
    files = corpus_files()
    if not files:
        pytest.skip("no corpus")
    checked = 0
    for f in files:
        r = run("info", "--json", f)
        if r.returncode != 0:
            # The command refuses it; so does Python, with the same message.
            with pytest.raises(c3dfix.C3dError) as e:
                c3dfix.info(f)
            assert str(e.value) in r.stderr
            continue
        want = json.loads(r.stdout)
        assert c3dfix.info(f) == want, f
        assert c3dfix.info(str(f)) == want, f
        checked += 1
    assert checked >= 90, checked


def test_info_of_a_trial_read_names_its_path():
    f = more("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d")
    want = json.loads(run("info", "--json", f).stdout)
    got = c3dfix.info(c3dfix.read(f))
    assert got == want
    assert got["file"] == str(f)
    assert got["frames"] == 291 and len(got["force_platforms"]) == 4
    assert len(got["events"]) == 12
    assert got["up"] == "+z" and got["up_source"] == "plates"


@pytest.mark.parametrize(
    "trial",
    [
        "more:tsalemink__C3D-parser__FMC_MH0222_BP15.c3d",
        "more:HansUniVie__MuscleLength__test.c3d",
        "fullbody:85_02.c3d",
    ],
)
def test_view_writes_the_commands_bytes(tmp_path, trial):
    where, name = trial.split(":")
    f = more(name) if where == "more" else fullbody(name)
    want, stderr = command_page(tmp_path, f)
    out = tmp_path / "py.html"
    warnings = c3dfix.view(f, out)
    assert out.read_bytes() == want
    # The warnings the command prints on standard error, one a line.
    assert [f"c3dfix: warning: {f}: {w}" for w in warnings] == stderr.splitlines()
    # A trial read first gives the same page (titled with its file name).
    c3dfix.view(c3dfix.read(f), out, force=True)
    assert out.read_bytes() == want
    # Not replaced unless asked.
    with pytest.raises(c3dfix.C3dError, match="force=True"):
        c3dfix.view(f, out)


def test_view_with_the_plates_warnings_returns_them(tmp_path):
    f = more("HansUniVie__MuscleLength__test.c3d")
    warnings = c3dfix.view(f, tmp_path / "p.html")
    assert len(warnings) == 8
    assert warnings[0].startswith("plate 1: FORCE_PLATFORM:ZERO frames 1..10")


def test_view_against_the_original_with_sticks_and_detected_events(tmp_path):
    f = more("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d")
    repaired = tmp_path / "repaired.c3d"
    r = run("repair", f, "-o", repaired)
    assert r.returncode == 0, r.stderr
    sticks = tmp_path / "sticks.json"
    sticks.write_text(json.dumps([["LASI", "RASI"], ["LKNE", "LANK"]]))
    want, _ = command_page(
        tmp_path, repaired, "--against", f, "--sticks", sticks, "--detect-events"
    )
    out = tmp_path / "py.html"
    c3dfix.view(
        repaired,
        out,
        against=c3dfix.read(f),
        sticks=[("LASI", "RASI"), ("LKNE", "LANK")],
        detect_events=True,
    )
    assert out.read_bytes() == want
    # The detected events are on the page, apart from the file's own.
    assert b"(detected)" in want


def test_view_refuses_what_the_command_refuses(tmp_path):
    f = more("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d")
    with pytest.raises(c3dfix.C3dError, match="has no marker \"NOPE\"; available: "):
        c3dfix.view(f, tmp_path / "x.html", sticks=[("LASI", "NOPE")])
    assert not (tmp_path / "x.html").exists()


def test_plot_draws_the_commands_bytes(tmp_path):
    f = more("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d")
    repaired = tmp_path / "repaired.c3d"
    assert run("repair", f, "-o", repaired).returncode == 0
    for ext in ("svg", "png"):
        cmd = tmp_path / f"cli.{ext}"
        r = run(
            "plot", repaired, "--marker", "LASI,RKNE", "--against", f,
            "--analog", "1", "--detect-events", "-o", cmd,
        )
        assert r.returncode == 0, r.stderr
        out = tmp_path / f"py.{ext}"
        c3dfix.plot(
            repaired, out, ["LASI", "RKNE"], against=c3dfix.read(f), analog="1",
            detect_events=True,
        )
        assert out.read_bytes() == cmd.read_bytes(), ext
    with pytest.raises(c3dfix.C3dError, match="must end in .svg or .png"):
        c3dfix.plot(f, tmp_path / "x.pdf", ["LASI"])
    with pytest.raises(c3dfix.C3dError, match="at most 6"):
        c3dfix.plot(f, tmp_path / "x.svg", ["LASI"] * 7)


def test_plot_forces_draws_the_commands_bytes_and_returns_the_warnings(tmp_path):
    f = more("HansUniVie__MuscleLength__test.c3d")
    cmd = tmp_path / "cli.png"
    r = run("plot", f, "--forces", "--threshold", "20", "-o", cmd)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "py.png"
    warnings = c3dfix.plot_forces(f, out, threshold=20.0)
    assert out.read_bytes() == cmd.read_bytes()
    assert [f"c3dfix: warning: {f}: {w}" for w in warnings] == r.stderr.splitlines()
    assert len(warnings) == 8


def test_the_stubs_say_the_signatures():
    """info, view, plot and plot_forces: the stub's keywords and defaults are the extension's."""
    import ast
    import inspect
    from pathlib import Path

    stub = ast.parse((Path(c3dfix.__file__).parent / "__init__.pyi").read_text())
    names = ("info", "view", "plot", "plot_forces")
    found = {}
    for node in stub.body:
        if isinstance(node, ast.FunctionDef) and node.name in names:
            a = node.args
            defaults = [None] * (len(a.args) - len(a.defaults)) + [
                ast.literal_eval(d) for d in a.defaults
            ]
            found[node.name] = [(p.arg, d) for p, d in zip(a.args, defaults)]
    for name in names:
        params = inspect.signature(getattr(c3dfix, name)).parameters.values()
        runtime = [
            (p.name, None if p.default is inspect.Parameter.empty else p.default)
            for p in params
        ]
        # A default the extension computes (plot_forces' threshold, the library's
        # DEFAULT_THRESHOLD_N) shows as `...`: its name is compared, its value is the stub's.
        stubbed = [
            (k, d if r is not Ellipsis else Ellipsis) for (k, d), (_, r) in zip(found[name], runtime)
        ]
        assert stubbed == runtime, name


def test_a_picture_is_never_written_over_its_trial(tmp_path):
    src = more("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d")
    f = tmp_path / "trial.c3d"
    # A trial under a picture's name: the extension alone would not stop the plots.
    g = tmp_path / "trial.svg"
    for p in (f, g):
        p.write_bytes(src.read_bytes())
    for write in (
        lambda: c3dfix.view(f, f, force=True),
        lambda: c3dfix.view(src, f, against=f, force=True),
        lambda: c3dfix.plot(c3dfix.read(g), g, ["LASI"], force=True),
        lambda: c3dfix.plot_forces(g, g, force=True),
    ):
        with pytest.raises(c3dfix.C3dError, match="is the input file .*refusing to overwrite"):
            write()
    assert f.read_bytes() == src.read_bytes() and g.read_bytes() == src.read_bytes()


def test_view_of_a_bvh_skeleton_writes_the_commands_bytes(tmp_path):
    d = corpus("BVH_SAMPLES", "../shared/bvh-samples")
    if d is None:
        pytest.skip("bvh-samples not found")
    f = d / "bvhtoolbox_walk01.bvh"
    want, _ = command_page(tmp_path, f)
    out = tmp_path / "py.html"
    assert c3dfix.view(f, out) == []
    assert out.read_bytes() == want
    # Against itself, as the command draws it.
    want, _ = command_page(tmp_path, f, "--against", f)
    c3dfix.view(f, out, against=f, force=True)
    assert out.read_bytes() == want
    with pytest.raises(c3dfix.C3dError, match="BVH file's bones"):
        c3dfix.view(f, out, sticks=[("a", "b")], force=True)
