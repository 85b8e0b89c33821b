//! Gait events on the command line: `c3dfix events`. The reference is a Nexus trial of
//! c3d-more, `tsalemink__C3D-parser__RBWH_bfnd_w1.c3d` (100 Hz, first frame 211, three
//! plates, seven Foot Strike / Foot Off events of its lab), and the repository's synthetic
//! walk `walk_truth.c3d` (strides of 1/0.9 s) where no corpus is needed.

use super::{c3dfix, s, sample, stderr, stdout};
use c3d::{Analog, C3d, Parameters, Points, Processor};
use serde_json::Value as Json;
use std::path::{Path, PathBuf};

fn rbwh() -> Option<PathBuf> {
    Some(testkit::c3d_more()?.join("tsalemink__C3D-parser__RBWH_bfnd_w1.c3d"))
}

fn events_json(args: &[&str]) -> Vec<Json> {
    let mut all = vec!["events", "--json"];
    all.extend_from_slice(args);
    let out = c3dfix(&all);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Json = serde_json::from_slice(&out.stdout).expect("events --json is JSON");
    v["events"].as_array().expect("an events array").clone()
}

/// (context, label, time) of the file's own EVENT group, from `info --json`.
fn lab_events(file: &Path) -> Vec<(String, String, f64)> {
    let out = c3dfix(&["info", "--json", s(file)]);
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    v["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["context"].as_str().unwrap().to_string(),
                e["label"].as_str().unwrap().to_string(),
                e["time"].as_f64().unwrap(),
            )
        })
        .collect()
}

fn key(e: &Json) -> (String, String, f64) {
    (
        e["context"].as_str().unwrap().to_string(),
        e["label"].as_str().unwrap().to_string(),
        e["time"].as_f64().unwrap(),
    )
}

#[test]
fn plate_events_match_the_labs_own_events_to_a_millisecond() {
    let Some(file) = rbwh() else { return };
    let ev = events_json(&["--from", "plates", s(&file)]);
    let got: Vec<(String, String, f64, u64, u64)> = ev
        .iter()
        .map(|e| {
            assert_eq!(e["source"], "plate");
            let (c, l, t) = key(e);
            (
                c,
                l,
                t,
                e["frame"].as_u64().unwrap(),
                e["plate"].as_u64().unwrap(),
            )
        })
        .collect();
    // Frames in the file's numbering (first frame 211): round(time × 100) + 1.
    let want = [
        ("Right", "Foot Strike", 244, 2),
        ("Left", "Foot Strike", 308, 3),
        ("Right", "Foot Off", 322, 2),
        ("Left", "Foot Off", 387, 3),
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    let lab = lab_events(&file);
    for (g, w) in got.iter().zip(want) {
        assert_eq!((g.0.as_str(), g.1.as_str(), g.3, g.4), w, "{got:?}");
        assert_eq!(g.3, (g.2 * 100.0).round() as u64 + 1);
        // The lab's event of that foot and kind: on the same time base, within 1 ms.
        let near = lab
            .iter()
            .filter(|l| l.0 == g.0 && l.1 == g.1)
            .map(|l| (l.2 - g.2).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(near < 0.001, "{g:?}: nearest lab event {near} s away");
    }
}

#[test]
fn auto_takes_the_plates_where_a_foot_lands_and_the_markers_elsewhere() {
    let Some(file) = rbwh() else { return };
    let ev = events_json(&[s(&file)]);
    let sources: Vec<&str> = ev.iter().map(|e| e["source"].as_str().unwrap()).collect();
    assert_eq!(
        sources,
        [
            "plate",
            "kinematics",
            "plate",
            "plate",
            "kinematics",
            "plate",
            "kinematics",
            // The right off at 4.494 s (frame 450, 6 frames before the trial's end), after
            // the lab's last event: found since an extreme just beyond a trial's end counts
            // (issue 45 item 6); it keeps the trial's rhythm (the right off before it at
            // 3.213 s, a stride of 1.28 s).
            "kinematics"
        ]
    );
    // Every one of the lab's seven events is found, within 120 ms (this trial's kinematic
    // strikes off the plates land up to 70 ms after the lab's; docs/events.md).
    let lab = lab_events(&file);
    assert_eq!(lab.len(), 7);
    for l in &lab {
        let near = ev
            .iter()
            .map(key)
            .filter(|e| e.0 == l.0 && e.1 == l.1)
            .map(|e| (e.2 - l.2).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(near < 0.12, "{l:?}: {near} s");
    }
    // Sorted by time.
    let times: Vec<f64> = ev.iter().map(|e| e["time"].as_f64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    let kin = events_json(&["--from", "kinematics", s(&file)]);
    assert_eq!(kin.len(), 8);
    assert!(kin.iter().all(|e| e["source"] == "kinematics"));
}

#[test]
fn the_synthetic_walk_gives_one_strike_and_one_off_per_foot_per_stride() {
    let file = sample("walk_truth.c3d");
    let ev = events_json(&[s(&file)]);
    assert_eq!(ev.len(), 14);
    let stride = 1.0 / 0.9;
    for side in ["Left", "Right"] {
        for label in ["Foot Strike", "Foot Off"] {
            let t: Vec<f64> = ev
                .iter()
                .map(key)
                .filter(|e| e.0 == side && e.1 == label)
                .map(|e| e.2)
                .collect();
            assert!(t.len() >= 3, "{side} {label}: {t:?}");
            for w in t.windows(2) {
                assert!((w[1] - w[0] - stride).abs() < 0.01, "{side} {label}: {t:?}");
            }
        }
    }
    // Named markers give the same events; a name the file lacks is refused.
    let named = events_json(&[
        "--markers",
        "lheel=LHEE,rheel=RHEE,ltoe=LTOE,rtoe=RTOE",
        "--markers",
        "pelvis=LPSI+RPSI",
        s(&file),
    ]);
    assert_eq!(named, ev);
    let out = c3dfix(&["events", "--markers", "lheel=NOPE", s(&file)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("--markers lheel=NOPE"),
        "{}",
        stderr(&out)
    );
    let out = c3dfix(&["events", "--markers", "knee=LKNE", s(&file)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("ROLE=NAME"), "{}", stderr(&out));
    let out = c3dfix(&["events", "--from", "feet", s(&file)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("expected plates, kinematics or auto"));
    // No plates in the file: --from plates says so.
    let out = c3dfix(&["events", "--from", "plates", s(&file)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no force plates"), "{}", stderr(&out));
}

/// A sample of a marker at a frame (None: missing).
type Sample = Box<dyn Fn(usize, usize) -> Option<[f32; 3]>>;

/// A float C3D file of `frames` frames with the Plug-in Gait foot and pelvis markers, each
/// sample given by `at(frame, marker)` (None: missing, residual −1).
fn write_trial(path: &Path, frames: usize, at: impl Fn(usize, usize) -> Option<[f32; 3]>) {
    let labels = ["LHEE", "LTOE", "RHEE", "RTOE", "SACR"];
    let mut pts = Points::new(frames, labels.len());
    for f in 0..frames {
        for i in 0..labels.len() {
            let k = pts.index(f, i);
            match at(f, i) {
                Some(p) => {
                    pts.xyz[k] = p;
                    pts.residual[k] = 0.5;
                }
                None => pts.residual[k] = -1.0,
            }
        }
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 100.0).unwrap();
    let names: Vec<String> = labels.iter().map(|s| s.to_string()).collect();
    ps.set_strings("POINT", "LABELS", &names).unwrap();
    ps.set_strings("POINT", "UNITS", &["mm".into()]).unwrap();
    let c = C3d::new(pts, Analog::new(frames, 0, 1), ps, Processor::Intel, -1.0);
    std::fs::write(path, c.to_bytes().unwrap()).unwrap();
}

#[test]
fn trials_without_walking_get_a_clear_error_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let standing = |_f: usize, i: usize| {
        Some(match i {
            4 => [0.0, 0.0, 950.0],
            _ => [i as f32 * 100.0, 0.0, 40.0],
        })
    };
    let cases: Vec<(&str, usize, Sample, &str)> = vec![
        (
            "one_frame.c3d",
            1,
            Box::new(standing),
            "1 frame(s): events need at least 3 frames",
        ),
        ("standing.c3d", 200, Box::new(standing), "no walking"),
        (
            "feet_missing.c3d",
            200,
            Box::new(move |f, i| if i == 4 { standing(f, i) } else { None }),
            "every sample of the foot markers is missing",
        ),
        (
            "nan.c3d",
            200,
            Box::new(|_, _| Some([f32::NAN; 3])),
            "every sample of the pelvis markers is missing",
        ),
    ];
    for (name, frames, at, expect) in cases {
        let p = dir.path().join(name);
        write_trial(&p, frames, at);
        let out = c3dfix(&["events", s(&p)]);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", stdout(&out));
        let e = stderr(&out);
        assert!(e.contains(name) && e.contains(expect), "{name}: {e}");
        assert!(!e.contains("panicked"), "{e}");
        assert!(stdout(&out).is_empty());
    }
    // No foot markers at all; several files: each is reported, the good one printed.
    let Some(extra) = testkit::c3d_extra() else {
        return;
    };
    let cube = extra.join("btkdata_MyCube.c3d");
    let out = c3dfix(&["events", s(&cube), s(&sample("walk_truth.c3d"))]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out)
            .contains("btkdata_MyCube.c3d: no foot markers: none of the trial's 14 markers"),
        "{}",
        stderr(&out)
    );
    assert!(
        stdout(&out).contains("walk_truth.c3d: 14 events"),
        "{}",
        stdout(&out)
    );
}

/// The bytes of `path` from its data section on, and the offset of that section.
fn data_section(path: &Path) -> (usize, Vec<u8>) {
    let c = c3d::read_file(path).unwrap();
    let at = c.data_offset().unwrap();
    (at, c.source_bytes().unwrap()[at..].to_vec())
}

#[test]
fn events_are_written_into_the_event_group_as_nexus_writes_them() {
    let Some(file) = rbwh() else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.c3d");
    let printed = events_json(&["-o", s(&out), "--replace", s(&file)]);
    assert_eq!(printed.len(), 8);
    // Read back by this reader: the lab's seven events replaced by our eight, same times.
    let back = lab_events(&out);
    assert_eq!(back.len(), 8);
    for (b, p) in back.iter().zip(&printed) {
        let p = key(p);
        assert_eq!((&b.0, &b.1), (&p.0, &p.1));
        assert!((b.2 - p.2).abs() < 1e-6, "{b:?} {p:?}");
    }
    // Every other byte: the data section is unchanged (moved by the parameter block the
    // eighth event needs).
    assert_eq!(data_section(&out).1, data_section(&file).1);
    // c3dio reads the group back (it takes the count from EVENT:USED and the times from
    // the header's block, which is left as the file has it, so only the rest is compared).
    let c = c3dio::C3d::load(s(&out)).unwrap();
    assert_eq!(c.events.len(), 8);
    for (e, p) in c.events.iter().zip(&printed) {
        assert_eq!(e.label, p["label"].as_str().unwrap());
        assert_eq!(e.context, p["context"].as_str().unwrap());
        let strike = e.label == "Foot Strike";
        assert_eq!(e.icon_id, if strike { 1 } else { 2 });
        assert_eq!(e.generic_flag, 0);
        assert!(e.description.starts_with(if strike {
            "The moment any part of the foot first contacts the floor"
        } else {
            "The moment the foot ceases all contact with the floor"
        }));
    }
    // The same again gives the same bytes; without --replace the lab's events are kept.
    let again = dir.path().join("again.c3d");
    events_json(&["-o", s(&again), "--replace", s(&out)]);
    assert!(std::fs::read(&again).unwrap() == std::fs::read(&out).unwrap());
    let kept = dir.path().join("kept.c3d");
    events_json(&["-o", s(&kept), s(&file)]);
    let both = lab_events(&kept);
    assert_eq!(both.len(), 15);
    // `info` lists events in time order, so the lab's seven are among the fifteen.
    for e in lab_events(&file) {
        assert!(both.contains(&e), "{e:?} not kept in {both:?}");
    }
    // An existing OUT needs --force.
    let o = c3dfix(&["events", "-o", s(&kept), s(&file)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
}

#[test]
fn in_place_with_a_backup_and_the_options_that_need_a_destination() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("walk.c3d");
    let original = std::fs::read(sample("walk_truth.c3d")).unwrap();
    std::fs::write(&f, &original).unwrap();
    let printed = events_json(&["--in-place", "--backup", "--replace", s(&f)]);
    assert_eq!(printed.len(), 14);
    assert!(std::fs::read(dir.path().join("walk.c3d.bak")).unwrap() == original);
    // The synthetic walk's seven Foot Strike events are replaced by the fourteen found.
    let back = lab_events(&f);
    assert_eq!(back.len(), 14);
    assert_eq!(
        data_section(&f).1,
        data_section(&sample("walk_truth.c3d")).1
    );
    for args in [
        vec!["events", "--replace", s(&f)],
        vec!["events", "-o", "x.c3d", s(&f), s(&f)],
    ] {
        let o = c3dfix(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stdout(&o).is_empty());
    }
}

/// A lab's folder: `events DIR --in-place --jobs 2` writes every trial below it (each as
/// `events FILE -o` writes it alone, whatever thread did it), and `gait DIR --json` then
/// reads the written events of every trial back, in the folder's sorted order.
#[test]
fn a_folder_of_trials_is_done_in_parallel_and_each_as_alone() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let names = [
        "HansUniVie__MuscleLength__test.c3d",
        "tsalemink__C3D-parser__FMC_MH0222_BP15.c3d",
        "tsalemink__C3D-parser__RBWH_bfnd_w1.c3d",
    ];
    let dir = tempfile::tempdir().unwrap();
    let lab = dir.path().join("lab");
    std::fs::create_dir_all(lab.join("day2")).unwrap();
    let mut alone = Vec::new();
    for (i, n) in names.iter().enumerate() {
        let sub = if i == 2 {
            lab.join("day2")
        } else {
            lab.clone()
        };
        std::fs::copy(more.join(n), sub.join(n)).unwrap();
        let one = dir.path().join(format!("alone{i}.c3d"));
        let out = c3dfix(&["events", s(&more.join(n)), "--replace", "-o", s(&one)]);
        assert!(out.status.success(), "{}", stderr(&out));
        alone.push(std::fs::read(&one).unwrap());
    }
    let out = c3dfix(&[
        "events",
        s(&lab),
        "--in-place",
        "--replace",
        "--jobs",
        "2",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    let files: Vec<&str> = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["file"].as_str().unwrap())
        .collect();
    // Sorted by path: `HansUniVie…` < `day2/…` < `tsalemink…`.
    assert_eq!(files.len(), 3, "{files:?}");
    assert!(files[0].ends_with(names[0]), "{files:?}");
    assert!(
        files[1].ends_with(&format!("day2/{}", names[2])),
        "{files:?}"
    );
    assert!(files[2].ends_with(names[1]), "{files:?}");
    for (i, n) in names.iter().enumerate() {
        let sub = if i == 2 {
            lab.join("day2")
        } else {
            lab.clone()
        };
        assert_eq!(std::fs::read(sub.join(n)).unwrap(), alone[i], "{n}");
    }
    let no_leftovers = std::fs::read_dir(&lab)
        .unwrap()
        .flatten()
        .all(|e| !e.file_name().to_string_lossy().contains("c3dfix-tmp"));
    assert!(no_leftovers);
    // The gait parameters of the folder, from the events just written.
    let out = c3dfix(&["gait", s(&lab), "--json", "-j", "2"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Json = serde_json::from_slice(&out.stdout).unwrap();
    let docs = v["files"].as_array().unwrap();
    assert_eq!(docs.len(), 3);
    for d in docs {
        let params = d["parameters"].as_array().unwrap();
        assert!(
            params.iter().any(|p| p["name"] == "Cadence"),
            "{}: {d}",
            d["file"]
        );
    }
    // An empty folder is said, not passed over.
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let out = c3dfix(&["events", s(&empty)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no C3D files"), "{}", stderr(&out));
}

/// `--calibrate-from`: markers alone with a session calibration. Qualisys' two gait trials
/// of c3d-more (one lab, 100 Hz, two plates each): ClinicalGait_Gait1's kinematic events
/// shifted by the lags FunctionalKnee_GaitFB2's markers showed against its own plates
/// (strikes +6.7 ms, offs −1.7 ms, two contacts each; the offs' +2.6 ms before the offs
/// were shifted by the trial's stride), and judged by Gait1's own plates.
#[test]
fn events_calibrated_from_another_trial_of_the_session() {
    let Some(more) = testkit::c3d_more() else {
        eprintln!("skipped: C3D_MORE not set");
        return;
    };
    let gait1 = more.join("qualisys__cgm2-web-report-uploader__ClinicalGait_Gait1.c3d");
    let fb2 = more.join("qualisys__cgm2-web-report-uploader__FunctionalKnee_GaitFB2.c3d");
    let json = |args: &[&str]| -> Json {
        let mut all = vec!["events", "--json"];
        all.extend_from_slice(args);
        let out = c3dfix(&all);
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_slice(&out.stdout).expect("events --json is JSON")
    };
    let raw = json(&["--from", "kinematics", s(&gait1)]);
    assert!(raw.get("session_calibration").is_none());
    // The trial itself is among the references: it never calibrates itself.
    let cal = json(&[
        "--from",
        "kinematics",
        s(&gait1),
        "--calibrate-from",
        s(&fb2),
        "--calibrate-from",
        s(&gait1),
    ]);
    let sc = &cal["session_calibration"];
    assert_eq!(sc["trials"], 1, "{sc}");
    assert_eq!(sc["min_contacts"], 1);
    // Offs −1.8 ms: −1.7 before the trial's edge extremes counted in FB2's stride.
    for (kind, ms) in [("strike", 6.7), ("off", -1.8)] {
        assert_eq!(sc[kind]["contacts"], 2, "{sc}");
        assert_eq!(sc[kind]["used"], true);
        for side in ["left_ms", "right_ms"] {
            assert!((sc[kind][side].as_f64().unwrap() - ms).abs() < 0.05, "{sc}");
        }
    }
    // Every kinematic event moved by its kind's offset, nothing else changed.
    let (before, after) = (
        raw["events"].as_array().unwrap(),
        cal["events"].as_array().unwrap(),
    );
    // 14: the left off at 7.214 s, 0.14 s before the trial's last frame, is found since an
    // extreme cut by the trial's end needs only a tenth of its fall there; it keeps the
    // trial's rhythm (left offs at 4.212, 5.232, 6.237 s).
    assert_eq!(before.len(), 14);
    assert_eq!(after.len(), 14);
    for (b, a) in before.iter().zip(after) {
        assert_eq!((&b["context"], &b["label"]), (&a["context"], &a["label"]));
        let ms = if a["label"] == "Foot Strike" {
            6.7
        } else {
            -1.84
        };
        let moved = (a["time"].as_f64().unwrap() - b["time"].as_f64().unwrap()) * 1000.0;
        assert!((moved - ms).abs() < 0.05, "{b} -> {a}");
    }
    // Against Gait1's own plates (signed ms, calibrated − plate): the strikes, already
    // within 5 ms, move past them (−4.2 → +2.5, −1.3 → +5.5); the offs, which the stride
    // shift already brought 2.9 ms closer (−19.2 → −16.3, −24.4 → −21.5 from the markers
    // alone), move 1.8 ms away with FB2's lag (−18.1, −23.3; −16.6 and −21.7 before the
    // stride shift): the two trials are two protocols, not one session (docs/events.md).
    let plates = events_json(&["--from", "plates", s(&gait1)]);
    let err = |events: &[Json], p: &Json| {
        events
            .iter()
            .filter(|e| e["context"] == p["context"] && e["label"] == p["label"])
            .map(|e| (e["time"].as_f64().unwrap() - p["time"].as_f64().unwrap()) * 1000.0)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap()
    };
    let got: Vec<(String, f64, f64)> = plates
        .iter()
        .map(|p| {
            (
                format!(
                    "{} {}",
                    p["context"].as_str().unwrap(),
                    p["label"].as_str().unwrap()
                ),
                err(before, p),
                err(after, p),
            )
        })
        .collect();
    let want = [
        ("Right Foot Strike", -4.2, 2.5),
        ("Left Foot Strike", -1.3, 5.5),
        ("Right Foot Off", -16.3, -18.1),
        ("Left Foot Off", -21.5, -23.3),
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for ((name, b, a), (wname, wb, wa)) in got.iter().zip(want) {
        assert_eq!(name, wname);
        assert!((b - wb).abs() < 0.1 && (a - wa).abs() < 0.1, "{got:?}");
    }
    // In auto, the trial's own plates calibrate both kinds: the session's offsets are
    // reported, not used.
    let auto = json(&[s(&gait1), "--calibrate-from", s(&fb2)]);
    assert_eq!(auto["session_calibration"]["strike"]["used"], false);
    assert_eq!(auto["session_calibration"]["off"]["used"], false);
    // No other trial: no offset, the events as the markers give them, and a warning.
    let alone = json(&[
        "--from",
        "kinematics",
        s(&gait1),
        "--calibrate-from",
        s(&gait1),
    ]);
    assert_eq!(alone["session_calibration"]["trials"], 0);
    assert_eq!(alone["events"], raw["events"]);
    let w = alone["warnings"].to_string();
    assert!(
        w.contains("0 contact(s) for strikes") && w.contains("offs are left"),
        "{w}"
    );
    // Text output names the offsets; bad references exit 2 with the reason.
    let out = c3dfix(&[
        "events",
        "--from",
        "kinematics",
        s(&gait1),
        "--calibrate-from",
        s(&fb2),
    ]);
    assert!(
        stdout(&out).contains("session calibration (markers with the offsets of 1 other trial(s)): strikes +6.7 ms from 2 contacts, offs -1.8 ms from 2 contacts"),
        "{}",
        stdout(&out)
    );
    let missing = more.join("no_such_session");
    let out = c3dfix(&["events", s(&gait1), "--calibrate-from", s(&missing)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no_such_session: no such file or folder (--calibrate-from)"));
    let out = c3dfix(&[
        "events",
        "--from",
        "plates",
        s(&gait1),
        "--calibrate-from",
        s(&fb2),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--calibrate-from shifts kinematic events"));
}
