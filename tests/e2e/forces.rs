//! Force plates on the command line: `forces`, and the plates in `info`, the OpenSim MOT
//! export (with `--axes`, which TRC takes too) and `plot --forces`. The reference trial is
//! the c3d.org sample `sample_10/TYPE-2a.c3d`: two AMTI (type 2) plates at 960 Hz, 16
//! samples per 60 Hz frame, positions in mm.

use super::{c3dfix, s, sample, stderr, stdout};
use c3d::Value;
use serde_json::Value as Json;
use std::path::{Path, PathBuf};

/// `sample_10/TYPE-2a.c3d` of the c3d.org corpus, or `None` (after saying so) without it.
fn type2a() -> Option<PathBuf> {
    Some(
        testkit::c3d_samples()?
            .join("sample_10")
            .join("TYPE-2a.c3d"),
    )
}

fn forces_json(file: &Path) -> Json {
    let out = c3dfix(&["forces", "--json", s(file)]);
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).expect("forces --json is JSON")
}

fn xyz(v: &Json) -> [f64; 3] {
    let a = v.as_array().expect("a triple");
    [0, 1, 2].map(|k| a[k].as_f64().expect("a number"))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[test]
fn forces_reports_both_plates_of_the_amti_sample() {
    let Some(file) = type2a() else { return };
    let out = c3dfix(&["forces", s(&file)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let t = stdout(&out);
    assert!(
        t.contains("2 force platforms (COP where the push >= 10 N)"),
        "{t}"
    );
    assert!(
        // 528.0 N, not the raw 521.6: ZERO's frames read a pull of 6.3 N, now removed.
        t.contains("plate 1  type 2  channels 1,2,3,4,5,6  960 Hz  peak push 528.0 N  unloaded level -6.3 N subtracted (frames 1-10, FORCE_PLATFORM:ZERO)"),
        "{t}"
    );
    assert!(
        t.contains("plate 2  type 2  channels 7,8,9,10,11,12"),
        "{t}"
    );
    // Plate 1's stance: frames 108-141, samples 1725-2246 (16 samples per frame); with the
    // pull of 6.3 N removed the push reaches 10 N a sample earlier and leaves it 33 samples
    // later than the raw reading (frames 108-139, samples 1726-2213) did. Times on the
    // file's base: sample 1725 at 1725 / 960 s from frame 1.
    assert!(
        t.contains("contact frames 108-141 (samples 1725-2246, 1.797-2.340 s), peak 528.0 N"),
        "{t}"
    );
    assert!(t.contains("contact frames 134-164"), "{t}");

    let v = forces_json(&file);
    let plates = v["platforms"].as_array().unwrap();
    assert_eq!(plates.len(), 2);
    for key in [
        "index",
        "type",
        "rate",
        "channels",
        "corners",
        "centre",
        "origin",
        "force",
        "moment",
        "cop",
        "free_moment",
        "peak_force",
        "contacts",
        "baseline",
        "units",
    ] {
        assert!(plates[0].get(key).is_some(), "{key} missing");
    }
    assert_eq!(plates[0]["type"], 2);
    assert_eq!(plates[1]["index"], 2);
    assert_eq!(plates[0]["rate"], 960.0);
    assert_eq!(plates[0]["units"]["moment"], "Nmm");
    assert_eq!(plates[0]["force"].as_array().unwrap().len(), 360 * 16);
    assert_eq!(xyz(&plates[0]["centre"]), [254.0, 232.0, 0.0]);
    let c = &plates[0]["contacts"][0];
    assert_eq!(
        [&c["first_frame"], &c["last_frame"]],
        [&Json::from(108), &Json::from(141)]
    );
    assert!(close(
        c["first_time"].as_f64().unwrap(),
        1725.0 / 960.0,
        1e-12
    ));
    assert_eq!(plates[0]["baseline"]["source"], "FORCE_PLATFORM:ZERO");
    assert!(close(
        plates[0]["baseline"]["level"].as_f64().unwrap(),
        -6.3,
        0.01
    ));
    // One footfall, one contact: the raw reading's 8 were noise around a pull of 5.4 N.
    assert_eq!(plates[1]["contacts"].as_array().unwrap().len(), 1);
    // Unloaded: the COP and free moment are undefined, written as null; the force is not.
    assert_eq!(plates[0]["cop"][0], serde_json::json!([null, null, null]));
    assert_eq!(
        plates[0]["free_moment"][0],
        serde_json::json!([null, null, null])
    );
    assert!(plates[0]["force"][0][2].is_number());
    // Mid-stance on plate 1: the lab's Z is up, so the reaction's z is the body's weight
    // share: 421.631 N with ZERO's pull of 6.3 N removed (415.315 raw), and the COP moves by
    // the moments' offsets ZERO removes (382.125, 368.725 raw).
    let f = xyz(&plates[0]["force"][2000]);
    assert!(close(f[2], 421.6305, 1e-5), "{f:?}");
    let cop = xyz(&plates[0]["cop"][2000]);
    assert!(
        close(cop[0], 381.765, 1e-5) && close(cop[1], 364.06, 1e-5),
        "{cop:?}"
    );
    assert_eq!(v["warnings"], serde_json::json!([]));
}

#[test]
fn forces_on_a_file_without_plates_says_so() {
    let out = c3dfix(&["forces", s(&sample("walk_int.c3d"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("walk_int.c3d: no force platforms"));
    let out = c3dfix(&["forces", "--json", s(&sample("walk_int.c3d"))]);
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["platforms"], serde_json::json!([]));
}

/// A copy of `file` in `dir` with FORCE_PLATFORM changed by `edit`.
fn modified(file: &Path, dir: &Path, name: &str, edit: impl FnOnce(&mut c3d::C3d)) -> PathBuf {
    let mut c = c3d::read_file(file).unwrap();
    edit(&mut c);
    let out = dir.join(name);
    std::fs::write(&out, c.to_bytes().unwrap()).unwrap();
    out
}

#[test]
fn a_bad_plate_is_left_out_with_a_warning_and_the_other_computed() {
    let Some(file) = type2a() else { return };
    let dir = tempfile::tempdir().unwrap();
    let channel = modified(&file, dir.path(), "channel.c3d", |c| {
        let p = c.parameters.get("FORCE_PLATFORM", "CHANNEL").unwrap();
        let dims = p.dims.clone();
        let mut v: Vec<i16> = p.as_i32s().iter().map(|&x| x as i16).collect();
        v[6] = 99; // plate 2's first channel, beyond the file's 20
        c.parameters
            .set("FORCE_PLATFORM", "CHANNEL", dims, Value::Int(v))
            .unwrap();
    });
    let corners = modified(&file, dir.path(), "corners.c3d", |c| {
        let v = c
            .parameters
            .get("FORCE_PLATFORM", "CORNERS")
            .unwrap()
            .as_f32s();
        // Room for one plate's corners while USED says 2.
        c.parameters
            .set(
                "FORCE_PLATFORM",
                "CORNERS",
                vec![3, 4, 1],
                Value::Float(v[..12].to_vec()),
            )
            .unwrap();
    });
    let cal = modified(&file, dir.path(), "cal.c3d", |c| {
        c.parameters
            .set("FORCE_PLATFORM", "TYPE", vec![2], Value::Int(vec![4, 2]))
            .unwrap();
        assert!(c.parameters.remove("FORCE_PLATFORM", "CAL_MATRIX"));
    });
    for (path, plate, parameter, kept) in [
        (&channel, 2, "FORCE_PLATFORM:CHANNEL", 1),
        (&corners, 2, "FORCE_PLATFORM:CORNERS", 1),
        (&cal, 1, "FORCE_PLATFORM:CAL_MATRIX", 2),
    ] {
        let out = c3dfix(&["forces", s(path)]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains(&format!("warning: {}: plate {plate}: {parameter}", s(path))),
            "{err}"
        );
        let t = stdout(&out);
        assert!(t.contains("1 force platform "), "{t}");
        assert!(t.contains(&format!("plate {kept}  type 2")), "{t}");
        // The plate kept is computed as in the untouched file.
        let v = forces_json(path);
        let plates = v["platforms"].as_array().unwrap();
        assert_eq!(plates.len(), 1);
        assert_eq!(plates[0]["index"], kept);
        let w = v["warnings"].as_array().unwrap();
        assert!(
            w.iter().any(|w| w
                .as_str()
                .unwrap()
                .starts_with(&format!("plate {plate}: {parameter}"))),
            "{w:?}"
        );
        let peak = plates[0]["peak_force"].as_f64().unwrap();
        // The raw peaks 521.6 and 582.8 N plus the pulls of 6.3 and 5.4 N ZERO removes.
        let want = if kept == 1 { 528.0 } else { 588.2 };
        assert!((peak - want).abs() < 0.05, "{peak}");
        // info names the same plate and parameter.
        let out = c3dfix(&["info", s(path)]);
        assert!(
            stdout(&out).contains(&format!("- plate {plate}: {parameter}")),
            "{}",
            stdout(&out)
        );
    }
}

#[test]
fn info_lists_the_plates() {
    let Some(file) = type2a() else { return };
    let out = c3dfix(&["info", s(&file)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let t = stdout(&out);
    assert!(t.contains("plates       2 force platforms"), "{t}");
    assert!(
        // One contact per plate: the raw reading's 2 and 8 were noise around a pull of 6 N
        // crossing |Fz| = 10 N.
        t.contains("plate 1  type 2  channels 1,2,3,4,5,6  centre (254.0, 232.0, 0.0) mm  peak push 528.0 N  1 contact"),
        "{t}"
    );
    assert!(t.contains("plate 2  type 2  channels 7,8,9,10,11,12  centre (762.0, 325.0, 0.0) mm  peak push 588.2 N  1 contact"), "{t}");
    let out = c3dfix(&["info", "--json", s(&file)]);
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    let p = v["force_platforms"].as_array().unwrap();
    assert_eq!(p.len(), 2);
    assert_eq!(p[0]["type"], 2);
    assert_eq!(p[0]["channels"], serde_json::json!([1, 2, 3, 4, 5, 6]));
    assert_eq!(p[1]["contacts"], 1);
    assert_eq!(xyz(&p[1]["centre"]), [762.0, 325.0, 0.0]);
    assert_eq!(v["force_platform_warnings"], serde_json::json!([]));
    // A file without plates lists none (and says nothing of plates in text).
    let out = c3dfix(&["info", "--json", s(&sample("walk_int.c3d"))]);
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["force_platforms"], serde_json::json!([]));
    let out = c3dfix(&["info", s(&sample("walk_int.c3d"))]);
    assert!(!stdout(&out).contains("plates "));
}

/// A MOT file's header lines, column names and rows.
fn read_mot(path: &Path) -> (Vec<String>, Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .by_ref()
        .take_while(|l| *l != "endheader")
        .map(String::from)
        .collect();
    let columns: Vec<String> = lines
        .next()
        .unwrap()
        .split('\t')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| {
            l.split('\t')
                .map(|x| x.parse::<f64>().unwrap_or_else(|_| panic!("{x:?} in {l}")))
                .collect::<Vec<f64>>()
        })
        .collect();
    (header, columns, rows)
}

#[test]
fn mot_export_is_opensim_ground_reaction_in_si_units() {
    let Some(file) = type2a() else { return };
    let dir = tempfile::tempdir().unwrap();
    let mot = dir.path().join("grf.mot");
    let out = c3dfix(&["export", s(&file), "--format", "mot", "-o", s(&mot)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (header, columns, rows) = read_mot(&mot);
    assert_eq!(
        header,
        [
            "name TYPE-2a",
            "version=1",
            "nRows=5760",
            "nColumns=19",
            "inDegrees=yes"
        ]
    );
    assert_eq!(columns.len(), 19);
    assert_eq!(
        &columns[..10],
        [
            "time",
            "ground_force_1_vx",
            "ground_force_1_vy",
            "ground_force_1_vz",
            "ground_force_1_px",
            "ground_force_1_py",
            "ground_force_1_pz",
            "ground_torque_1_x",
            "ground_torque_1_y",
            "ground_torque_1_z"
        ]
    );
    assert_eq!(columns[18], "ground_torque_2_z");
    assert_eq!(rows.len(), 5760);
    assert!(rows
        .iter()
        .all(|r| r.len() == 19 && r.iter().all(|x| x.is_finite())));
    // Time from 0 at the analog rate.
    assert_eq!(rows[0][0], 0.0);
    assert!(close(rows[960][0], 1.0, 1e-9));

    let v = forces_json(&file);
    let p1 = &v["platforms"][0];
    // Loaded (sample 2000 on plate 1): force in N, COP mm → m, free moment N·mm → N·m.
    let (f, cop, tz) = (
        xyz(&p1["force"][2000]),
        xyz(&p1["cop"][2000]),
        xyz(&p1["free_moment"][2000]),
    );
    let r = &rows[2000];
    for k in 0..3 {
        assert!(close(r[1 + k], f[k], 1e-5), "{r:?} {f:?}");
        assert!(close(r[4 + k], cop[k] / 1000.0, 1e-5), "{r:?} {cop:?}");
        assert!((r[7 + k] - tz[k] / 1000.0).abs() < 2e-6, "{r:?} {tz:?}");
    }
    // 1.06042 N·m, not the raw 2.42175: ZERO's means of Fx, Fy and Mz, subtracted, were part
    // of the raw free moment.
    assert!(close(r[9], 1.060421, 1e-4), "{r:?}");
    // Unloaded (sample 0 on plate 1, COP null in JSON): no force or torque, at the centre.
    assert!(p1["cop"][0][0].is_null());
    assert_eq!(&rows[0][1..4], [0.0, 0.0, 0.0]);
    assert_eq!(&rows[0][4..7], [0.254, 0.232, 0.0]);
    assert_eq!(&rows[0][7..10], [0.0, 0.0, 0.0]);

    // --axes x,z,-y: OpenSim's Y is the lab's z (up), its Z the lab's −y.
    let yup = dir.path().join("yup.mot");
    let out = c3dfix(&[
        "export",
        s(&file),
        "--format",
        "mot",
        "--axes",
        "x,z,-y",
        "-o",
        s(&yup),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (_, _, turned) = read_mot(&yup);
    let (a, b) = (&rows[2000], &turned[2000]);
    for base in [1, 4, 7] {
        assert_eq!(b[base], a[base]);
        assert_eq!(b[base + 1], a[base + 2]);
        assert_eq!(b[base + 2], -a[base + 1] + 0.0);
    }
    assert!(b[2] > 400.0, "the vertical force is OpenSim's y: {b:?}");
}

#[test]
fn axes_must_be_a_rotation_and_mot_needs_plates() {
    let walk = sample("walk_int.c3d");
    let dir = tempfile::tempdir().unwrap();
    for (axes, why) in [
        ("x,y,-z", "not a rotation"),
        ("x,z,y", "not a rotation"),
        ("x,x,z", "used twice"),
        ("x,y", "expected three lab axes"),
        ("x,y,w", "is no lab axis"),
    ] {
        let out_path = dir.path().join("out.trc");
        let out = c3dfix(&[
            "export",
            s(&walk),
            "--format",
            "trc",
            "--axes",
            axes,
            "-o",
            s(&out_path),
        ]);
        assert_eq!(out.status.code(), Some(2), "{axes}");
        assert!(stderr(&out).contains(why), "{axes}: {}", stderr(&out));
        assert!(!out_path.exists());
    }
    let out = c3dfix(&["export", s(&walk), "--format", "csv", "--axes", "x,z,-y"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--axes applies to --format trc, mot and opensim only"));

    let mot = dir.path().join("walk.mot");
    let out = c3dfix(&["export", s(&walk), "--format", "mot", "-o", s(&mot)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("walk_int.c3d: no force platforms: nothing to write as MOT"),
        "{}",
        stderr(&out)
    );
    assert!(!mot.exists());
}

#[test]
fn trc_export_turns_the_markers_with_axes() {
    let walk = sample("walk_int.c3d");
    let plain = c3dfix(&["export", s(&walk), "--format", "trc"]);
    let turned = c3dfix(&["export", s(&walk), "--format", "trc", "--axes", "x,z,-y"]);
    assert!(turned.status.success(), "{}", stderr(&turned));
    let (a, b) = (stdout(&plain), stdout(&turned));
    let (a, b): (Vec<&str>, Vec<&str>) = (a.lines().collect(), b.lines().collect());
    assert_eq!(a.len(), b.len());
    // Five header lines and a blank one, the same either way.
    assert_eq!(a[..6], b[..6]);
    let mut compared = 0;
    for (ra, rb) in a[6..].iter().zip(&b[6..]) {
        let (fa, fb): (Vec<&str>, Vec<&str>) = (ra.split('\t').collect(), rb.split('\t').collect());
        assert_eq!(fa[..2], fb[..2]);
        for m in 0..(fa.len() - 2) / 3 {
            let (x, y, z) = (fa[2 + 3 * m], fa[3 + 3 * m], fa[4 + 3 * m]);
            if x == "NaN" {
                // A missing sample is NaN in all three fields, so every row is whole.
                assert!(fb[2 + 3 * m..5 + 3 * m].iter().all(|v| *v == "NaN"));
                assert_eq!((y, z), ("NaN", "NaN"));
                continue;
            }
            let num = |t: &str| t.parse::<f32>().unwrap();
            assert_eq!(num(fb[2 + 3 * m]), num(x));
            assert_eq!(num(fb[3 + 3 * m]), num(z));
            assert_eq!(num(fb[4 + 3 * m]), -num(y));
            compared += 1;
        }
    }
    assert!(compared > 10_000, "{compared}");
}

#[test]
fn plot_forces_draws_the_vertical_force_and_the_cop_over_the_plates() {
    let Some(file) = type2a() else { return };
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("grf.svg");
    let out = c3dfix(&["plot", s(&file), "--forces", "-o", s(&svg)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    for want in [
        "TYPE-2a.c3d: force plates",
        "vertical ground reaction (lab Z)",
        "Fz (N)",
        "Time (s)",
        "centre of pressure, seen from above",
        "lab X (mm)",
        "lab Y (mm)",
        "plate 1",
        "plate 2",
    ] {
        assert!(text.contains(want), "{want} missing");
    }
    // One filled outline per plate.
    assert_eq!(text.matches("<polygon").count(), 2);
    let png = dir.path().join("grf.png");
    let out = c3dfix(&["plot", s(&file), "--forces", "-o", s(&png)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));

    // No plates: refused, nothing written; --forces draws no markers.
    let none = dir.path().join("none.svg");
    let out = c3dfix(&[
        "plot",
        s(&sample("walk_int.c3d")),
        "--forces",
        "-o",
        s(&none),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("no force platforms"),
        "{}",
        stderr(&out)
    );
    assert!(!none.exists());
    let out = c3dfix(&[
        "plot",
        s(&file),
        "--forces",
        "--marker",
        "RKNE",
        "-o",
        s(&none),
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn mot_export_of_every_plate_type_in_the_corpora_is_complete_and_finite() {
    let (Some(samples), Some(extra)) = (testkit::c3d_samples(), testkit::c3d_extra()) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let files = [
        samples.join("sample_10").join("TYPE-2a.c3d"),
        samples.join("sample_10").join("TYPE-4a.c3d"),
        samples.join("sample_10").join("TYPE-3.c3d"),
        extra.join("btkdata_Gait.c3d"),
    ];
    let mut types = std::collections::BTreeSet::new();
    for file in &files {
        let v = forces_json(file);
        let plates = v["platforms"].as_array().unwrap();
        assert!(!plates.is_empty(), "{}", file.display());
        let mot = dir.path().join("out.mot");
        let out = c3dfix(&[
            "export",
            s(file),
            "--format",
            "mot",
            "--axes",
            "x,z,-y",
            "--force",
            "-o",
            s(&mot),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let (header, columns, rows) = read_mot(&mot);
        let samples = plates[0]["force"].as_array().unwrap().len();
        assert_eq!(columns.len(), 1 + 9 * plates.len(), "{}", file.display());
        assert_eq!(header[2], format!("nRows={samples}"));
        assert_eq!(header[3], format!("nColumns={}", columns.len()));
        assert_eq!(rows.len(), samples);
        assert!(rows
            .iter()
            .all(|r| r.len() == columns.len() && r.iter().all(|x| x.is_finite())));
        for (k, p) in plates.iter().enumerate() {
            types.insert(p["type"].as_i64().unwrap());
            assert_eq!(
                columns[1 + 9 * k],
                format!("ground_force_{}_vx", p["index"])
            );
            // The vertical force (OpenSim's y) at the plate's peak matches forces' lab z.
            let fz: Vec<f64> = p["force"]
                .as_array()
                .unwrap()
                .iter()
                .map(|f| f[2].as_f64().unwrap_or(0.0))
                .collect();
            let i = (0..fz.len())
                .max_by(|&a, &b| fz[a].abs().total_cmp(&fz[b].abs()))
                .unwrap();
            // Rows outside the plate's contacts are no load in the MOT (see `mot`).
            let in_contact = p["contacts"].as_array().unwrap().iter().any(|c| {
                (c["first_sample"].as_u64().unwrap()..=c["last_sample"].as_u64().unwrap())
                    .contains(&(i as u64))
            });
            if p["cop"][i][0].is_number() && in_contact {
                assert!(close(rows[i][2 + 9 * k], fz[i], 1e-5), "{}", file.display());
            }
        }
    }
    assert_eq!(types.into_iter().collect::<Vec<_>>(), [2, 3, 4]);
}

/// The user's trial (`walking2`: plates resting at a pull of 14 and 20 N): in the MOT every
/// row outside the footfall is exactly zero in force and torque, the COP at the plate's
/// centre; `--no-zero-baseline` keeps the raw values; `plot --forces` takes the same options.
#[test]
fn an_unloaded_plate_is_exactly_zero_in_the_mot() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let file = more.join("opensim-org__opensim-core__walking2.c3d");
    let dir = tempfile::tempdir().unwrap();
    let mot = dir.path().join("w.mot");
    let out = c3dfix(&["export", s(&file), "--format", "mot", "-o", s(&mot)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&mot).unwrap();
    let rows: Vec<Vec<f64>> = text
        .split("endheader\n")
        .nth(1)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split('\t').map(|x| x.parse().unwrap()).collect())
        .collect();
    let v = forces_json(&file);
    for (k, p) in v["platforms"].as_array().unwrap().iter().enumerate() {
        let contacts = p["contacts"].as_array().unwrap();
        assert_eq!(contacts.len(), 1, "plate {}", k + 1);
        let (a, b) = (
            contacts[0]["first_sample"].as_u64().unwrap() as usize,
            contacts[0]["last_sample"].as_u64().unwrap() as usize,
        );
        let col = 1 + 9 * k;
        let mut unloaded = 0;
        for (i, r) in rows.iter().enumerate() {
            if i < a || i > b {
                unloaded += 1;
                assert_eq!(&r[col..col + 3], [0.0; 3], "row {i}");
                assert_eq!(&r[col + 6..col + 9], [0.0; 3], "row {i}");
            }
        }
        assert!(unloaded > rows.len() / 2, "{unloaded} of {}", rows.len());
    }
    let out = c3dfix(&["forces", s(&file), "--no-zero-baseline"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stdout(&out).contains("unloaded level"), "{}", stdout(&out));
    let png = dir.path().join("f.svg");
    let out = c3dfix(&[
        "plot",
        s(&file),
        "--forces",
        "--threshold",
        "20",
        "--no-zero-baseline",
        "--lowpass",
        "butterworth:4:50",
        "-o",
        s(&png),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = c3dfix(&[
        "plot",
        s(&file),
        "--marker",
        "X",
        "--threshold",
        "20",
        "-o",
        s(&png),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

/// Frames and times on the file's own base: `FMC_MH0222_BP15` starts at frame 260 (100 Hz),
/// so its first sample is at 2.59 s, and plate 3's contact starts at the file's Right Foot
/// Strike (3.273 s) within a frame.
#[test]
fn contacts_and_times_are_on_the_files_base() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let file = more.join("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d");
    let v = forces_json(&file);
    assert!(
        close(v["start_time"].as_f64().unwrap(), 2.59, 1e-9),
        "{}",
        v["start_time"]
    );
    let p3 = &v["platforms"][2];
    let k = &p3["contacts"][0];
    assert_eq!(k["first_frame"], 328);
    assert!(
        (k["first_time"].as_f64().unwrap() - 3.273).abs() < 0.01,
        "{k}"
    );
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("f.csv");
    let out = c3dfix(&["forces", s(&file), "-o", s(&csv)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("contact frames 328-388"),
        "{}",
        stdout(&out)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let first: f64 = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(close(first, 2.59, 1e-9), "{first}");
}

/// `export --format opensim` writes NAME.trc and NAME.mot into --out-dir, turned so that the
/// plates' up (+z) is OpenSim's Y; `export --format mot` takes the plate options of `forces`.
#[test]
fn opensim_export_writes_both_files_y_up_and_mot_takes_the_plate_options() {
    let Some(file) = type2a() else { return };
    let top = tempfile::tempdir().unwrap();
    // A folder that does not exist yet is made, as `batch --out-dir` makes its folders.
    let dir = top.path().join("opensim/trial");
    let out = c3dfix(&[
        "export",
        s(&file),
        "--format",
        "opensim",
        "--out-dir",
        s(&dir),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("up +z from the force plates"),
        "{}",
        stdout(&out)
    );
    let (trc, mot) = (
        dir.as_path().join("TYPE-2a.trc"),
        dir.as_path().join("TYPE-2a.mot"),
    );
    let (_, columns, rows) = read_mot(&mot);
    assert_eq!(columns[2], "ground_force_1_vy");
    let plain = dir.as_path().join("plain.mot");
    let out = c3dfix(&["export", s(&file), "--format", "mot", "-o", s(&plain)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (_, _, lab) = read_mot(&plain);
    // The lab's vertical force (z) is OpenSim's y, whatever the direction of travel.
    for i in [0, 2000, 4000] {
        assert_eq!(rows[i][2], lab[i][3], "row {i}");
    }
    let text = std::fs::read_to_string(&trc).unwrap();
    assert!(text.starts_with("PathFileType\t4\t(X/Y/Z)\tTYPE-2a.c3d\n"));
    // Written again only with --force.
    let out = c3dfix(&[
        "export",
        s(&file),
        "--format",
        "opensim",
        "--out-dir",
        s(dir.as_path()),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("exists"), "{}", stderr(&out));

    // The plate options of `forces`: a higher threshold leaves more rows unloaded.
    let high = dir.as_path().join("high.mot");
    let out = c3dfix(&[
        "export",
        s(&file),
        "--format",
        "mot",
        "--threshold",
        "400",
        "-o",
        s(&high),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (_, _, hi) = read_mot(&high);
    let unloaded = |rows: &[Vec<f64>]| rows.iter().filter(|r| r[3] == 0.0).count();
    assert!(
        unloaded(&hi) > unloaded(&lab),
        "{} {}",
        unloaded(&hi),
        unloaded(&lab)
    );
    let out = c3dfix(&["export", s(&file), "--format", "opensim"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--format opensim needs --out-dir DIR"));
}

/// `--markers` chooses the exported points, in the order given; an unknown label is an
/// error that lists the file's labels.
#[test]
fn markers_choose_the_exported_points() {
    let walk = sample("walk_int.c3d");
    let out = c3dfix(&[
        "export",
        s(&walk),
        "--format",
        "trc",
        "--markers",
        "RKNE,LASI",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[2].starts_with("100\t100\t400\t2\tmm"), "{}", lines[2]);
    assert_eq!(lines[3], "Frame#\tTime\tRKNE\t\t\tLASI\t\t");
    assert!(lines[6..].iter().all(|l| l.split('\t').count() == 8));
    let out = c3dfix(&["export", s(&walk), "--format", "csv", "--markers", "NOPE"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("no marker \"NOPE\""),
        "{}",
        stderr(&out)
    );
}

#[test]
fn info_counts_a_plates_origin_warning_among_the_files_warnings() {
    // rtosim's two plates store their ORIGIN from the other end: a fault of the file, said
    // under info's warnings (once, not again among the plates' own).
    let Some(labs) = testkit::c3d_labs() else {
        return;
    };
    let file = labs.join("RealTimeBiomechanics__rtosim__walking_1.c3d");
    let out = c3dfix(&["info", "--json", s(&file)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    let w = v["warnings"].as_array().unwrap();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w[0]
        .as_str()
        .unwrap()
        .starts_with("plate 1: FORCE_PLATFORM:ORIGIN x and y are -241.3, -819"));
    assert_eq!(v["force_platform_warnings"], serde_json::json!([]));
    let t = stdout(&c3dfix(&["info", s(&file)]));
    assert!(!t.contains("warnings     none"), "{t}");
}
