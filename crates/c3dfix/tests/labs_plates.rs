//! Plates and the lab's up on the next lab's trials (`c3d-labs`): a pull never made a push
//! by the baseline, an ORIGIN written from the other end read reversed, no plate's contacts
//! dropped without a word, plates' need of the foot markers said, and the up of a subject
//! who does not travel.

use c3dfix::events::{detect_events, EventOptions, EventSource};
use c3dfix::{force_platforms, ForceOptions};

#[test]
fn a_plate_that_only_pulls_gets_no_baseline_and_no_contact() {
    // The sprint's plate 2: its vertical channel reads 0 on 548 samples of 785 and a pull
    // of about 95 N on the others; the quiet stretch's mean (a pull of 25.6 N) is no offset.
    let Some(path) = testkit::c3d_labs_trial("basgoncalves__msk_modelling_python__sprint_1") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let fp = force_platforms(&c, &ForceOptions::default()).unwrap();
    let p2 = &fp.platforms[1];
    assert_eq!(p2.index, 2);
    assert!(p2.baseline.is_none());
    assert!(p2.contacts.is_empty());
    assert!(p2.push.iter().all(|v| *v <= 0.0));
    let w: Vec<String> = fp.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter()
            .any(|w| w.contains("pull of 25.6 N that moves by 40.5 N")),
        "{w:?}"
    );
    // The other plates keep their contacts (one footfall each on 1, 3 and 5).
    let n: Vec<usize> = fp.platforms.iter().map(|p| p.contacts.len()).collect();
    assert_eq!(n, [1, 0, 1, 0, 1]);
}

#[test]
fn a_runs_plate_reads_its_level_in_the_flights() {
    // RBDS' treadmill run (300 Hz) and pyorerun's run (2 kHz, one footfall in 0.4 s): every
    // quarter-second window holds part of a stance, so the plate once "carried at least
    // 234 N (552 N) throughout" and nothing was subtracted. Between the steps it reads
    // nothing: the level is taken in a flight, near zero, and no warning says otherwise.
    for (name, level_n, contacts) in [
        (
            "regifukuchi__BMC-RIC-running-biomechanics__RBDS001runT35",
            -0.3,
            100,
        ),
        ("pyomeca__pyorerun__Running_0002", -2.0, 1),
    ] {
        let Some(path) = testkit::c3d_labs_trial(name) else {
            return;
        };
        let c = c3dfix::open(&path).unwrap();
        let fp = force_platforms(&c, &ForceOptions::default()).unwrap();
        let p = &fp.platforms[0];
        let b = p.baseline.expect("a level read in a flight");
        assert_eq!(b.source, c3dfix::BaselineSource::Quiet, "{name}");
        assert!((b.level - level_n).abs() < 0.05, "{name}: {}", b.level);
        assert!(
            fp.warnings
                .iter()
                .all(|w| !w.to_string().contains("throughout")),
            "{name}: {:?}",
            fp.warnings
        );
        assert_eq!(p.contacts.len(), contacts, "{name}");
    }
}

#[test]
fn a_treadmill_plates_origin_written_from_the_other_end_is_read_reversed() {
    // rtosim: each belt's plate shows 8 contacts, but FORCE_PLATFORM:ORIGIN as stored puts
    // the centre of pressure outside the plate in every loaded sample; with x and y
    // negated it lies on the plate (and under one foot), and the plates give every step.
    let Some(path) = testkit::c3d_labs_trial("RealTimeBiomechanics__rtosim__walking_1") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let fp = force_platforms(&c, &ForceOptions::default()).unwrap();
    let origins: Vec<[f64; 3]> = fp
        .platforms
        .iter()
        .map(|p| p.origin.map(|v| (v * 10.0).round() / 10.0))
        .collect();
    assert_eq!(origins, [[241.3, 819.0, 0.0], [-241.0, 819.0, 0.0]]);
    let w: Vec<String> = fp.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w[0].contains(
            "outside the plate in 100 % of its loaded samples; with their signs reversed, 1 %"
        ),
        "{w:?}"
    );
    let opts = EventOptions {
        from: EventSource::Plates,
        ..EventOptions::default()
    };
    let d = detect_events(&c, &opts, &path).unwrap();
    assert_eq!(d.events.len(), 30);
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
}

#[test]
fn a_plates_contacts_that_give_no_event_are_said() {
    // sample21 marks the right leg only: plate 2's two contacts are the unmarked left
    // foot's, and no foot alone explains them.
    let Some(samples) = testkit::c3d_samples() else {
        return;
    };
    let path = samples.join("sample_21/sample21.c3d");
    let c = c3dfix::open(&path).unwrap();
    let d = detect_events(&c, &EventOptions::default(), &path).unwrap();
    assert!(
        d.warnings.iter().any(|w| w.starts_with(
            "plate 2: 2 contact(s) but no event: in none does one foot alone stand over the centre of pressure"
        )),
        "{:?}",
        d.warnings
    );
}

#[test]
fn plate_events_without_markers_say_plates_need_them() {
    // btkdata_Res16bits: six plates, no pelvis marker.
    let Some(extra) = testkit::c3d_extra() else {
        return;
    };
    let path = extra.join("btkdata_Res16bits.c3d");
    let c = c3dfix::open(&path).unwrap();
    let opts = EventOptions {
        from: EventSource::Plates,
        ..EventOptions::default()
    };
    let e = detect_events(&c, &opts, &path).unwrap_err().to_string();
    assert!(e.contains("no pelvis marker"), "{e}");
    assert!(
        e.contains("events from the plates need the foot and pelvis markers as well"),
        "{e}"
    );
}

#[test]
fn a_subject_lifting_on_the_spot_stands_on_z() {
    // pyomeca's box lifting: upper-body markers and a box held forward; the markers spread
    // farther along x than the pelvis-to-shoulder height, but the trunk stands along +z.
    let Some(path) = testkit::c3d_labs_trial("pyomeca__pyomeca__markers_analogs") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let up = c3dfix::axes::up(&c).unwrap();
    assert_eq!(
        (up.up.to_string(), up.source),
        ("+z".to_string(), c3dfix::UpSource::Markers)
    );
}
