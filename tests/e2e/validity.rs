//! Missing samples as the C3D manual defines them, the same in every command: `info`, `gaps`,
//! `repair --report` and `export` agree with each other and with an independent decoder
//! (`tests/reference/c3d_validity.py`, whose output `tests/reference/validity.json` is
//! committed); filters never resurrect a missing sample; conversions keep the missing set.

use super::{c3dfix, s, stderr, stdout};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Every corpus file with its key in the reference (`c3d-samples/sample_00/…`).
fn corpus_files() -> Vec<(String, PathBuf)> {
    let mut out = Vec::new();
    for root in [
        testkit::c3d_samples(),
        testkit::c3d_extra(),
        testkit::c3d_fullbody(),
    ]
    .into_iter()
    .flatten()
    {
        let name = root
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        for f in testkit::files_with_ext(&root, "c3d") {
            let rel = f
                .strip_prefix(&root)
                .unwrap()
                .to_string_lossy()
                .into_owned();
            out.push((format!("{name}/{rel}"), f));
        }
    }
    out
}

fn json(args: &[&str]) -> serde_json::Value {
    let o = c3dfix(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}: {}", stdout(&o)))
}

/// Valid frames per point, from `info --json`.
fn info_counts(f: &Path) -> Vec<u64> {
    json(&["info", "--json", s(f)])["markers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["valid_frames"].as_u64().unwrap())
        .collect()
}

#[test]
fn info_counts_valid_frames_as_the_independent_decoder_does() {
    let files = corpus_files();
    if files.is_empty() {
        return;
    }
    let reference: BTreeMap<String, serde_json::Value> = serde_json::from_str(
        &std::fs::read_to_string(testkit::workspace_root().join("tests/reference/validity.json"))
            .unwrap(),
    )
    .unwrap();
    let mut compared = 0;
    let mut missing_total = 0u64;
    for (key, f) in &files {
        let r = reference
            .get(key)
            .unwrap_or_else(|| panic!("{key} is not in tests/reference/validity.json"));
        if r.get("error").is_some() {
            // Only the empty file: refused by both.
            assert_eq!(c3dfix(&["info", s(f)]).status.code(), Some(2), "{key}");
            continue;
        }
        let expect: Vec<u64> = r
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap())
            .collect();
        let ours = info_counts(f);
        if key.ends_with("sample_24/MotionMonitorC3D.c3d") {
            // Its header's analog word count contradicts the file size; c3dfix reads the
            // layout the size implies, the reference the header's.
            assert_ne!(ours, expect, "{key}: the exception no longer differs");
            continue;
        }
        assert_eq!(ours, expect, "{key}: valid frames per point");
        let frames = json(&["info", "--json", s(f)])["frames"].as_u64().unwrap();
        missing_total += ours.iter().map(|&v| frames - v).sum::<u64>();
        compared += 1;
    }
    eprintln!(
        "{compared} files agree with the independent decoder, {missing_total} missing samples"
    );
    assert!(compared >= 90, "only {compared} files compared");
}

#[test]
fn the_vicon_and_qualisys_spelling_of_missing_is_read_as_missing() {
    let Some(full) = testkit::c3d_fullbody() else {
        return;
    };
    let Some(samples) = testkit::c3d_samples() else {
        return;
    };
    // 03_rolling stores missing samples as (0, 0, 0) with the fourth word 65535.0.
    let v = json(&["info", "--json", s(&full.join("03_rolling.c3d"))]);
    let frames = v["frames"].as_u64().unwrap();
    let markers = v["markers"].as_array().unwrap();
    let missing: u64 = markers
        .iter()
        .map(|m| frames - m["valid_frames"].as_u64().unwrap())
        .sum();
    assert_eq!(missing, 35_965);
    assert_eq!(markers.iter().filter(|m| m["gaps"] != 0).count(), 67);
    // 16bitanalog: every marker missing in every frame.
    let v = json(&[
        "info",
        "--json",
        s(&samples.join("sample_07/16bitanalog.c3d")),
    ]);
    let markers = v["markers"].as_array().unwrap();
    assert_eq!(markers.len(), 27);
    assert!(markers.iter().all(|m| m["valid_frames"] == 0));
    // 128analogchannels: 8 405 missing samples in 5 markers.
    let v = json(&[
        "info",
        "--json",
        s(&samples.join("sample_17/128analogchannels.c3d")),
    ]);
    let frames = v["frames"].as_u64().unwrap();
    let per: Vec<u64> = v["markers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| frames - m["valid_frames"].as_u64().unwrap())
        .collect();
    assert_eq!(per.iter().sum::<u64>(), 8_405);
    assert_eq!(per.iter().filter(|&&m| m > 0).count(), 5);
    // marche281 stores 0x7F007F00 (not a 16-bit word) on real data: valid, with a warning.
    let v = json(&[
        "info",
        "--json",
        s(&samples.join("sample_30/marche281.c3d")),
    ]);
    let frames = v["frames"].as_u64().unwrap();
    assert!(v["markers"]
        .as_array()
        .unwrap()
        .iter()
        .all(|m| m["valid_frames"].as_u64() == Some(frames)));
    let warned = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w.as_str().unwrap().contains("not a 16-bit integer"))
        .count();
    assert_eq!(warned, 1);
}

/// Where sample `k`'s bytes are in a file as read.
fn sample_range(c: &c3d::C3d, k: usize) -> std::ops::Range<usize> {
    let l = c.layout();
    let wb = l.word_bytes();
    let at = c.data_offset().unwrap() + (k / l.points) * l.frame_bytes() + (k % l.points) * 4 * wb;
    at..at + 4 * wb
}

#[test]
fn a_filter_leaves_every_missing_sample_missing_byte_for_byte() {
    let files = corpus_files();
    if files.is_empty() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("filtered.c3d");
    let (mut checked, mut files_with_missing) = (0usize, 0usize);
    for (key, f) in &files {
        let Ok(orig) = c3d::read_file(f) else {
            continue;
        };
        if orig.points().count() == 0 || orig.points().frames() == 0 {
            continue; // nothing to repair (the command says so)
        }
        let o = c3dfix(&[
            "repair",
            s(f),
            "-o",
            s(&out),
            "--fill",
            "none",
            "--lowpass",
            "butterworth:4:6",
            "--force",
        ]);
        assert!(o.status.success(), "{key}: {}", stderr(&o));
        let rep = c3d::read_file(&out).unwrap();
        let (p, q) = (orig.points(), rep.points());
        let (a, b) = (orig.source_bytes().unwrap(), rep.source_bytes().unwrap());
        let mut any = false;
        for k in 0..p.frames() * p.count() {
            if p.is_valid_at(k) {
                continue;
            }
            any = true;
            checked += 1;
            assert!(!q.is_valid_at(k), "{key}: sample {k} came back valid");
            assert_eq!(
                a[sample_range(&orig, k)],
                b[sample_range(&rep, k)],
                "{key}: sample {k}'s bytes changed"
            );
        }
        files_with_missing += any as usize;
    }
    eprintln!("{checked} missing samples in {files_with_missing} files kept byte for byte");
    assert!(checked > 100_000, "only {checked} missing samples checked");
}

#[test]
fn conversions_write_nan_and_65535_samples_as_missing() {
    let Some(full) = testkit::c3d_fullbody() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // 03_rolling (65535.0 words) with NaN or infinite coordinates put into a few samples
    // whose fourth word stays valid, as some exporters write them.
    let mut c = c3d::read_file(full.join("03_rolling.c3d")).unwrap();
    let mut bytes = c.source_bytes().unwrap().to_vec();
    let mut poisoned = Vec::new();
    for (n, k) in (0..c.points().frames() * c.points().count())
        .filter(|&k| c.points().is_valid_at(k))
        .step_by(997)
        .take(40)
        .enumerate()
    {
        let r = sample_range(&c, k);
        let v = if n % 2 == 0 { f32::NAN } else { f32::INFINITY };
        bytes[r.start + 4 * (n % 3)..r.start + 4 * (n % 3) + 4].copy_from_slice(&v.to_le_bytes());
        poisoned.push(k);
    }
    let src = dir.path().join("poisoned.c3d");
    std::fs::write(&src, &bytes).unwrap();
    c = c3d::read_file(&src).unwrap();
    let missing = |c: &c3d::C3d| -> Vec<usize> {
        let p = c.points();
        (0..p.frames() * p.count())
            .filter(|&k| !p.is_valid_at(k))
            .collect()
    };
    let expect = missing(&c);
    assert_eq!(expect.len(), 35_965 + poisoned.len());
    assert!(poisoned.iter().all(|k| expect.binary_search(k).is_ok()));
    for args in [
        &["--format", "int"][..],
        &["--processor", "dec"],
        &["--processor", "sgi"],
        &["--processor", "dec", "--format", "int"],
        &["--processor", "sgi", "--format", "int"],
    ] {
        let out = dir.path().join("converted.c3d");
        let mut a = vec!["convert", s(&src), "-o", s(&out), "--force"];
        a.extend_from_slice(args);
        let o = c3dfix(&a);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let back = c3d::read_file(&out).unwrap();
        assert_eq!(missing(&back), expect, "{args:?}: missing set");
        // And an independent reader of the converted file sees the same.
        let v = json(&["info", "--json", s(&out)]);
        let valid: u64 = v["markers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["valid_frames"].as_u64().unwrap())
            .sum();
        let p = back.points();
        assert_eq!(valid as usize, p.frames() * p.count() - expect.len());
    }
}

#[test]
fn gaps_info_report_and_export_agree_on_missing_samples() {
    let files = corpus_files();
    if files.is_empty() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (rep_out, report, exported) = (
        dir.path().join("r.c3d"),
        dir.path().join("r.json"),
        dir.path().join("e.json"),
    );
    let mut compared = 0;
    for (key, f) in &files {
        match c3d::read_file(f) {
            Ok(c) if c.points().count() > 0 && c.points().frames() > 0 => {}
            _ => continue,
        }
        let info = json(&["info", "--json", s(f)]);
        let first = info["first_frame"].as_u64().unwrap() as usize;
        let labels: Vec<String> = info["markers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["label"].as_str().unwrap().to_string())
            .collect();
        // export: null coordinates where a sample is missing, per point.
        let o = c3dfix(&[
            "export",
            s(f),
            "--format",
            "json",
            "-o",
            s(&exported),
            "--force",
        ]);
        assert!(o.status.success(), "{key}: {}", stderr(&o));
        let e: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&exported).unwrap()).unwrap();
        let export_missing: Vec<Vec<bool>> = e["markers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| {
                m["xyz"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.is_null())
                    .collect()
            })
            .collect();
        assert_eq!(export_missing.len(), labels.len(), "{key}");
        for (i, m) in info["markers"].as_array().unwrap().iter().enumerate() {
            let n = export_missing[i].iter().filter(|&&x| !x).count();
            assert_eq!(
                n as u64,
                m["valid_frames"].as_u64().unwrap(),
                "{key}: point {i}"
            );
        }
        // gaps and repair --report (both in the file's frame numbers), by point index: runs of
        // missing frames of the markers they cover (model outputs are not markers).
        let runs = |missing: &[bool]| -> Vec<(usize, usize)> {
            let mut out = Vec::new();
            let mut f = 0;
            while f < missing.len() {
                if missing[f] {
                    let s0 = f;
                    while f < missing.len() && missing[f] {
                        f += 1;
                    }
                    out.push((s0, f - 1));
                } else {
                    f += 1;
                }
            }
            out
        };
        let g = json(&["gaps", "--json", s(f)]);
        let mut from_gaps: BTreeMap<String, Vec<(usize, usize)>> = BTreeMap::new();
        for x in g["gaps"].as_array().unwrap() {
            from_gaps
                .entry(x["label"].as_str().unwrap().to_string())
                .or_default()
                .push((
                    x["first_frame"].as_u64().unwrap() as usize - first,
                    x["last_frame"].as_u64().unwrap() as usize - first,
                ));
        }
        let o = c3dfix(&[
            "repair",
            s(f),
            "-o",
            s(&rep_out),
            "--fill",
            "none",
            "--report",
            s(&report),
            "--force",
        ]);
        assert!(o.status.success(), "{key}: {}", stderr(&o));
        let r: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
        // The report's gaps name a row of its `markers` list (model outputs are not markers).
        let rows: Vec<String> = r["markers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["label"].as_str().unwrap().to_string())
            .collect();
        let mut from_report: BTreeMap<String, Vec<(usize, usize)>> = BTreeMap::new();
        for x in r["gaps"].as_array().unwrap() {
            from_report
                .entry(rows[x["marker"].as_u64().unwrap() as usize].clone())
                .or_default()
                .push((
                    x["first"].as_u64().unwrap() as usize - first,
                    x["last"].as_u64().unwrap() as usize - first,
                ));
        }
        let unique = |l: &String| labels.iter().filter(|x| *x == l).count() == 1;
        for (i, label) in labels.iter().enumerate().filter(|(_, l)| unique(l)) {
            let expect = runs(&export_missing[i]);
            let none = Vec::new();
            if rows.contains(label) {
                let got = from_report.get(label).unwrap_or(&none);
                assert_eq!(got, &expect, "{key}: report gaps of {label}");
                let got = from_gaps.get(label).unwrap_or(&none);
                assert_eq!(got, &expect, "{key}: gaps of {label}");
            }
        }
        compared += 1;
    }
    assert!(compared >= 90, "only {compared} files compared");
}

#[test]
fn info_names_zero_invalid_when_many_valid_samples_sit_at_the_origin() {
    let Some(samples) = testkit::c3d_samples() else {
        return;
    };
    let f = samples.join("sample_09/PlugInC3D.c3d");
    let v = json(&["info", "--json", s(&f)]);
    assert_eq!(v["origin_samples"], 1254);
    let o = c3dfix(&["info", s(&f)]);
    assert!(stdout(&o).contains("--zero-invalid"), "{}", stdout(&o));
    // A file without such samples says nothing.
    let o = c3dfix(&["info", s(&samples.join("sample_30/marche281.c3d"))]);
    assert!(!stdout(&o).contains("--zero-invalid"));
}

#[test]
fn repair_names_zero_invalid_when_it_keeps_samples_at_the_origin() {
    let Some(samples) = testkit::c3d_samples() else {
        return;
    };
    // ART-Human stores the frame where the body was lost as every point at the origin
    // with a valid fourth word: kept as recorded unless the user says otherwise.
    let f = samples.join("sample_00/Advanced Realtime Tracking GmbH/arthuman-sample.c3d");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.c3d");
    let o = c3dfix(&["repair", s(&f), "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("63 samples sit exactly at (0, 0, 0)")
            && stdout(&o).contains("--zero-invalid"),
        "{}",
        stdout(&o)
    );
    let v = json(&["repair", "--json", s(&f), "-o", s(&out), "--force"]);
    assert_eq!(v["samples_at_origin"], 63, "{v}");
    // Told, it fills them as the gaps they are, and has nothing more to say.
    let o = c3dfix(&["repair", s(&f), "-o", s(&out), "--force", "--zero-invalid"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("63 found in 63 markers: 63 filled"),
        "{}",
        stdout(&o)
    );
    assert!(!stdout(&o).contains("(0, 0, 0)"), "{}", stdout(&o));
}
