//! `c3dfix swaps`: label swaps and jumps found in the demo walk, named by label and by the
//! file's own frame numbers; bad input answered clearly.

use super::{c3dfix, s, sample, stderr, stdout};
use c3d::{Analog, C3d, Parameters, Points, Processor};
use std::path::{Path, PathBuf};

/// `walk_float.c3d` (35 markers, 400 frames from frame 1, 0.4 mm noise and its own gaps)
/// edited by `edit`, written to `dir/name`.
fn edited(dir: &Path, name: &str, edit: impl FnOnce(&mut C3d)) -> PathBuf {
    let mut c = c3d::read_file(sample("walk_float.c3d")).unwrap();
    edit(&mut c);
    let p = dir.join(name);
    std::fs::write(&p, c.to_bytes().unwrap()).unwrap();
    p
}

/// Exchange the samples of points `a` and `b` over frames `lo..=hi` (0-based).
fn exchange(c: &mut C3d, a: &str, b: &str, lo: usize, hi: usize) {
    let (a, b) = (c.point_index(a).unwrap(), c.point_index(b).unwrap());
    let p = c.points_mut();
    for f in lo..=hi {
        let (i, j) = (p.index(f, a), p.index(f, b));
        p.xyz.swap(i, j);
        p.residual.swap(i, j);
        p.camera_mask.swap(i, j);
    }
}

fn json(path: &Path) -> serde_json::Value {
    let out = c3dfix(&["swaps", "--json", s(path)]);
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn swaps_on_the_untouched_walk_finds_nothing() {
    for f in ["walk_float.c3d", "walk_int.c3d", "walk_truth.c3d"] {
        let v = json(&sample(f));
        assert_eq!(v["frames"], 400, "{f}");
        assert_eq!(v["markers"], 35, "{f}");
        assert_eq!(v["swaps"].as_array().unwrap().len(), 0, "{f}: {v}");
    }
}

#[test]
fn swaps_finds_an_injected_swap_in_the_files_frame_numbers() {
    let dir = tempfile::tempdir().unwrap();
    // Two pelvis markers for 20 frames (0-based 150..=169: frames 151–170 of the file).
    let p = edited(dir.path(), "swapped.c3d", |c| {
        exchange(c, "LASI", "LPSI", 150, 169)
    });
    let v = json(&p);
    let finds = v["swaps"].as_array().unwrap();
    assert_eq!(finds.len(), 1, "{v}");
    let x = &finds[0];
    assert_eq!(x["kind"], "swap");
    assert_eq!(x["markers"], serde_json::json!(["LASI", "LPSI"]));
    assert_eq!(x["first_frame"], 151);
    assert_eq!(x["last_frame"], 170);
    assert!(x["confidence"].as_f64().unwrap() >= 0.5, "{x}");
    assert_eq!(x["settled"], true);
    // Text names the pair and the frames.
    let out = c3dfix(&["swaps", s(&p)]);
    let t = stdout(&out);
    assert!(
        t.contains("1 finds (1 settled) in 35 markers (400 frames)"),
        "{t}"
    );
    assert!(t.contains("swap LASI ↔ LPSI"), "{t}");
    assert!(t.contains("151–170"), "{t}");
}

#[test]
fn swaps_finds_a_jump_of_a_label_onto_a_stray_point() {
    let dir = tempfile::tempdir().unwrap();
    // RTHI 35 mm off for frames 201–215 of the file.
    let p = edited(dir.path(), "jumped.c3d", |c| {
        let m = c.point_index("RTHI").unwrap();
        let pts = c.points_mut();
        for f in 200..215 {
            let k = pts.index(f, m);
            pts.xyz[k][0] += 25.0;
            pts.xyz[k][2] -= 25.0;
        }
    });
    let v = json(&p);
    let finds = v["swaps"].as_array().unwrap();
    assert_eq!(finds.len(), 1, "{v}");
    let x = &finds[0];
    assert_eq!(x["kind"], "jump");
    assert_eq!(x["markers"], serde_json::json!(["RTHI"]));
    assert_eq!(x["first_frame"], 201);
    assert_eq!(x["last_frame"], 215);
}

/// A trial of `markers` × `frames` from frame 1, each marker a fixed offset from a moving
/// point (so every pair keeps its distance), all samples `valid` or none.
fn synthetic(path: &Path, markers: usize, frames: usize, valid: bool, labels: &[&str]) {
    let mut pts = Points::new(frames, markers);
    for f in 0..frames {
        for i in 0..markers {
            let k = pts.index(f, i);
            pts.xyz[k] = [f as f32 * 10.0 + 50.0 * i as f32, 30.0 * i as f32, 900.0];
            pts.residual[k] = if valid { 0.5 } else { -1.0 };
        }
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 100.0).unwrap();
    let labels: Vec<String> = labels.iter().map(|l| l.to_string()).collect();
    ps.set_strings("POINT", "LABELS", &labels).unwrap();
    let c = C3d::new(pts, Analog::new(frames, 0, 1), ps, Processor::Intel, -1.0);
    std::fs::write(path, c.to_bytes().unwrap()).unwrap();
}

fn refused(args: &[&str], expect: &str) {
    let out = c3dfix(args);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let e = stderr(&out);
    assert!(e.contains(expect), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    assert!(out.stdout.is_empty(), "partial output: {}", stdout(&out));
}

#[test]
fn swaps_answers_bad_input_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let one = d.join("one.c3d");
    synthetic(&one, 1, 100, true, &["A"]);
    refused(
        &["swaps", s(&one)],
        "needs at least 2 markers; the file has 1",
    );
    let two = d.join("two_frames.c3d");
    synthetic(&two, 4, 2, true, &["A", "B", "C", "D"]);
    refused(
        &["swaps", s(&two)],
        "needs at least 3 frames; the file has 2",
    );
    let none = d.join("all_missing.c3d");
    synthetic(&none, 4, 100, false, &["A", "B", "C", "D"]);
    refused(
        &["swaps", "--json", s(&none)],
        "every marker sample is missing",
    );

    // Labels given twice: each find names the point, and the output says so.
    let dup = d.join("duplicate.c3d");
    synthetic(&dup, 4, 100, true, &["A", "B", "A", "D"]);
    let v = json(&dup);
    assert_eq!(v["swaps"].as_array().unwrap().len(), 0, "{v}");
    let w = v["warnings"][0].as_str().unwrap();
    assert!(w.contains("label \"A\" names points 1, 3"), "{w}");

    // NaN coordinates are missing samples, never a panic; the injected swap is still
    // found with its edges.
    let nan = edited(d, "nan.c3d", |c| {
        exchange(c, "LASI", "LPSI", 150, 169);
        let m = c.point_index("RASI").unwrap();
        let pts = c.points_mut();
        for f in 100..110 {
            let k = pts.index(f, m);
            pts.xyz[k] = [f32::NAN; 3];
        }
    });
    let v = json(&nan);
    let finds = v["swaps"].as_array().unwrap();
    assert_eq!(finds.len(), 1, "{v}");
    assert_eq!(finds[0]["first_frame"], 151);
    assert_eq!(finds[0]["last_frame"], 170);
}

/// Every point sample of a file: coordinates, residual and camera mask, as decoded.
fn samples(path: &Path) -> (Vec<[f32; 3]>, Vec<f32>, Vec<u8>) {
    let c = c3d::read_file(path).unwrap();
    let p = c.points();
    (p.xyz.clone(), p.residual.clone(), p.camera_mask.clone())
}

fn repair_json(args: &[&str]) -> serde_json::Value {
    let out = c3dfix(args);
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn repair_swaps_fix_exchanges_a_swap_back_exactly_and_a_rerun_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Float and integer storage (the residual word and camera mask packed differently).
    for (base, name) in [
        ("walk_float.c3d", "swapped_float.c3d"),
        ("walk_int.c3d", "swapped_int.c3d"),
    ] {
        let mut c = c3d::read_file(sample(base)).unwrap();
        exchange(&mut c, "LASI", "LPSI", 150, 169);
        let p = d.join(name);
        std::fs::write(&p, c.to_bytes().unwrap()).unwrap();
        let out = d.join(format!("fixed_{name}"));
        // No fill: the swap stage alone changes the samples.
        let v = repair_json(&[
            "repair",
            s(&p),
            "-o",
            s(&out),
            "--swaps",
            "fix",
            "--fill",
            "none",
            "--json",
        ]);
        assert_eq!(v["swaps_undone"], 1, "{base}: {v}");
        let x = &v["swap_list"][0];
        assert_eq!(x["kind"], "swap");
        assert_eq!(x["markers"], serde_json::json!(["LASI", "LPSI"]));
        assert_eq!(
            (&x["first_frame"], &x["last_frame"]),
            (&151.into(), &170.into())
        );
        assert_eq!(x["action"], "undone");
        assert!(x["evidence"]["links"].as_u64().unwrap() > 0, "{x}");
        // 20 frames × 2 markers, every sample valid in the walk there.
        assert_eq!(v["samples_changed"], 40, "{base}: {v}");
        // Bit for bit the recorded samples: coordinates, residuals, camera masks.
        let (want, got) = (samples(&sample(base)), samples(&out));
        assert!(
            want.0 == got.0 && want.1 == got.1 && want.2 == got.2,
            "{base}"
        );

        // The file records what was undone; a second repair leaves it as it is.
        let c = c3d::read_file(&out).unwrap();
        assert_eq!(
            c.parameters.get_strings("C3DFIX", "SWAPS").unwrap(),
            vec!["--swaps fix".to_string()]
        );
        let lasi = c.point_index("LASI").unwrap() as f32 + 1.0;
        let lpsi = c.point_index("LPSI").unwrap() as f32 + 1.0;
        assert_eq!(
            c.param("C3DFIX", "UNDONE").unwrap().as_f32s(),
            vec![lasi.min(lpsi), lasi.max(lpsi), 151.0, 170.0]
        );
        let again = d.join(format!("again_{name}"));
        let w = repair_json(&[
            "repair",
            s(&out),
            "-o",
            s(&again),
            "--swaps",
            "fix",
            "--fill",
            "none",
            "--json",
        ]);
        assert_eq!(w["samples_changed"], 0, "{w}");
        assert_eq!(w["already_applied"][0], "swaps (--swaps fix)", "{w}");
        assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&again).unwrap());
    }
}

#[test]
fn repair_swaps_report_lists_the_find_and_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p = edited(d, "swapped.c3d", |c| exchange(c, "LASI", "LPSI", 150, 169));
    let out = d.join("reported.c3d");
    let report = d.join("report.json");
    let o = c3dfix(&[
        "repair",
        s(&p),
        "-o",
        s(&out),
        "--fill",
        "none",
        "--swaps",
        "report",
        "--report",
        s(&report),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = stdout(&o);
    assert!(
        t.contains("swap     LASI ↔ LPSI frames 151–170")
            && t.contains("reported (--swaps fix undoes it)"),
        "{t}"
    );
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(v["swaps"][0]["action"], "reported", "{v}");
    assert_eq!(v["swaps"][0]["first_frame"], 151);
    assert_eq!(v["summary"]["samples_changed"], 0);
    let (a, b) = (samples(&p), samples(&out));
    assert!(a.0 == b.0 && a.1 == b.1 && a.2 == b.2);
    // Off: not looked for.
    let off = d.join("off.c3d");
    let w = repair_json(&[
        "repair",
        s(&p),
        "-o",
        s(&off),
        "--fill",
        "none",
        "--swaps",
        "off",
        "--json",
    ]);
    assert!(w.get("swap_list").is_none(), "{w}");
    refused(
        &[
            "repair",
            s(&p),
            "-o",
            s(&d.join("x.c3d")),
            "--swaps",
            "undo",
        ],
        "expected fix, report or off",
    );
}

#[test]
fn repair_swaps_fix_refills_a_jump_near_the_recorded_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // RTHI 35 mm off for frames 201–215 of the file, then refilled by `auto`.
    let p = edited(d, "jumped.c3d", |c| {
        let m = c.point_index("RTHI").unwrap();
        let pts = c.points_mut();
        for f in 200..215 {
            let k = pts.index(f, m);
            pts.xyz[k][0] += 25.0;
            pts.xyz[k][2] -= 25.0;
        }
    });
    let out = d.join("fixed.c3d");
    let v = repair_json(&["repair", s(&p), "-o", s(&out), "--swaps", "fix", "--json"]);
    assert_eq!(v["jumps_to_gaps"], 1, "{v}");
    let x = &v["swap_list"][0];
    assert_eq!((&x["kind"], &x["action"]), (&"jump".into(), &"gap".into()));
    let g = v["gap_list"]
        .as_array()
        .unwrap()
        .iter()
        .find(|g| g["label"] == "RTHI" && g["first"] == 201)
        .unwrap_or_else(|| panic!("no gap at the jump: {v}"));
    assert_eq!(g["last"], 215);
    assert!(g["method"].is_string(), "{g}");
    let truth = c3d::read_file(sample("walk_float.c3d")).unwrap();
    let fixed = c3d::read_file(&out).unwrap();
    let m = truth.point_index("RTHI").unwrap();
    let mut err: Vec<f32> = (200..215)
        .map(|f| {
            let (a, b) = (
                truth.points().xyz[truth.points().index(f, m)],
                fixed.points().xyz[fixed.points().index(f, m)],
            );
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        })
        .collect();
    err.sort_by(f32::total_cmp);
    assert!(err[7] < 5.0, "median refill error {} mm: {err:?}", err[7]);
}

#[test]
fn repair_and_batch_with_swaps_on_too_little_to_judge_go_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let one = d.join("one.c3d");
    synthetic(&one, 1, 100, true, &["A"]);
    let v = repair_json(&[
        "repair",
        s(&one),
        "-o",
        s(&d.join("one_out.c3d")),
        "--swaps",
        "fix",
        "--json",
    ]);
    assert_eq!(
        v["swaps_note"],
        "finding swaps needs at least 2 markers; the file has 1"
    );
    // batch: every file's summary lists its finds.
    let src = d.join("in");
    std::fs::create_dir(&src).unwrap();
    edited(&src, "swapped.c3d", |c| {
        exchange(c, "LASI", "LPSI", 150, 169)
    });
    synthetic(&src.join("one.c3d"), 1, 100, true, &["A"]);
    let outdir = d.join("out");
    let o = c3dfix(&[
        "batch",
        s(&src),
        "--out-dir",
        s(&outdir),
        "--swaps",
        "fix",
        "--fill",
        "none",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = stdout(&o);
    assert!(t.contains("\"swaps_undone\":1"), "{t}");
    let (want, got) = (
        samples(&sample("walk_float.c3d")),
        samples(&outdir.join("swapped.c3d")),
    );
    assert!(want.0 == got.0 && want.1 == got.1 && want.2 == got.2);
}
