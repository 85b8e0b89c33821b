//! Events seen: `c3dfix plot` draws them as labelled vertical lines, `c3dfix view` marks
//! them on its time bar. The reference is c3d-more's `FMC_MH0222_BP15` (100 Hz, frames
//! 260–550, twelve Foot Strike / Foot Off events of its lab).

use super::view::{chromium, selftest};
use super::{c3dfix, s, stderr};
use serde_json::Value as Json;
use std::path::{Path, PathBuf};

fn fmc() -> Option<PathBuf> {
    Some(testkit::c3d_more()?.join("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d"))
}

/// (short label, time) of the file's events, from `info --json`, and of the detected ones,
/// from `events --json`, in time order.
/// Events as (short label, time).
type Labelled = Vec<(String, f64)>;

fn events(file: &Path) -> (Labelled, Labelled) {
    let short = |c: &str, l: &str| {
        format!(
            "{}{}",
            &c[..1],
            if l == "Foot Strike" { "FS" } else { "FO" }
        )
    };
    let read = |args: &[&str]| -> Labelled {
        let out = c3dfix(args);
        assert!(out.status.success(), "{}", stderr(&out));
        let v: Json = serde_json::from_slice(&out.stdout).unwrap();
        let mut e: Labelled = v["events"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                (
                    short(e["context"].as_str().unwrap(), e["label"].as_str().unwrap()),
                    e["time"].as_f64().unwrap(),
                )
            })
            .collect();
        e.sort_by(|a, b| a.1.total_cmp(&b.1));
        e
    };
    (
        read(&["info", "--json", s(file)]),
        read(&["events", "--json", s(file)]),
    )
}

/// The SVG's texts: (x, y, content).
fn texts(svg: &str) -> Vec<(f64, f64, String)> {
    svg.split("<text ")
        .skip(1)
        .filter_map(|t| {
            let attr = |name: &str| -> Option<f64> {
                let at = t.find(&format!("{name}=\""))? + name.len() + 2;
                t[at..at + t[at..].find('"')?].parse().ok()
            };
            let body = &t[t.find('>')? + 1..t.find("</text>")?];
            Some((attr("x")?, attr("y")?, body.trim().to_string()))
        })
        .collect()
}

/// Each event labelled once (the file's along the top of the first panel, the detected
/// ones along its bottom), centred on its time on the panel's axis.
fn check_labels(svg: &str, lab: &Labelled, detected: &Labelled) {
    let t = texts(svg);
    // The time axis of the first panel: ticks 3.0 and 5.0 s give the scale.
    let tick = |v: &str| t.iter().find(|x| x.2 == v).expect(v).0;
    let (x3, x5) = (tick("3.0"), tick("5.0"));
    let at = |time: f64| x3 + (time - 3.0) * (x5 - x3) / 2.0;
    let labels: Vec<&(f64, f64, String)> = t
        .iter()
        .filter(|x| ["LFS", "LFO", "RFS", "RFO"].contains(&x.2.as_str()))
        .collect();
    // Within 2 px of its time: the label's pixel and the ticks' rounding.
    assert_eq!(labels.len(), lab.len() + detected.len(), "{labels:?}");
    let top = labels.iter().map(|l| l.1).fold(f64::MAX, f64::min);
    for (set, is_top) in [(lab, true), (detected, false)] {
        let row: Vec<_> = labels.iter().filter(|l| (l.1 == top) == is_top).collect();
        assert_eq!(row.len(), set.len(), "top {is_top}: {row:?}");
        for ((name, time), l) in set.iter().zip(row) {
            assert_eq!(&l.2, name, "{time} s");
            assert!(
                (l.0 - at(*time)).abs() <= 2.0,
                "{name} at {time} s drawn at x {} (expected {:.1})",
                l.0,
                at(*time)
            );
        }
    }
    assert!(t.iter().any(|x| x.2 == "events (file)"));
    assert!(t.iter().any(|x| x.2 == "events (detected)"));
}

#[test]
fn plot_draws_the_files_events_and_detected_ones_at_their_times() {
    let Some(file) = fmc() else { return };
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("p.svg");
    let out = c3dfix(&[
        "plot",
        s(&file),
        "--marker",
        "LHEE",
        "--analog",
        "Force.Fz2",
        "--detect-events",
        "-o",
        s(&svg),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (lab, detected) = events(&file);
    assert_eq!(lab.len(), 12);
    assert!(detected.len() >= 10, "{detected:?}");
    check_labels(&std::fs::read_to_string(&svg).unwrap(), &lab, &detected);
    // On the plates' vertical force too.
    let out = c3dfix(&[
        "plot",
        s(&file),
        "--forces",
        "--detect-events",
        "-o",
        s(&svg),
        "--force",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    check_labels(&std::fs::read_to_string(&svg).unwrap(), &lab, &detected);
    // Without the flag, the file's events only.
    let out = c3dfix(&[
        "plot",
        s(&file),
        "--marker",
        "LHEE",
        "-o",
        s(&svg),
        "--force",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let t = texts(&std::fs::read_to_string(&svg).unwrap());
    assert_eq!(t.iter().filter(|x| x.2 == "LFS").count(), 3);
    assert!(!t.iter().any(|x| x.2 == "events (detected)"));
}

#[test]
fn the_viewer_marks_events_on_its_time_bar() {
    let Some(file) = fmc() else { return };
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("v.html");
    let out = c3dfix(&["view", s(&file), "--detect-events", "-o", s(&page)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let html = std::fs::read_to_string(&page).unwrap();
    // The page's data: every event at its stored frame (time × 100 − 259).
    let start = html
        .find("<script id=\"meta\" type=\"application/json\">")
        .unwrap()
        + 42;
    let end = start + html[start..].find("</script>").unwrap();
    let meta: Json = serde_json::from_str(&html[start..end]).unwrap();
    let ev = meta["events"].as_array().unwrap();
    let (lab, detected) = events(&file);
    assert_eq!(ev.len(), lab.len() + detected.len());
    let file_ev: Vec<&Json> = ev.iter().filter(|e| e["detected"] == false).collect();
    for ((name, time), e) in lab.iter().zip(&file_ev) {
        assert_eq!(e["short"], name.as_str());
        let index = e["index"].as_f64().unwrap();
        assert!((index - (time * 100.0 - 259.0)).abs() < 1e-3, "{e}");
    }
    assert_eq!(file_ev[0]["full"], "Left Foot Strike 2.790 s");
    // In a browser: a tick per event where the thumb stands at its frame, and a click on
    // one goes to its frame.
    let Some(bin) = chromium() else { return };
    let r = selftest(&bin, &page, &dir.path().join("profile"));
    assert_eq!(r["errors"], serde_json::json!([]), "{r}");
    assert_eq!(r["events"], ev.len(), "{r}");
    assert_eq!(r["event_ticks"], ev.len(), "{r}");
    assert_eq!(r["event_labels"][0], "LFS", "{r}");
    assert!(
        r["event_offsets"]
            .as_array()
            .unwrap()
            .iter()
            .all(|d| d.as_f64().unwrap().abs() <= 3.0),
        "{r}"
    );
    assert_eq!(r["frame_after_event_click"], r["event_clicked"], "{r}");
    assert_eq!(r["ok"], true, "{r}");
}
