//! Gait cycles on the command line: `c3dfix cycles`. The references are two trials whose
//! labs marked their foot strikes: c3d-more's `tsalemink__C3D-parser__FMC_MH0222_BP15.c3d`
//! (100 Hz from frame 260, four plates at 1000 Hz, three strikes of each foot) and
//! c3d-samples' `sample_11/2198928.c3d` (60 Hz, Plug-in Gait angles as points, two strikes of
//! each foot).

use super::{c3dfix, s, stderr, stdout};
use c3d::{Analog, C3d, Parameters, Points, Processor, Value};
use serde_json::Value as Json;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

fn fmc() -> Option<PathBuf> {
    Some(testkit::c3d_more()?.join("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d"))
}

/// A CSV as its header and rows of cells (an empty cell: None).
struct Table {
    head: Vec<String>,
    rows: Vec<Vec<Option<String>>>,
}

impl Table {
    fn parse(text: &str) -> Table {
        let mut lines = text.lines();
        let head = lines
            .next()
            .expect("a header")
            .split(',')
            .map(String::from)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|c| (!c.is_empty()).then(|| c.to_string()))
                    .collect()
            })
            .collect();
        Table { head, rows }
    }

    fn col(&self, name: &str) -> usize {
        self.head
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.head))
    }

    fn f(&self, row: usize, name: &str) -> f64 {
        self.rows[row][self.col(name)]
            .as_deref()
            .map_or(f64::NAN, |c| c.parse().unwrap())
    }

    fn text(&self, row: usize, name: &str) -> String {
        self.rows[row][self.col(name)].clone().unwrap_or_default()
    }
}

fn cycles_csv(dir: &Path, args: &[&str]) -> Table {
    let out_path = dir.join("cycles.csv");
    let mut all = vec!["cycles", "-o", s(&out_path), "--force"];
    all.extend_from_slice(args);
    let out = c3dfix(&all);
    assert!(out.status.success(), "{}", stderr(&out));
    Table::parse(&std::fs::read_to_string(&out_path).unwrap())
}

/// The lab's Foot Strike times of each side, from `info --json`.
fn lab_strikes(file: &Path) -> HashMap<String, Vec<f64>> {
    let out = c3dfix(&["info", "--json", s(file)]);
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    let mut m: HashMap<String, Vec<f64>> = HashMap::new();
    for e in v["events"].as_array().unwrap() {
        if e["label"] == "Foot Strike" {
            m.entry(e["context"].as_str().unwrap().to_string())
                .or_default()
                .push(e["time"].as_f64().unwrap());
        }
    }
    for t in m.values_mut() {
        t.sort_by(f64::total_cmp);
    }
    m
}

/// `(time, value)` samples of one column of an export CSV (`Time` and `name`), missing
/// samples left out.
fn series(table: &Table, name: &str) -> Vec<(f64, Option<f64>)> {
    (0..table.rows.len())
        .map(|r| {
            let v = table.rows[r][table.col(name)]
                .as_deref()
                .map(|c| c.parse().unwrap());
            (table.f(r, "Time"), v)
        })
        .collect()
}

/// Linear interpolation of `(time, value)` samples at `t` (None where a neighbour is missing).
fn interp(samples: &[(f64, Option<f64>)], t: f64) -> Option<f64> {
    let i = samples.iter().rposition(|(ts, _)| *ts <= t + 1e-9)?;
    let (t0, v0) = samples[i];
    if (t - t0).abs() < 1e-9 {
        return v0;
    }
    let (t1, v1) = *samples.get(i + 1)?;
    Some(v0? + (v1? - v0?) * (t - t0) / (t1 - t0))
}

#[test]
fn cycles_run_between_the_labs_strikes_and_read_the_markers_on_the_files_time_base() {
    let Some(file) = fmc() else { return };
    let dir = tempfile::tempdir().unwrap();
    let t = cycles_csv(dir.path(), &[s(&file), "--markers", "LHEE,RTOE"]);
    let strikes = lab_strikes(&file);
    // Three strikes per foot: two cycles each, 101 rows per cycle.
    let close = |a: &[f64], b: &[f64]| {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
    };
    assert!(
        close(&strikes["Left"], &[2.79, 3.773, 4.74]),
        "{:?}",
        strikes["Left"]
    );
    assert!(
        close(&strikes["Right"], &[3.273, 4.25, 5.19]),
        "{:?}",
        strikes["Right"]
    );
    assert_eq!(t.rows.len(), 4 * 101);
    let mut seen = Vec::new();
    for r in (0..t.rows.len()).step_by(101) {
        let side = t.text(r, "side");
        let n: usize = t.text(r, "cycle").parse().unwrap();
        let (start, end) = (t.f(r, "start_time"), t.f(r, "end_time"));
        let st = &strikes[&side];
        assert!((start - st[n - 1]).abs() < 1e-6 && (end - st[n]).abs() < 1e-6);
        // Frames on the file's numbering: first frame 260 at 2.59 s, so 2.79 s is frame 280.
        let frame: usize = t.text(r, "start_frame").parse().unwrap();
        assert_eq!(frame, (start * 100.0).round() as usize + 1);
        assert_eq!(t.f(r, "percent"), 0.0);
        assert_eq!(t.f(r + 100, "percent"), 100.0);
        assert!((t.f(r + 100, "time") - end).abs() < 1e-6);
        assert!((t.f(r + 50, "time") - (start + end) / 2.0).abs() < 1e-6);
        seen.push((side, n, frame));
    }
    assert_eq!(
        seen,
        vec![
            ("Left".into(), 1, 280),
            ("Left".into(), 2, 378),
            ("Right".into(), 1, 328),
            ("Right".into(), 2, 426)
        ]
    );
    // Every value is the marker's trajectory (export's CSV, same time base) interpolated
    // at the row's time.
    let export = dir.path().join("points.csv");
    let out = c3dfix(&[
        "export",
        s(&file),
        "--format",
        "csv",
        "--markers",
        "LHEE,RTOE",
        "-o",
        s(&export),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let e = Table::parse(&std::fs::read_to_string(&export).unwrap());
    assert_eq!(e.f(0, "Time"), 2.59);
    let mut compared = 0;
    for (col, exp) in [("LHEE_z (mm)", "LHEE_Z"), ("RTOE_x (mm)", "RTOE_X")] {
        let trace = series(&e, exp);
        for r in 0..t.rows.len() {
            let want = interp(&trace, t.f(r, "time"));
            let got = t.f(r, "percent").is_finite().then(|| t.f(r, col));
            match want {
                Some(w) => {
                    let g = got.unwrap();
                    assert!((g - w).abs() < 1e-3, "{col} row {r}: {g} against {w}");
                    compared += 1;
                }
                None => assert!(t.f(r, col).is_nan(), "{col} row {r}: a value in a gap"),
            }
        }
    }
    assert!(compared > 700, "{compared}");
    // The heel is low at its own strike: within 30 mm of its lowest over the cycle.
    let r = 0;
    let low = (r..r + 101)
        .map(|k| t.f(k, "LHEE_z (mm)"))
        .fold(f64::INFINITY, f64::min);
    assert!(
        t.f(r, "LHEE_z (mm)") - low < 30.0,
        "{}",
        t.f(r, "LHEE_z (mm)")
    );
}

#[test]
fn plate_forces_over_a_cycle_rise_at_the_strike_and_end_at_the_labs_foot_off() {
    let Some(file) = fmc() else { return };
    let dir = tempfile::tempdir().unwrap();
    let t = cycles_csv(
        dir.path(),
        &[
            s(&file),
            "--forces",
            "--side",
            "left",
            "--analog",
            "Force.Fz2",
        ],
    );
    assert_eq!(t.rows.len(), 2 * 101);
    assert!(t.head.contains(&"FP4_Fz (N)".to_string()), "{:?}", t.head);
    // The first left cycle lands on no plate: plate 2 is loaded only as the next strike
    // comes down on it (3.771 s, the last 0.2 % of the cycle).
    assert!((0..100).all(|k| t.f(k, "FP2_Fz (N)").abs() < 10.0));
    assert!(
        !t.head.iter().any(|h| h.starts_with("LHEE")),
        "{:?}",
        t.head
    );
    // The second left cycle (3.773 to 4.740 s) lands on plate 2 (its contact 3.771 to
    // 4.369 s, `forces`); the lab's Left Foot Off is at 4.365 s: 61.2 % of the cycle.
    let off = (4.365 - 3.773) / (4.74 - 3.773) * 100.0;
    let r0 = 101;
    let loaded: Vec<usize> = (0..=100)
        .filter(|&k| t.f(r0 + k, "FP2_Fz (N)").abs() > 10.0)
        .collect();
    assert!(!loaded.is_empty());
    let (first, last) = (loaded[0], *loaded.last().unwrap());
    assert!(first <= 1, "loaded from {first} %");
    assert!(
        (last as f64 - off).abs() <= 1.5,
        "unloaded after {last} %, lab {off:.1} %"
    );
    // The plate's own Fz channel, read as an analog channel at its own rate, is the lab's
    // vertical force turned round (the plate's z points down; its unloaded level is 0 N).
    for k in 0..t.rows.len() {
        let (a, f) = (t.f(k, "Force.Fz2 (N)"), t.f(k, "FP2_Fz (N)"));
        assert!((a + f).abs() < 1e-3, "row {k}: channel {a}, plate {f}");
    }
    // Body weight is carried in between (a vertical force of several hundred newtons).
    let peak = loaded
        .iter()
        .map(|&k| t.f(r0 + k, "FP2_Fz (N)").abs())
        .fold(0.0, f64::max);
    assert!(peak > 600.0 && peak < 1200.0, "{peak}");
    // The same force as `forces --json` gives, interpolated at the row's time.
    let out = c3dfix(&["forces", "--json", s(&file)]);
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    let start = v["start_time"].as_f64().unwrap();
    let fz: Vec<(f64, Option<f64>)> = v["platforms"][1]["force"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, f)| (start + i as f64 / 1000.0, f[2].as_f64()))
        .collect();
    for k in 0..=100 {
        let want = interp(&fz, t.f(r0 + k, "time")).unwrap();
        let got = t.f(r0 + k, "FP2_Fz (N)");
        // The CSV's time is printed to the microsecond (a thousandth of a sample here), and
        // a force changes by a few newtons per sample: within 0.05 N.
        assert!((got - want).abs() < 0.05, "{k} %: {got} against {want}");
    }
}

#[test]
fn angles_keep_their_unit_and_each_side_is_asked_for_alone() {
    let Some(dir11) = testkit::c3d_samples() else {
        return;
    };
    let file = dir11.join("sample_11").join("2198928.c3d");
    let dir = tempfile::tempdir().unwrap();
    let t = cycles_csv(
        dir.path(),
        &[s(&file), "--side", "right", "--markers", "RKneeAngles,RANK"],
    );
    // Right strikes at 0.675 and 1.45 s: one cycle, frames 42 and 88 at 60 Hz.
    assert_eq!(t.rows.len(), 101);
    assert_eq!(t.text(0, "side"), "Right");
    assert_eq!(t.text(0, "start_frame"), "42");
    assert_eq!(t.text(0, "end_frame"), "88");
    // Plug-in Gait's knee flexion is degrees, never scaled as a length: near extension at
    // the strike, 50–75° in swing.
    let flex: Vec<f64> = (0..101).map(|k| t.f(k, "RKneeAngles_x (deg)")).collect();
    assert!(flex[0].abs() < 15.0, "{}", flex[0]);
    let max = flex.iter().copied().fold(f64::MIN, f64::max);
    assert!((40.0..75.0).contains(&max), "{max}");
    assert!(t.head.contains(&"RANK_x (mm)".to_string()));
    // Left alone: one cycle from 0.288 s.
    let l = cycles_csv(
        dir.path(),
        &[s(&file), "--side", "left", "--markers", "LANK"],
    );
    assert_eq!(l.rows.len(), 101);
    assert!((l.f(0, "start_time") - 0.288333).abs() < 1e-5);
}

#[test]
fn detected_strikes_cut_cycles_within_two_frames_of_the_labs() {
    let Some(file) = fmc() else { return };
    let dir = tempfile::tempdir().unwrap();
    let t = cycles_csv(dir.path(), &[s(&file), "--detect", "--markers", "LHEE"]);
    let strikes = lab_strikes(&file);
    let mut n = 0;
    for r in (0..t.rows.len()).step_by(101) {
        let st = &strikes[&t.text(r, "side")];
        let start = t.f(r, "start_time");
        let near = st
            .iter()
            .map(|x| (x - start).abs())
            .fold(f64::MAX, f64::min);
        assert!(near <= 0.025, "{start}: {near} s from the lab's");
        n += 1;
    }
    assert!(n >= 3, "{n} cycles");
}

/// A 100 Hz float trial of one marker moving along x at 1 m/s, with the given events.
fn write_trial(path: &Path, frames: usize, events: &[(&str, &str, f32)]) {
    let mut pts = Points::new(frames, 1);
    for f in 0..frames {
        let k = pts.index(f, 0);
        pts.xyz[k] = [f as f32 * 10.0, 0.0, 900.0];
        pts.residual[k] = if f == 50 { -1.0 } else { 0.5 };
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 100.0).unwrap();
    ps.set_strings("POINT", "LABELS", &["SACR".into()]).unwrap();
    ps.set_strings("POINT", "UNITS", &["mm".into()]).unwrap();
    ps.set_i16("EVENT", "USED", events.len() as i16).unwrap();
    let times: Vec<f32> = events.iter().flat_map(|e| [0.0, e.2]).collect();
    ps.set(
        "EVENT",
        "TIMES",
        vec![2, events.len() as u8],
        Value::Float(times),
    )
    .unwrap();
    let ctx: Vec<String> = events.iter().map(|e| e.0.to_string()).collect();
    let lab: Vec<String> = events.iter().map(|e| e.1.to_string()).collect();
    ps.set_strings("EVENT", "CONTEXTS", &ctx).unwrap();
    ps.set_strings("EVENT", "LABELS", &lab).unwrap();
    let c = C3d::new(pts, Analog::new(frames, 0, 1), ps, Processor::Intel, -1.0);
    std::fs::write(path, c.to_bytes().unwrap()).unwrap();
}

#[test]
fn gaps_stay_missing_and_events_outside_the_trial_are_said() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("walk.c3d");
    // 200 frames (0 to 1.99 s); a left cycle 0.1–1.1 s, a right one reaching past the end.
    write_trial(
        &p,
        200,
        &[
            ("Left", "Foot Strike", 0.1),
            ("Left", "Foot Strike", 1.1),
            ("Right", "Foot Strike", 1.5),
            ("Right", "Foot Strike", 2.5),
        ],
    );
    let out_path = dir.path().join("c.csv");
    let out = c3dfix(&["cycles", s(&p), "-o", s(&out_path)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(
            "Right cycle 1.5000–2.5000 s left out: it reaches outside the trial (0.0000–1.9900 s)"
        ),
        "{}",
        stderr(&out)
    );
    assert!(
        stdout(&out).contains("1 cycles (1 left, 0 right)"),
        "{}",
        stdout(&out)
    );
    let t = Table::parse(&std::fs::read_to_string(&out_path).unwrap());
    assert_eq!(t.rows.len(), 101);
    // x = 10 mm per frame: at k % the time is 0.1 + 0.01 k s, frame 10 + k, x = 100 + 10 k;
    // frame 50 is missing, so 40 % (on it) is empty, and nothing else is.
    for k in 0..=100 {
        let x = t.f(k, "SACR_x (mm)");
        if k == 40 {
            assert!(x.is_nan(), "a value invented in the gap: {x}");
        } else {
            assert!((x - (100.0 + 10.0 * k as f64)).abs() < 1e-3, "{k} %: {x}");
        }
    }
    // Only out-of-trial cycles, or no strikes: a clear error, exit 2, nothing written.
    for (name, events, expect) in [
        (
            "outside.c3d",
            vec![("Left", "Foot Strike", 3.0), ("Left", "Foot Strike", 4.0)],
            "no complete gait cycle in the trial (Foot Strike events from the file's EVENT group: Left 2, Right 0",
        ),
        (
            "none.c3d",
            vec![("Left", "Foot Off", 0.5)],
            "Left 0, Right 0",
        ),
    ] {
        let p = dir.path().join(name);
        write_trial(&p, 200, &events);
        let o = dir.path().join(format!("{name}.csv"));
        let out = c3dfix(&["cycles", s(&p), "-o", s(&o)]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        let e = stderr(&out);
        assert!(e.contains(name) && e.contains(expect), "{name}: {e}");
        assert!(!e.contains("panicked"), "{e}");
        assert!(!o.exists());
    }
    // Options that make no sense.
    for (args, expect) in [
        (
            vec!["--side", "middle"],
            "--side middle: expected left, right or both",
        ),
        (vec!["--analog", "EMG9"], "no analog channel \"EMG9\""),
        (vec!["--markers", "NOPE"], "no marker \"NOPE\""),
        (vec!["--forces"], "no force plate"),
    ] {
        let mut all = vec!["cycles", s(&p)];
        all.extend(args.iter().copied());
        let out = c3dfix(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(expect), "{args:?}: {}", stderr(&out));
    }
}
