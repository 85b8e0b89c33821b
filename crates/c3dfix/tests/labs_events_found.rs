//! Lab events found from the markers alone that earlier builds missed (c3d-labs' strikes,
//! and one c3d-samples off): at a trial's first or last frames (labs crop one-cycle trials
//! at their strikes), where the heel marker drops out for a few frames just before its
//! strike, and where the pelvis is seen for under a second (a walkway run). Each is pinned
//! against the lab's own event.

use c3dfix::events::{detect_events, EventOptions, EventSource};
use gait::{Kind, Side};
use std::path::PathBuf;

/// The signed error (s) of the kinematic event of `side` and `kind` nearest the lab's at
/// `lab_s` in the trial at `path` (None: its corpus is absent).
fn error_at(path: Option<PathBuf>, side: Side, kind: Kind, lab_s: f64) -> Option<f64> {
    let path = path?;
    let c = c3dfix::open(&path).unwrap();
    let opts = EventOptions {
        from: EventSource::Kinematics,
        ..EventOptions::default()
    };
    let d = detect_events(&c, &opts, &path).unwrap();
    // The lab's event is in the file as the test says.
    assert!(
        c.events().iter().any(|e| {
            c3dfix::event_labels::gait_event(&e.context, &e.label) == Some((side, kind))
                && (e.time - lab_s).abs() < 0.001
        }),
        "{}: no lab event at {lab_s} s",
        path.display()
    );
    d.events
        .iter()
        .filter(|e| e.side == side && e.kind == kind)
        .map(|e| e.time - lab_s)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        .or(Some(f64::INFINITY))
}

/// [`error_at`] for a strike of c3d-labs' trial `name`.
fn strike_error(name: &str, side: Side, lab_s: f64) -> Option<f64> {
    let path = testkit::c3d_labs_trial(name);
    error_at(path, side, Kind::FootStrike, lab_s)
}

#[test]
fn a_strike_two_frames_before_a_cropped_trials_end_is_found() {
    // BMC's one-cycle trial ends on its lab's (and plate's) left strike, 4.350 s; the heel's
    // forward extreme lies two frames before the end, falling 6 mm after it.
    let Some(e) = strike_error("BMClab__BMC__C_S05_T08_3_Cycle", Side::Left, 4.35) else {
        return;
    };
    assert!(e.abs() < 0.015, "{e}");
}

#[test]
fn a_strike_whose_heel_extreme_lies_just_before_the_trials_start_is_found() {
    // s2mLab's walk starts 5 frames (25 ms) before its lab's first left strike; the heel's
    // forward extreme lies about 3 frames before the first frame.
    let Some(e) = strike_error(
        "s2mLab__BioptimPaperExamples__normal01_out",
        Side::Left,
        0.025,
    ) else {
        return;
    };
    assert!(e.abs() < 0.01, "{e}");
}

#[test]
fn a_heel_lost_for_five_frames_before_its_strike_still_gives_it() {
    // MOtoNMS' Padova walks (60 Hz): RCA missing 83 ms just before the right strikes.
    for (name, lab, within) in [
        ("RehabEngGroup__MOtoNMS__Walking1", 2.4333, 0.02),
        ("RehabEngGroup__MOtoNMS__Walking3", 2.25, 0.035),
    ] {
        let Some(e) = strike_error(name, Side::Right, lab) else {
            return;
        };
        assert!(e.abs() < within, "{name}: {e}");
    }
}

#[test]
fn a_run_whose_pelvis_is_seen_for_half_a_second_gets_its_strike() {
    // MOtoNMS' Running_1 (250 Hz): SACR seen for 125 frames while the right foot lands on
    // plate 1 (lab strike 3.244 s); the direction's window shrinks to what is seen.
    let Some(e) = strike_error("RehabEngGroup__MOtoNMS__Running_1", Side::Right, 3.244) else {
        return;
    };
    assert!(e.abs() < 0.025, "{e}");
}

#[test]
fn an_off_one_frame_before_the_trials_end_is_found() {
    // Motion Analysis' Walk1 (c3d-samples, 60 Hz) ends 2 frames after its lab's last left
    // off (2.467 s, context `LTO`); the toe's backward extreme lies one frame before the
    // end, with one sample after it.
    let path =
        testkit::c3d_samples().map(|d| d.join("sample_00/Motion Analysis Corporation/Walk1.c3d"));
    let Some(e) = error_at(path, Side::Left, Kind::FootOff, 2.4667) else {
        return;
    };
    assert!(e.abs() < 0.005, "{e}");
}
