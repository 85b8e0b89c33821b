//! Gait-cycle parameters on the command line: `c3dfix gait`. The references are the Nexus
//! trials carrying Nexus' own values in their ANALYSIS group (`sample_11/2198928.c3d`,
//! `HansUniVie__MuscleLength__test.c3d`); the repository's synthetic walk `walk_truth.c3d`
//! serves where no corpus is needed (its events detected).

use super::{c3dfix, s, sample, stderr, stdout};
use c3dfix::events::TrialEvent;
use gait::{Kind, Side, Source};
use serde_json::Value as Json;
use std::path::{Path, PathBuf};

fn sample_11() -> Option<PathBuf> {
    Some(testkit::c3d_samples()?.join("sample_11/2198928.c3d"))
}

fn hans() -> Option<PathBuf> {
    Some(testkit::c3d_more()?.join("HansUniVie__MuscleLength__test.c3d"))
}

fn gait_json(args: &[&str]) -> Json {
    let mut all = vec!["gait", "--json"];
    all.extend_from_slice(args);
    let out = c3dfix(&all);
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).expect("gait --json is JSON")
}

/// (context, name, unit, value) rows of the ANALYSIS group, and the string widths of
/// NAMES, SUBJECTS, CONTEXTS, UNITS, DESCRIPTIONS.
type Row = (String, String, String, f32);

fn analysis(path: &Path) -> (Vec<Row>, Vec<u8>) {
    let c = c3d::read_file(path).unwrap();
    let ps = &c.parameters;
    let st = |n: &str| ps.get_strings("ANALYSIS", n).unwrap();
    let (names, contexts, units) = (st("NAMES"), st("CONTEXTS"), st("UNITS"));
    let values = ps.get("ANALYSIS", "VALUES").unwrap().as_f32s();
    let used = ps.get_i32("ANALYSIS", "USED").unwrap() as usize;
    let widths = ["NAMES", "SUBJECTS", "CONTEXTS", "UNITS", "DESCRIPTIONS"]
        .iter()
        .map(|n| ps.get("ANALYSIS", n).unwrap().dims[0])
        .collect();
    let rows = (0..used)
        .map(|i| {
            (
                contexts[i].trim().to_string(),
                names[i].trim().to_string(),
                units[i].trim().to_string(),
                values[i],
            )
        })
        .collect();
    (rows, widths)
}

fn data_section(path: &Path) -> Vec<u8> {
    let c = c3d::read_file(path).unwrap();
    let at = c.data_offset().unwrap();
    c.source_bytes().unwrap()[at..].to_vec()
}

#[test]
fn json_names_every_value_as_nexus_names_it_in_the_analysis_group() {
    let Some(file) = hans() else { return };
    let v = gait_json(&[s(&file)]);
    assert_eq!(v["events"], "file");
    assert_eq!(v["toes"], serde_json::json!(["LTOE", "RTOE"]));
    let params = v["parameters"].as_array().unwrap();
    assert_eq!(params.len(), 26);
    let (nexus, _) = analysis(&file);
    for (context, name, unit, value) in &nexus {
        let p = params
            .iter()
            .find(|p| p["context"] == context.as_str() && p["name"] == name.as_str())
            .unwrap_or_else(|| panic!("no {context} {name}"));
        assert_eq!(p["unit"], unit.as_str());
        let got = p["value"].as_f64().unwrap();
        let tol = match unit.as_str() {
            "s" => 1.0 / 120.0,
            "%" => 1.0,
            "m" => 0.005,
            _ => 0.01 * *value as f64,
        };
        assert!(
            (got - *value as f64).abs() <= tol,
            "{context} {name}: {got} {value}"
        );
    }
    // Step width and limp index follow each side's eleven.
    assert_eq!(params[11]["name"], "Step Width");
    assert_eq!(params[12]["name"], "Limp Index");
    assert_eq!(params[13]["context"], "Right");
}

#[test]
fn written_into_the_analysis_group_as_nexus_writes_it() {
    let Some(file) = sample_11() else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.c3d");
    let v = gait_json(&["--detect", "--from", "plates", s(&file)]);
    assert_eq!(v["events"], "detected");
    let o = c3dfix(&["gait", "--write", "-o", s(&out), s(&file)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let printed = gait_json(&[s(&file)]);
    let printed = printed["parameters"].as_array().unwrap();
    let (rows, widths) = analysis(&out);
    // Nexus' widths and order; its 22 values replaced by our 26, Left's then Right's.
    assert_eq!(widths, vec![32, 32, 16, 12, 48]);
    assert_eq!(rows.len(), 26);
    for (r, p) in rows.iter().zip(printed) {
        assert_eq!(r.0, p["context"].as_str().unwrap());
        assert_eq!(r.1, p["name"].as_str().unwrap());
        assert_eq!(r.2, p["unit"].as_str().unwrap());
        assert_eq!(r.3, p["value"].as_f64().unwrap() as f32);
    }
    let c = c3d::read_file(&out).unwrap();
    let subjects = c.parameters.get_strings("ANALYSIS", "SUBJECTS").unwrap();
    assert!(subjects.iter().all(|x| x.trim() == "21989"));
    let order: Vec<String> = c
        .parameters
        .parameters_of(c.parameters.group("ANALYSIS").unwrap().id)
        .map(|p| p.name.clone())
        .collect();
    assert_eq!(
        order,
        [
            "USED",
            "NAMES",
            "SUBJECTS",
            "CONTEXTS",
            "UNITS",
            "DESCRIPTIONS",
            "VALUES"
        ]
    );
    // Every other byte: the data section is unchanged.
    assert!(data_section(&out) == data_section(&file));
    // Again on the written file: ours replaced by ours, the same bytes.
    let again = dir.path().join("again.c3d");
    let o = c3dfix(&["gait", "--write", "-o", s(&again), s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&again).unwrap() == std::fs::read(&out).unwrap());
    // An existing OUT needs --force; OUT is never the input.
    let o = c3dfix(&["gait", "--write", "-o", s(&again), s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    let o = c3dfix(&["gait", "--write", "-o", s(&out), "--force", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--in-place"), "{}", stderr(&o));
}

#[test]
fn detected_events_in_place_with_a_backup_and_csv_of_several_files() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("walk.c3d");
    let original = std::fs::read(sample("walk_truth.c3d")).unwrap();
    std::fs::write(&f, &original).unwrap();
    // The synthetic walk's events are Foot Strikes only: no cycle from them.
    let o = c3dfix(&["gait", s(&f)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no complete cycle"), "{}", stderr(&o));
    let o = c3dfix(&[
        "gait",
        "--detect",
        "--write",
        "--in-place",
        "--backup",
        s(&f),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(dir.path().join("walk.c3d.bak")).unwrap() == original);
    let (rows, _) = analysis(&f);
    assert_eq!(rows.len(), 26);
    // Strides of 1/0.9 s: 108 steps/min.
    let cadence = rows.iter().find(|r| r.1 == "Cadence").unwrap().3;
    assert!((cadence - 108.0).abs() < 1.0, "{cadence}");
    assert!(data_section(&f) == data_section(&sample("walk_truth.c3d")));
    // CSV of several files, one row per value; a file that fails is named, exit 2.
    let csv = dir.path().join("params.csv");
    let o = c3dfix(&[
        "gait",
        "--detect",
        "-o",
        s(&csv),
        s(&f),
        s(&sample("walk_truth.c3d")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "file,context,name,value,unit");
    assert_eq!(lines.len(), 1 + 2 * 26);
    assert!(lines[1].contains(",Left,Cadence,"), "{}", lines[1]);
    let o = c3dfix(&["gait", "-o", s(&csv), s(&f)]);
    assert_eq!(o.status.code(), Some(2), "an existing CSV needs --force");
    let o = c3dfix(&["gait", "-o", s(&f), s(&f)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("refusing to overwrite"),
        "{}",
        stderr(&o)
    );
}

/// A trial whose EVENT group holds `events` (written as `c3dfix events` writes them).
fn with_events(dir: &Path, name: &str, events: &[(Side, Kind, f64)]) -> PathBuf {
    let mut c = c3dfix::open(sample("walk_truth.c3d")).unwrap();
    let ev: Vec<TrialEvent> = events
        .iter()
        .map(|&(side, kind, time)| TrialEvent {
            side,
            kind,
            time,
            frame: 0,
            source: Source::Kinematics,
            plate: None,
        })
        .collect();
    c3dfix::event_group::write_events(&mut c, &ev, true).unwrap();
    let p = dir.join(name);
    c3dfix::save(&c, &p, &c3dfix::SaveOptions::default()).unwrap();
    p
}

#[test]
fn bad_input_gets_a_clear_message_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let (fs, fo) = (Kind::FootStrike, Kind::FootOff);
    let (left, right) = (Side::Left, Side::Right);
    let left_only = [
        (left, fs, 1.0),
        (right, fo, 1.1),
        (right, fs, 1.55),
        (left, fo, 1.65),
        (left, fs, 2.1),
    ];
    // One side only: what can be is reported, the other side named.
    let p = with_events(dir.path(), "left_only.c3d", &left_only);
    let v = gait_json(&[s(&p)]);
    assert_eq!(v["parameters"].as_array().unwrap().len(), 13);
    assert!(
        v["warnings"][0]
            .as_str()
            .unwrap()
            .starts_with("Right: no complete cycle"),
        "{v}"
    );
    let mut late = left_only.to_vec();
    late.push((right, fs, 99.0));
    let cases: Vec<(PathBuf, &str)> = vec![
        (
            with_events(dir.path(), "outside.c3d", &late),
            "the Right Foot Strike event at 99.0000 s lies outside the trial",
        ),
        (
            with_events(dir.path(), "none.c3d", &[]),
            "no Foot Strike or Foot Off events",
        ),
        (
            with_events(
                dir.path(),
                "strikes.c3d",
                &[(left, fs, 1.0), (left, fs, 2.1)],
            ),
            "Left: no complete cycle",
        ),
    ];
    for (p, expect) in cases {
        let out = c3dfix(&["gait", s(&p)]);
        assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
        let e = stderr(&out);
        assert!(e.contains(s(&p)) && e.contains(expect), "{e}");
        assert!(!e.contains("panicked") && stdout(&out).is_empty(), "{e}");
    }
    // No foot markers for lengths: the times are reported, the lengths said missing.
    let p = with_events(dir.path(), "no_feet.c3d", &left_only);
    let mut c = c3dfix::open(&p).unwrap();
    let labels: Vec<String> = (0..c.point_count()).map(|i| format!("M{i}")).collect();
    c.parameters
        .set_strings("POINT", "LABELS", &labels)
        .unwrap();
    let p = dir.path().join("renamed.c3d");
    c3dfix::save(&c, &p, &c3dfix::SaveOptions::default()).unwrap();
    let v = gait_json(&[s(&p)]);
    let names: Vec<&str> = v["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert!(!names.contains(&"Stride Length") && names.contains(&"Stride Time"));
    let w = v["warnings"][0].as_str().unwrap();
    assert!(
        w.starts_with("no lengths (and no walking speed): no foot markers"),
        "{w}"
    );
}
