//! Gait events on the next lab's trials (`c3d-labs`, on which no constant was chosen): foot
//! markers of other marker sets, found by name or told apart by position, treadmills, and
//! trials that have no feet to give events.

use c3dfix::events::{detect_events, is_treadmill, Detected, EventOptions, EventSource};
use gait::{Kind, Side};
use std::path::PathBuf;

fn detect(path: &PathBuf, from: EventSource) -> c3dfix::Result<Detected> {
    let c = c3dfix::open(path).unwrap();
    let opts = EventOptions {
        from,
        ..EventOptions::default()
    };
    detect_events(&c, &opts, path)
}

fn role<'a>(d: &'a Detected, r: &str) -> Vec<&'a str> {
    d.markers
        .iter()
        .find(|(name, _)| name == r)
        .map(|(_, v)| v.iter().map(|s| s.as_str()).collect())
        .unwrap_or_default()
}

fn count(d: &Detected, context: &str, label: &str) -> usize {
    d.events
        .iter()
        .filter(|e| e.side.context() == context && e.kind.label() == label)
        .count()
}

#[test]
fn an_ior_anatomical_set_gives_events_from_the_calcaneus_and_first_metatarsal_head() {
    // MOtoNMS' Padova walk: calcaneus RCA, metatarsal heads RIMH/RVMH, no toe marker.
    let Some(path) = testkit::c3d_labs_trial("RehabEngGroup__MOtoNMS__Walking1") else {
        return;
    };
    let d = detect(&path, EventSource::Kinematics).unwrap();
    assert_eq!(role(&d, "lheel"), ["LCA"]);
    assert_eq!(role(&d, "ltoe"), ["LIMH"]);
    assert_eq!(role(&d, "rheel"), ["RCA"]);
    assert_eq!(role(&d, "pelvis"), ["LPSIS", "RPSIS"]);
    // The left foot's strike on plate 2 (3.017 s) and its off (3.719 s), from the markers.
    let t = |label: &str, near: f64| {
        d.events
            .iter()
            .filter(|e| e.side == Side::Left && e.kind.label() == label)
            .map(|e| e.time - near)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap()
    };
    assert!(
        t("Foot Strike", 3.017).abs() < 0.05,
        "{}",
        t("Foot Strike", 3.017)
    );
    assert!(
        t("Foot Off", 3.719).abs() < 0.03,
        "{}",
        t("Foot Off", 3.719)
    );
}

#[test]
fn dotted_heel_names_with_qualifiers_are_told_apart_by_position() {
    // RBDS (treadmill run): L.Heel.Bottom, L.Heel.Lateral, L.Heel.Top, L.MT1, L.MT5.
    let Some(path) =
        testkit::c3d_labs_trial("regifukuchi__BMC-RIC-running-biomechanics__RBDS001runT35")
    else {
        return;
    };
    let d = detect(&path, EventSource::Kinematics).unwrap();
    assert_eq!(role(&d, "lheel"), ["L.Heel.Bottom"]);
    assert_eq!(role(&d, "ltoe"), ["L.MT1"]);
    assert_eq!(role(&d, "rheel"), ["R.Heel.Bottom"]);
    assert_eq!(role(&d, "rtoe"), ["R.MT5"]);
    assert_eq!(role(&d, "pelvis"), ["L.PSIS", "R.PSIS"]);
    assert!(
        d.notes[0].starts_with("left foot: heel L.Heel.Bottom and toe L.MT1, the rearmost"),
        "{:?}",
        d.notes
    );
    assert!(d.notes.iter().any(|n| n == c3dfix::events::TREADMILL_NOTE));
    assert_eq!(d.notes.last().unwrap(), c3dfix::events::RUNNING_NOTE);
}

#[test]
fn an_upper_body_set_is_refused_for_want_of_feet_not_of_a_heel() {
    // pyomeca's box lifting: shoulder, arm and box markers, no foot.
    let Some(path) = testkit::c3d_labs_trial("pyomeca__pyomeca__markers_analogs") else {
        return;
    };
    let e = detect(&path, EventSource::Auto).unwrap_err().to_string();
    assert!(
        e.contains("no foot markers: none of the trial's 51 markers"),
        "{e}"
    );
    assert!(!e.contains("--markers"), "{e}");
}

#[test]
fn treadmill_walking_gets_every_step_from_the_feet_relative_to_the_pelvis() {
    // rtosim: 8.7 s on an instrumented treadmill, the pelvis still; each belt's plate
    // shows 8 contacts of one foot.
    let Some(path) = testkit::c3d_labs_trial("RealTimeBiomechanics__rtosim__walking_1") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    assert!(is_treadmill(&c, &path));
    let d = detect(&path, EventSource::Kinematics).unwrap();
    assert_eq!(d.notes, [c3dfix::events::TREADMILL_NOTE]);
    assert_eq!(
        [
            count(&d, "Left", "Foot Strike"),
            count(&d, "Left", "Foot Off"),
            count(&d, "Right", "Foot Strike"),
            count(&d, "Right", "Foot Off"),
        ],
        [8, 7, 7, 8]
    );
    // An overground walk is no treadmill.
    let Some(walk) = testkit::c3d_labs_trial("psbiomech__lasem-data-processing__FAILT01_Walk01")
    else {
        return;
    };
    assert!(!is_treadmill(&c3dfix::open(&walk).unwrap(), &walk));
    // Nor is a walkway run whose pelvis is seen for less than a stride (85 % missing).
    let Some(run) = testkit::c3d_labs_trial("RehabEngGroup__MOtoNMS__Running_1") else {
        return;
    };
    assert!(!is_treadmill(&c3dfix::open(&run).unwrap(), &run));
}

#[test]
fn a_treadmill_run_with_a_foot_cluster_gets_its_events_not_a_missing_marker_error() {
    // 20140515T133244_run: four-marker foot clusters (L_foot_1…4) and a pelvis cluster;
    // the cluster's heel and toe need the walking direction, which is the treadmill's.
    let Some(path) =
        testkit::c3d_labs_trial("regifukuchi__BMC-RIC-running-biomechanics__20140515T133244_run")
    else {
        return;
    };
    let d = detect(&path, EventSource::Kinematics).unwrap();
    assert_eq!(role(&d, "lheel"), ["L_foot_2"]);
    assert_eq!(role(&d, "ltoe"), ["L_foot_3"]);
    assert_eq!(role(&d, "rheel"), ["R_foot_1"]);
    assert_eq!(role(&d, "rtoe"), ["R_foot_2"]);
    assert_eq!(d.events.len(), 152);
}

#[test]
fn treadmill_running_strikes_from_the_markers_match_the_instrumented_belt() {
    // RBDS001runT35: 30 s at 3.5 m/s, one plate under the belt. Every plate strike has a
    // kinematic one of the same foot within 60 ms, 95 % within 30 ms, the median 11.6 ms
    // (measured on this file; nothing was chosen on it).
    let Some(path) =
        testkit::c3d_labs_trial("regifukuchi__BMC-RIC-running-biomechanics__RBDS001runT35")
    else {
        return;
    };
    let plates = detect(&path, EventSource::Plates).unwrap();
    let kin = detect(&path, EventSource::Kinematics).unwrap();
    let strikes: Vec<_> = plates
        .events
        .iter()
        .filter(|e| e.kind == Kind::FootStrike)
        .collect();
    assert_eq!(strikes.len(), 85);
    let mut err: Vec<f64> = strikes
        .iter()
        .map(|p| {
            kin.events
                .iter()
                .filter(|k| k.kind == p.kind && k.side == p.side)
                .map(|k| (k.time - p.time).abs())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    err.sort_by(f64::total_cmp);
    assert!(err[err.len() - 1] < 0.060, "{err:?}");
    assert!(err[err.len() * 95 / 100] < 0.030, "{err:?}");
    assert!((err[err.len() / 2] - 0.0116).abs() < 0.002, "{err:?}");
}

/// Each `truth` event of `kind` against the nearest `found` event of the same foot and
/// kind (s, signed: found − truth), sorted by size.
fn errors(truth: &Detected, found: &Detected, kind: Kind) -> Vec<f64> {
    let mut err: Vec<f64> = truth
        .events
        .iter()
        .filter(|e| e.kind == kind)
        .filter_map(|p| {
            found
                .events
                .iter()
                .filter(|k| k.kind == p.kind && k.side == p.side)
                .map(|k| k.time - p.time)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        })
        .collect();
    err.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    err
}

#[test]
fn running_foot_offs_from_the_markers_come_where_the_toe_leaves_the_belt() {
    // RBDS001runT35's feet leave the floor before the other lands: a run, whose offs come
    // where the toe rises from its stance level (Zeni's toe extreme came 93 ms late, median,
    // 102 ms at the 95th percentile). Against the plate's 85 offs: 84 found within 150 ms,
    // median |error| 7.4 ms, 95th percentile 26 ms (the offset was chosen on c3d-more's
    // JA1Gait35; nothing on this file); since the off after the last strike is looked for
    // from the trial's end (its Zeni extreme lies past it), all 85, the last at 29.930 s
    // (the plate's 29.937 s, 0.06 s before the end).
    let Some(path) =
        testkit::c3d_labs_trial("regifukuchi__BMC-RIC-running-biomechanics__RBDS001runT35")
    else {
        return;
    };
    let plates = detect(&path, EventSource::Plates).unwrap();
    let kin = detect(&path, EventSource::Kinematics).unwrap();
    assert!(
        kin.notes.iter().any(|n| n.starts_with("running:")),
        "{:?}",
        kin.notes
    );
    let err: Vec<f64> = errors(&plates, &kin, Kind::FootOff)
        .into_iter()
        .filter(|e| e.abs() <= 0.15)
        .collect();
    assert_eq!(err.len(), 85);
    assert!((err[err.len() / 2].abs() - 0.0074).abs() < 0.001, "{err:?}");
    let last = kin
        .events
        .iter()
        .filter(|e| e.side == Side::Right && e.kind == Kind::FootOff)
        .map(|e| e.time)
        .fold(f64::NAN, f64::max);
    assert!((last - 29.930).abs() < 0.001, "{last}");
    assert!(err[err.len() * 95 / 100].abs() < 0.027, "{err:?}");
    // The sprint (5 plates): its three plate offs within 2 ms, where Zeni's were 44-48 ms
    // late (the last, 0.06 s before the trial's end, since extremes at the edge count).
    let Some(path) = testkit::c3d_labs_trial("basgoncalves__msk_modelling_python__sprint_1") else {
        return;
    };
    let plates = detect(&path, EventSource::Plates).unwrap();
    let kin = detect(&path, EventSource::Kinematics).unwrap();
    let err: Vec<f64> = errors(&plates, &kin, Kind::FootOff)
        .into_iter()
        .filter(|e| e.abs() <= 0.15)
        .collect();
    assert_eq!(err.len(), 3, "{err:?}");
    assert!(err.iter().all(|e| e.abs() < 0.002), "{err:?}");
}

#[test]
fn walking_trials_are_no_runs() {
    // The bundled synthetic walk: its Zeni offs come 35 ms before the other foot's strike,
    // but its toe rises 150 ms after them; a flight needs both offs to show it.
    let sample = testkit::workspace_root().join("sample_c3d/walk_truth.c3d");
    let kin = detect(&sample, EventSource::Kinematics).unwrap();
    assert!(kin.notes.is_empty(), "{:?}", kin.notes);
    // Double support: every walking trial of c3d-labs keeps Zeni's offs (no running note).
    for name in [
        "psbiomech__lasem-data-processing__FAILT01_Walk01",
        "s2mLab__BioptimPaperExamples__normal01_out",
        "RealTimeBiomechanics__rtosim__walking_1",
    ] {
        let Some(path) = testkit::c3d_labs_trial(name) else {
            return;
        };
        let kin = detect(&path, EventSource::Kinematics).unwrap();
        assert!(
            !kin.notes.iter().any(|n| n.starts_with("running:")),
            "{name}: {:?}",
            kin.notes
        );
    }
}

#[test]
fn a_labs_own_codes_in_the_general_context_are_read_as_gait_events() {
    // s2mLab's walk: LHS, RTO, RHS, LTO in General, two full cycles of each foot.
    let Some(path) = testkit::c3d_labs_trial("s2mLab__BioptimPaperExamples__normal01_out") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let ev = c3dfix::event_labels::file_gait_events(&c);
    assert_eq!(ev.len(), 7);
    let r = c3dfix::gait_parameters(&c, &c3dfix::GaitOptions::default(), &path).unwrap();
    let cadence = r
        .parameters
        .iter()
        .find(|p| p.context == "Left" && p.name == "Cadence")
        .map(|p| p.value);
    assert!(
        cadence.is_some_and(|v| (v - 129.0323).abs() < 1e-3),
        "{cadence:?}"
    );
    // The session calibration reads them as truth too.
    assert_eq!(c3dfix::lab_events(&c).len(), 7);
}

#[test]
fn treadmill_gait_parameters_leave_out_what_needs_the_belt_speed() {
    // rtosim: the markers' speed is the pelvis' drift (0.02 m/s), not the walk's.
    let Some(path) = testkit::c3d_labs_trial("RealTimeBiomechanics__rtosim__walking_1") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let opts = c3dfix::GaitOptions {
        detect: Some(EventOptions::default()),
        ..c3dfix::GaitOptions::default()
    };
    let r = c3dfix::gait_parameters(&c, &opts, &path).unwrap();
    let names: Vec<&str> = r
        .parameters
        .iter()
        .filter(|p| p.context == "Left")
        .map(|p| p.name)
        .collect();
    assert!(names.contains(&"Cadence") && names.contains(&"Step Width"));
    assert!(!names.contains(&"Walking Speed") && !names.contains(&"Stride Length"));
    assert!(r
        .warnings
        .contains(&c3dfix::gait_params::TREADMILL_WARNING.to_string()));
}

#[test]
fn a_belt_speed_given_measures_the_walk_over_the_belt() {
    // RBDS001runT35 runs at 3.5 m/s (its lab's description; the file stores no belt speed).
    // Given that speed, the toes carried into the belt's frame give 3.47 and 3.49 m/s and
    // strides of 2.45 and 2.53 m (0.71 and 0.72 s); without it they are left out.
    let Some(path) =
        testkit::c3d_labs_trial("regifukuchi__BMC-RIC-running-biomechanics__RBDS001runT35")
    else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let mut opts = c3dfix::GaitOptions {
        detect: Some(EventOptions::default()),
        belt_speed_m_s: Some(3.5),
        ..c3dfix::GaitOptions::default()
    };
    let r = c3dfix::gait_parameters(&c, &opts, &path).unwrap();
    let value = |r: &c3dfix::GaitReport, side: &str, name: &str| {
        r.parameters
            .iter()
            .find(|p| p.context == side && p.name == name)
            .map(|p| p.value)
    };
    for side in ["Left", "Right"] {
        let v = value(&r, side, "Walking Speed").unwrap();
        assert!((v - 3.5).abs() < 0.05, "{side}: {v}");
        let stride = value(&r, side, "Stride Length").unwrap();
        let time = value(&r, side, "Stride Time").unwrap();
        assert!((stride / time - v).abs() < 1e-9);
    }
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    opts.belt_speed_m_s = Some(-1.0);
    let e = c3dfix::gait_parameters(&c, &opts, &path).unwrap_err();
    assert!(e.to_string().contains("belt speed -1 m/s"), "{e}");
    opts.belt_speed_m_s = None;
    let r = c3dfix::gait_parameters(&c, &opts, &path).unwrap();
    assert_eq!(value(&r, "Left", "Walking Speed"), None);
}

#[test]
fn another_metatarsal_stands_in_where_the_toe_marker_is_missing() {
    // lasem's walk loses LTOE and RTOE near the trial's end; LP5MT and RP1MT/RP5MT, seen
    // there, stand in (moved by their median offset near each gap), and the last right and
    // left offs are found, each 0.11 and 0.10 s after the other foot's strike as in the
    // trial's other steps (16 events before, 18 now; no truth event moved in events_eval).
    let Some(path) = testkit::c3d_labs_trial("psbiomech__lasem-data-processing__FAILT01_Walk01")
    else {
        return;
    };
    let d = detect(&path, EventSource::Kinematics).unwrap();
    assert_eq!(d.events.len(), 18);
    assert!(
        d.notes
            .iter()
            .any(|n| n.starts_with("ltoe: LP5MT stands in for LTOE in 80 frames")),
        "{:?}",
        d.notes
    );
    assert_eq!(role(&d, "ltoe"), ["LTOE"]);
    let last_off = d
        .events
        .iter()
        .filter(|e| e.side == Side::Left && e.kind == Kind::FootOff)
        .map(|e| e.time)
        .fold(f64::NAN, f64::max);
    assert!((last_off - 6.6411).abs() < 1e-3, "{last_off}");
}

#[test]
fn a_marker_moving_rigidly_with_the_toe_stands_in_where_every_named_one_is_lost() {
    // MOtoNMS' Padova walks lose both right metatarsal heads (RIMH, RVMH) around the right
    // foot off; RIIT, 50 mm from RIMH and named in no list, keeps its offset from it within
    // 7-9 mm while the foot swings, and stands in. The lab's right offs (3.100 s, 2.917 s)
    // are found from the markers 32 and 38 ms late (missed before), and plate 1's right
    // stance, which gave no event for want of the toe near its centre of pressure, now
    // gives its strike and off in `auto`.
    for (trial, lab_off, plate) in [
        ("RehabEngGroup__MOtoNMS__Walking1", 3.100, (2.4318, 3.1289)),
        ("RehabEngGroup__MOtoNMS__Walking3", 2.917, (2.2367, 2.9466)),
    ] {
        let Some(path) = testkit::c3d_labs_trial(trial) else {
            return;
        };
        let d = detect(&path, EventSource::Kinematics).unwrap();
        assert!(
            d.notes
                .iter()
                .any(|n| n.starts_with("rtoe: RIIT stands in for RIMH")
                    && n.contains("as on one rigid part of the foot")),
            "{trial}: {:?}",
            d.notes
        );
        let off = d
            .events
            .iter()
            .filter(|e| e.side == Side::Right && e.kind == Kind::FootOff)
            .map(|e| e.time - lab_off)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap();
        assert!((0.025..0.045).contains(&off), "{trial}: {off}");
        let a = detect(&path, EventSource::Auto).unwrap();
        let on_plate: Vec<(Kind, f64)> = a
            .events
            .iter()
            .filter(|e| e.plate == Some(1))
            .map(|e| (e.kind, (e.time * 1e4).round() / 1e4))
            .collect();
        assert_eq!(
            on_plate,
            [(Kind::FootStrike, plate.0), (Kind::FootOff, plate.1)],
            "{trial}"
        );
        assert!(a.warnings.is_empty(), "{trial}: {:?}", a.warnings);
    }
}

#[test]
fn on_a_standing_trial_no_marker_is_taken_as_moving_with_the_foot() {
    // c3d-samples' sample_28 standing.C3D: a static calibration, whose toe and heel markers
    // have gaps. Standing still, every marker keeps its offset from every other (within
    // 1-5 mm here), so only frames where the foot moves may judge rigidity: none does, and
    // no marker stands in by position.
    let Some(dir) = testkit::c3d_samples() else {
        return;
    };
    let path = dir.join("sample_28/standing.C3D");
    let c = c3dfix::open(&path).unwrap();
    let mut choice = c3dfix::events::choose_markers(&c, &Default::default(), &path).unwrap();
    let feet = c3dfix::events::feet(&c, &mut choice, &path).unwrap();
    assert!(feet
        .left_toe
        .iter()
        .chain(&feet.right_heel)
        .any(|p| p[0].is_nan()));
    assert!(
        choice.stand_ins.iter().all(|s| !s.rigid),
        "{:?}",
        choice.stand_ins
    );
}

#[test]
fn a_one_letter_french_set_gives_its_events() {
    // c3d-samples' admarche2 (PD pied, CD cheville, BD bassin …, side last): once refused
    // for want of foot markers. The ankle stands in for the heel; where the right foot
    // lands on plate 1, `auto` takes the plate's strike and off, the markers elsewhere.
    let Some(dir) = testkit::c3d_samples() else {
        return;
    };
    let path = dir.join("sample_30/admarche2.c3d");
    let d = detect(&path, EventSource::Auto).unwrap();
    assert_eq!(role(&d, "rheel"), ["CD"]);
    assert_eq!(role(&d, "ltoe"), ["PG"]);
    assert_eq!(role(&d, "pelvis"), ["BG", "BD"]);
    // What standing in costs is said, per foot.
    assert_eq!(d.notes.len(), 2, "{:?}", d.notes);
    assert!(d.notes[1].starts_with("right foot: no heel marker, the ankle CD stands in for it"));
    assert_eq!(d.events.len(), 12);
    let plate: Vec<(Side, Kind, f64)> = d
        .events
        .iter()
        .filter(|e| e.plate.is_some())
        .map(|e| (e.side, e.kind, (e.time * 1e4).round() / 1e4))
        .collect();
    assert_eq!(
        plate,
        [
            (Side::Right, Kind::FootStrike, 2.712),
            (Side::Right, Kind::FootOff, 3.3074)
        ]
    );
    // From the markers alone the strike leads the plate's by 64 ms (the ankle's lead) and
    // the off by 29 ms.
    let k = detect(&path, EventSource::Kinematics).unwrap();
    let near = |kind: Kind, t: f64| {
        k.events
            .iter()
            .filter(|e| e.side == Side::Right && e.kind == kind)
            .map(|e| ((e.time - t) * 1000.0).round())
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
    };
    assert_eq!(near(Kind::FootStrike, 2.712), Some(-64.0));
    assert_eq!(near(Kind::FootOff, 3.3074), Some(-29.0));
}
