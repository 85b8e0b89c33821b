//! One frame numbering and one time base in every output: every command run with `--json`
//! (and the exports, and the text of a few) on a trial whose first frame is not 1, with a
//! gap, a spike and a label swap put in at known frames. Every frame field holds the file's
//! own frame numbers (first frame from the header) and every time field
//! `(frame number − 1) / rate`, the EVENT group's base.

use super::{c3dfix, s, stderr, stdout};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// `FMC_MH0222_BP15` (c3d-more): 291 frames numbered 260–550 at 100 Hz.
const FIRST: u64 = 260;
const LAST: u64 = 550;
const RATE: f64 = 100.0;

/// A frame's time on the file's base.
fn time(frame: u64) -> f64 {
    (frame - 1) as f64 / RATE
}

/// The trial with LKNE missing at file frames 310–319, RANK 150 mm off at frame 380 and
/// LASI and LPSI exchanged over frames 410–429 (0-based 50..=59, 120, 150..=169).
fn edited(dir: &Path, src: &Path) -> PathBuf {
    let mut c = c3d::read_file(src).unwrap();
    assert_eq!(c.first_frame() as u64, FIRST);
    let at = |c: &c3d::C3d, l: &str| c.point_index(l).unwrap();
    let (kne, ank, lasi, lpsi) = (
        at(&c, "LKNE"),
        at(&c, "RANK"),
        at(&c, "LASI"),
        at(&c, "LPSI"),
    );
    let p = c.points_mut();
    for f in 50..60 {
        let k = p.index(f, kne);
        p.residual[k] = -1.0;
        p.camera_mask[k] = 0;
    }
    let k = p.index(120, ank);
    p.xyz[k][2] += 150.0;
    for f in 150..170 {
        let (a, b) = (p.index(f, lasi), p.index(f, lpsi));
        p.xyz.swap(a, b);
    }
    let out = dir.join("fmc.c3d");
    std::fs::write(&out, c.to_bytes().unwrap()).unwrap();
    out
}

/// Every frame and time field of `v` (at any depth), with the path that leads to it: keys
/// `frame`, `first`/`last` (of a gap list), and those ending in `_frame` are frames; keys
/// ending in `time` (not lists of samples) are times. Counts (`frames`, `valid_frames`,
/// `frames_changed`, …) are neither.
fn frame_and_time_fields(v: &Value, path: &str, out: &mut Vec<(String, f64, bool)>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let p = format!("{path}.{k}");
                let is_frame = k == "frame"
                    || ((k == "first" || k == "last") && path.contains("gap"))
                    || (k.ends_with("_frame") && !k.ends_with("per_frame"));
                let is_time = k == "time" || k.ends_with("_time");
                if let (true, Some(n)) = (is_frame || is_time, x.as_f64()) {
                    out.push((p, n, is_frame));
                } else {
                    frame_and_time_fields(x, &p, out);
                }
            }
        }
        Value::Array(a) => {
            for x in a {
                frame_and_time_fields(x, &format!("{path}[]"), out);
            }
        }
        _ => {}
    }
}

/// Checks every frame and time field of `what`'s JSON and gives back how many there were.
fn on_the_files_base(what: &str, v: &Value) -> usize {
    let mut fields = Vec::new();
    frame_and_time_fields(v, "", &mut fields);
    for (path, n, is_frame) in &fields {
        if *is_frame {
            assert!(
                n.fract() == 0.0 && (FIRST as f64..=LAST as f64).contains(n),
                "{what}: {path} = {n} is no frame of the file ({FIRST}–{LAST})"
            );
        } else {
            assert!(
                (time(FIRST) - 1e-6..=time(LAST) + 0.01).contains(n),
                "{what}: {path} = {n} s is outside the file's time base ({}–{} s)",
                time(FIRST),
                time(LAST)
            );
        }
    }
    fields.len()
}

fn json(args: &[&str]) -> Value {
    let out = c3dfix(args);
    assert!(
        out.status.code().is_some_and(|c| c <= 1),
        "{args:?}: {}",
        stderr(&out)
    );
    let text = stdout(&out);
    // `batch` and `convert --json` write a line per file, then the summary.
    serde_json::from_str(&text).unwrap_or_else(|_| {
        Value::Array(
            text.lines()
                .map(|l| serde_json::from_str(l).expect("a JSON line"))
                .collect(),
        )
    })
}

/// Finds `key == value` objects in `v` (any depth).
fn find<'a>(v: &'a Value, key: &str, value: &str, out: &mut Vec<&'a Value>) {
    match v {
        Value::Object(m) => {
            if m.get(key).and_then(Value::as_str) == Some(value) {
                out.push(v);
            }
            m.values().for_each(|x| find(x, key, value, out));
        }
        Value::Array(a) => a.iter().for_each(|x| find(x, key, value, out)),
        _ => {}
    }
}

fn one<'a>(v: &'a Value, key: &str, value: &str) -> &'a Value {
    let mut found = Vec::new();
    find(v, key, value, &mut found);
    assert_eq!(found.len(), 1, "{key} = {value} in {v}");
    found[0]
}

#[test]
fn every_output_numbers_frames_as_the_file_does() {
    let Some(more) = testkit::c3d_more() else {
        eprintln!("skipping: c3d-more not found (set C3D_MORE)");
        testkit::skipped("c3d-more not found");
        return;
    };
    let src = more.join("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d");
    let dir = tempfile::tempdir().unwrap();
    let f = edited(dir.path(), &src);
    let d = |n: &str| dir.path().join(n);
    let mut fields = 0;

    // info: the first frame, events on the file's time base.
    let v = json(&["info", "--json", s(&f)]);
    assert_eq!(v["first_frame"], FIRST);
    assert!(!v["events"].as_array().unwrap().is_empty());
    fields += on_the_files_base("info", &v);

    // gaps: LKNE's knocked-out frames.
    let v = json(&["gaps", "--json", s(&f)]);
    let g = one(&v, "label", "LKNE");
    assert_eq!(
        (g["first_frame"].as_u64(), g["last_frame"].as_u64()),
        (Some(310), Some(319)),
        "{g}"
    );
    fields += on_the_files_base("gaps", &v);
    let t = stdout(&c3dfix(&["gaps", s(&f)]));
    assert!(t.contains("310–319"), "{t}");

    // swaps: the exchange over frames 410–429.
    let v = json(&["swaps", "--json", s(&f)]);
    let x = &v["swaps"][0];
    assert_eq!(x["markers"], serde_json::json!(["LASI", "LPSI"]), "{v}");
    assert_eq!(
        (x["first_frame"].as_u64(), x["last_frame"].as_u64()),
        (Some(410), Some(429)),
        "{x}"
    );
    fields += on_the_files_base("swaps", &v);

    // repair: the gap filled, the spike found, in the summary and the full report.
    let rep = d("rep.c3d");
    let report = d("report.json");
    let v = json(&[
        "repair",
        s(&f),
        "-o",
        s(&rep),
        "--spikes",
        "hampel",
        "--json",
        "--report",
        s(&report),
    ]);
    let g = one(&v, "label", "LKNE");
    assert_eq!(
        (g["first"].as_u64(), g["last"].as_u64()),
        (Some(310), Some(319)),
        "{g}"
    );
    assert!(
        (g["first_time"].as_f64().unwrap() - time(310)).abs() < 1e-9,
        "{g}"
    );
    fields += on_the_files_base("repair --json", &v);
    let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let text = r.to_string();
    assert!(text.contains("380"), "the spike's frame: {text:.2000}");
    fields += on_the_files_base("repair --report", &r);

    // batch: the same gap in its per-file line.
    let input = d("in");
    std::fs::create_dir(&input).unwrap();
    std::fs::copy(&f, input.join("fmc.c3d")).unwrap();
    let v = json(&["batch", s(&input), "--out-dir", s(&d("out")), "--json"]);
    let g = one(&v, "label", "LKNE");
    assert_eq!(
        (g["first"].as_u64(), g["last"].as_u64()),
        (Some(310), Some(319)),
        "{g}"
    );
    fields += on_the_files_base("batch", &v);

    // diff: what the repair changed, at the file's frames.
    let v = json(&["diff", "--json", s(&f), s(&rep)]);
    let m = one(&v, "label", "LKNE");
    assert_eq!(
        (m["first_frame"].as_u64(), m["last_frame"].as_u64()),
        (Some(310), Some(319)),
        "{m}"
    );
    let m = one(&v, "label", "RANK");
    assert_eq!(m["first_frame"].as_u64(), Some(380), "{m}");
    fields += on_the_files_base("diff", &v);

    // forces and events: contacts and events on frames and times that agree.
    let v = json(&["forces", "--json", s(&f)]);
    let mut contacts = 0;
    for p in v["platforms"].as_array().unwrap() {
        for c in p["contacts"].as_array().unwrap() {
            let fr = c["first_frame"].as_u64().unwrap();
            assert!(
                (c["first_time"].as_f64().unwrap() - time(fr)).abs() < 0.01,
                "{c}"
            );
            contacts += 1;
        }
    }
    assert!(contacts >= 2, "{v:.300}");
    assert!((v["start_time"].as_f64().unwrap() - time(FIRST)).abs() < 1e-9);
    fields += on_the_files_base("forces", &v);
    let v = json(&["events", "--json", s(&f)]);
    for e in v["events"].as_array().unwrap() {
        let fr = e["frame"].as_u64().unwrap();
        assert!(
            (e["time"].as_f64().unwrap() - time(fr)).abs() <= 0.5 / RATE + 1e-9,
            "{e}"
        );
    }
    fields += on_the_files_base("events", &v);

    // Exports: the first row is the file's first frame at its time.
    let v = json(&["export", s(&f), "--format", "json"]);
    assert_eq!(v["first_frame"], FIRST);
    fields += on_the_files_base("export json", &v);
    let csv = stdout(&c3dfix(&["export", s(&f), "--format", "csv"]));
    assert!(
        csv.lines().nth(1).unwrap().starts_with("260,2.590000,"),
        "{csv:.300}"
    );
    let trc = stdout(&c3dfix(&["export", s(&f), "--format", "trc"]));
    assert!(
        trc.lines().nth(6).unwrap().starts_with("260\t2.590000\t"),
        "{trc:.600}"
    );
    let mot = d("f.mot");
    let out = c3dfix(&["export", s(&f), "--format", "mot", "-o", s(&mot)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&mot).unwrap();
    let rows: Vec<&str> = text
        .lines()
        .skip_while(|l| *l != "endheader")
        .skip(2)
        .collect();
    assert!(rows[0].starts_with("2.590000\t"), "{:?}", &rows[..2]);

    assert!(fields >= 50, "{fields} frame and time fields checked");
}
