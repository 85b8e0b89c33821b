"""report from Python: the session report `c3dfix report --json` prints and the page it
writes, from the same library functions, on c3d-more and its copy repaired by `c3dfix batch`.
"""

import json
import subprocess

import pytest

import c3dfix
from test_c3dfix import cli, corpus


def run(*args):
    return subprocess.run([str(cli()), *map(str, args)], capture_output=True, text=True)


def test_report_is_what_the_command_prints_and_writes(tmp_path):
    more = corpus("C3D_MORE", "../shared/c3d-more")
    if more is None:
        pytest.skip("c3d-more corpus not found")
    out = tmp_path / "repaired"
    r = run("batch", more, "--out-dir", out, "--json")
    assert r.returncode == 0, r.stderr
    lines = [json.loads(l) for l in r.stdout.splitlines()]
    by_file = {l["file"]: l["summary"] for l in lines if "file" in l}
    page = tmp_path / "py.html"
    rep = c3dfix.report([more], out=page, repaired=out, views=True)
    r = run("report", more, "--repaired", out, "--json")
    assert r.returncode == 0, r.stderr
    # The command without --views names no view pages; all else is the same.
    assert [{k: v for k, v in t.items() if k != "view"} for t in rep["trials"]] == json.loads(
        r.stdout
    )["trials"]
    assert rep["summary"] == json.loads(r.stdout)["summary"]
    assert rep["summary"]["trials"] == 20 and rep["summary"]["filled"] == 655
    for row in rep["trials"]:
        s = by_file[row["file"]]
        assert (row["filled"], row["left"], row["left_because"]) == (
            s["filled"],
            s["left"],
            s["left_because"],
        )
        assert (page.parent / "py_views" / row["view"]).is_file()
    cmd = tmp_path / "cli.html"
    r = run("report", more, "--repaired", out, "--views", "-o", cmd)
    assert r.returncode == 0, r.stderr
    # The same page but for its own name (title, views folder).
    assert page.read_text().replace("py_views", "X").replace("py.html", "Y") == cmd.read_text().replace(
        "cli_views", "X"
    ).replace("cli.html", "Y")
    with pytest.raises(c3dfix.C3dError, match="exists"):
        c3dfix.report([more], out=page)


def test_an_unreadable_trial_is_a_row(tmp_path):
    (tmp_path / "bad.c3d").write_bytes(b"not a c3d file at all")
    rep = c3dfix.report([tmp_path])
    assert rep["summary"]["unreadable"] == 1
    assert "bad.c3d" in rep["trials"][0]["error"]


def test_the_stub_says_the_signature():
    import ast
    import inspect
    from pathlib import Path

    stub = ast.parse((Path(c3dfix.__file__).parent / "__init__.pyi").read_text())
    node = next(n for n in stub.body if isinstance(n, ast.FunctionDef) and n.name == "report")
    a = node.args
    defaults = [None] * (len(a.args) - len(a.defaults)) + [ast.literal_eval(d) for d in a.defaults]
    stubbed = [(p.arg, d) for p, d in zip(a.args, defaults)]
    runtime = [
        (p.name, None if p.default is inspect.Parameter.empty else p.default)
        for p in inspect.signature(c3dfix.report).parameters.values()
    ]
    assert stubbed == runtime
