#!/usr/bin/env python3
"""The peers' gait events on the events benchmark's trials, as JSON for `events_eval --peers`.

Run by hand, never in CI (docs/events.md, "Side by side with the peers"):

    python3 -m venv target/peers/venv
    target/peers/venv/bin/pip install gaitkit gaitalytics ezc3d onnxruntime
    target/release/events_eval --list target/peers/trials.tsv
    target/peers/venv/bin/python scripts/events_peers.py target/peers/trials.tsv target/peers/peers.json
    target/release/events_eval --peers target/peers/peers.json > target/peers/eval.txt
    python3 scripts/events_peers.py --table target/peers/eval.txt   # docs/events.md's tables

Each trial is read by the peers themselves (gaitkit through ezc3d, gaitalytics through its own
reader). Both are told the foot and pelvis markers c3dfix chose (the list's columns), so the
methods are compared on the same markers: gaitkit's preset for the trial's marker set (its
`auto`) with c3dfix's heel, toe and sacrum put first; gaitalytics' mapping with c3dfix's heel,
toe and pelvis and the anterior superior iliac spines found by their common names (its
rotation needs them). Every method runs with its defaults. A method that raises, or finds no
event, is recorded with why.
"""

import json
import logging
import os
import sys
import tempfile
import time
import traceback

os.environ.setdefault("GAITKIT_AUTO_INSTALL_DEPS", "0")
logging.disable(logging.WARNING)

GAITKIT_METHODS = [
    "zeni", "oconnor", "hreljac", "mickelborough", "ghoussayni", "vancanneyt", "dgei",
    "bike", "intellevent", "deepevent",
]

ASIS = {
    "left": ["LASI", "LASIS", "L.ASIS", "L_ASIS", "LIAS", "L_IAS", "L.IAS", "LEFTHIP", "L_ASI", "LASIS1"],
    "right": ["RASI", "RASIS", "R.ASIS", "R_ASIS", "RIAS", "R_IAS", "R.IAS", "RIGHTHIP", "R_ASI", "RASIS1"],
}


def spec(names):
    """A gaitkit marker spec: one name, or the centre of the first two."""
    return names[0] if len(names) == 1 else tuple(names[:2])


def gaitkit_runs(path, roles):
    import gaitkit
    from gaitkit import _io

    lheel, ltoe, rheel, rtoe, pelvis = roles
    out = {}
    try:
        probe = _io.load_c3d(path)
        preset = dict(_io._MARKER_MAPS[probe["diagnostics"]["marker_set"]])
        for key, names in [("left_heel", lheel), ("left_toe", ltoe), ("right_heel", rheel),
                           ("right_toe", rtoe), ("sacrum", pelvis)]:
            if names:
                preset[key] = [spec(names)] + list(preset.get(key, []))
        trial = _io.load_c3d(path, marker_map=preset)
    except Exception as e:  # the peer's own reader refused the file
        reason = f"gaitkit could not read the trial: {type(e).__name__}: {e}"
        return {f"gaitkit {m}": {"error": reason} for m in GAITKIT_METHODS}
    for m in GAITKIT_METHODS:
        name = f"gaitkit {m}"
        try:
            r = gaitkit.detect(trial, method=m, auto_install_deps=False)
            events = []
            for side, ctx in [("left", "Left"), ("right", "Right")]:
                events += [[ctx, "FootStrike", float(e["frame"])] for e in r.hs(side)]
                events += [[ctx, "FootOff", float(e["frame"])] for e in r.to(side)]
            out[name] = {"events": events} if events else {"error": "ran, found no event"}
        except Exception as e:
            out[name] = {"error": f"{type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}"}
    return out


def gaitalytics_run(path, roles, labels):
    lheel, ltoe, rheel, rtoe, pelvis = roles
    upper = {l.upper(): l for l in labels}
    asis = {}
    for side in ["left", "right"]:
        found = [upper[n] for n in ASIS[side] if n in upper]
        if not found:
            return {"error": f"no {side} anterior superior iliac spine among the labels (its rotation needs both)"}
        asis[side] = found[0]
    if not (lheel and ltoe and rheel and rtoe and pelvis):
        return {"error": "c3dfix chose no marker for a role gaitalytics needs"}
    markers = {"l_heel": lheel[0], "r_heel": rheel[0], "l_toe": ltoe[0], "r_toe": rtoe[0],
               "l_ant_hip": asis["left"], "r_ant_hip": asis["right"]}
    if len(pelvis) == 1:
        markers["sacrum"] = pelvis[0]
    else:
        markers["l_post_hip"], markers["r_post_hip"] = pelvis[0], pelvis[1]
    import yaml
    import gaitalytics.api as ga

    config = {"analysis": {"markers": sorted(set(markers.values())), "analogs": []},
              "mapping": {"markers": markers, "analogs": {}}}
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(config, f)
        cfg_path = f.name
    try:
        cfg = ga.load_config(cfg_path)
        trial = ga.load_c3d_trial(path, cfg)
        table = ga.detect_events(trial, cfg)
        rate = None
        import ezc3d
        c = ezc3d.c3d(path, extract_forceplat_data=False)
        rate = float(c["header"]["points"]["frame_rate"])
        first = float(c["header"]["points"]["first_frame"])
        events = []
        for _, row in table.iterrows():
            kind = {"Foot Strike": "FootStrike", "Foot Off": "FootOff"}.get(row["label"])
            if kind is None:
                continue
            # gaitalytics' times are the file's (first frame's time added): back to 0-based.
            events.append([row["context"], kind, float(row["time"]) * rate - first])
        return {"events": events} if events else {"error": "ran, found no event"}
    except Exception as e:
        return {"error": f"{type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}"}
    finally:
        os.unlink(cfg_path)


def side_by_side(path):
    """The side-by-side tables of an `events_eval --peers` output: {truth: {detector: {lab: cells}}}."""
    out = {}
    for block in open(path).read().split("\n== ")[1:]:
        lines = block.split("\n")
        head = lines[0]
        if "(side by side)" not in head:
            continue
        detector, truth = head.split(" against ")
        truth = truth.split(" (side by side)")[0]
        rows = out.setdefault(truth, {}).setdefault(detector, {})
        for line in lines[2:]:
            if "|" not in line:
                break
            cells = [c.split() for c in line.split("|")]
            lab = " ".join(cells[0][:-1]).split(" (")[0]
            fs, fo = cells[1], cells[2]
            extra = cells[3][0] if len(cells) > 3 and cells[3] and cells[3][0] != "-" else "-"
            rows[lab] = {"trials": cells[0][-1], "fs": fs, "fo": fo, "extra": extra}
    return out


def cell(k):
    """'found/total median p95' of one kind's cells (n, found %, median, p95, signed)."""
    n, pct, med, p95 = int(k[0]), float(k[1].rstrip("%")), k[2], k[3]
    found = round(n * pct / 100.0)
    if med == "NaN":
        return f"{found}/{n}"
    return f"{found}/{n} {float(med):.0f} / {float(p95):.0f}"


def best_peer(rows, lab):
    """The peer finding most events on `lab` (then the lower median |error| of strikes)."""
    def key(item):
        name, labs = item
        r = labs.get(lab)
        if r is None:
            return (-1, 0)
        found = sum(int(k[0]) * float(k[1].rstrip("%")) / 100 for k in (r["fs"], r["fo"]))
        med = float(r["fs"][2]) if r["fs"][2] != "NaN" else 1e9
        return (round(found), -med)
    peers = [(n, l) for n, l in rows.items() if not n.startswith("c3dfix")]
    return max(peers, key=key)[0] if peers else None


def table(path):
    for truth, rows in side_by_side(path).items():
        print(f"\nAgainst {truth} events (found/total, median / 95th percentile of |error| in ms; extras):\n")
        print("| lab | c3dfix strikes | c3dfix offs | extras | best peer | its strikes | its offs | extras |")
        print("|---|---|---|---|---|---|---|---|")
        ours = rows["c3dfix (markers alone)"]
        for lab, r in ours.items():
            peer = best_peer(rows, lab)
            p = rows[peer][lab]
            print(f"| {lab} | {cell(r['fs'])} | {cell(r['fo'])} | {r['extra']} | {peer} | {cell(p['fs'])} | {cell(p['fo'])} | {p['extra']} |")
        print("\nPooled (ALL pooled), every detector:\n")
        print("| detector | strikes | offs | extras |")
        print("|---|---|---|---|")
        for name, labs in rows.items():
            r = labs.get("ALL pooled")
            if r:
                print(f"| {name} | {cell(r['fs'])} | {cell(r['fo'])} | {r['extra']} |")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(sys.argv[2])
        return
    if len(sys.argv) != 3:
        sys.exit("usage: events_peers.py TRIALS.tsv OUT.json")
    import ezc3d

    trials = {}
    lines = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
    for k, cells in enumerate(lines):
        path, roles = cells[0], [c.split("+") if c else [] for c in cells[1:6]]
        t0 = time.time()
        try:
            labels = [l.strip() for l in ezc3d.c3d(path, extract_forceplat_data=False)
                      ["parameters"]["POINT"]["LABELS"]["value"]]
        except Exception as e:
            labels = []
        answers = gaitkit_runs(path, roles)
        answers["gaitalytics"] = gaitalytics_run(path, roles, labels)
        trials[path] = answers
        print(f"{k + 1}/{len(lines)} {os.path.basename(path)} {time.time() - t0:.1f} s", file=sys.stderr)
    with open(sys.argv[2], "w") as f:
        json.dump({"trials": trials}, f)


if __name__ == "__main__":
    main()
