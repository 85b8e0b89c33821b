//! Plates and the lab's up on the next lab's trials (`c3d-labs`): a pull never made a push
//! by the baseline, no plate's contacts dropped without a word, plates' need of the foot
//! markers said, and the up of a subject who does not travel.

use c3dfix::events::{detect_events, EventOptions, EventSource};
use c3dfix::{force_platforms, ForceOptions};

fn labs(name: &str) -> Option<std::path::PathBuf> {
    Some(testkit::c3d_labs()?.join(format!("{name}.c3d")))
}

#[test]
fn a_plate_that_only_pulls_gets_no_baseline_and_no_contact() {
    // The sprint's plate 2: its vertical channel reads 0 on 548 samples of 785 and a pull
    // of about 95 N on the others; the quiet stretch's mean (a pull of 25.6 N) is no offset.
    let Some(path) = labs("basgoncalves__msk_modelling_python__sprint_1") else {
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
fn a_treadmills_plates_say_why_their_contacts_give_no_event() {
    // rtosim: each belt's plate shows 8 contacts, but the centre of pressure lies outside
    // the plate in every one (its ORIGIN's x and y read with the other sign would put it
    // under the feet): no foot can be told, and the events say so.
    let Some(path) = labs("RealTimeBiomechanics__rtosim__walking_1") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let opts = EventOptions {
        from: EventSource::Plates,
        ..EventOptions::default()
    };
    let d = detect_events(&c, &opts, &path).unwrap();
    assert!(d.events.is_empty());
    assert!(
        d.warnings[0].starts_with(
            "plate 1: 8 contact(s) but no event: the centre of pressure lies outside the plate in 8 of them"
        ),
        "{:?}",
        d.warnings
    );
    assert!(d.warnings[1].starts_with("plate 2: 8 contact(s)"));
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
    let Some(path) = labs("pyomeca__pyomeca__markers_analogs") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    let up = c3dfix::axes::up(&c).unwrap();
    assert_eq!(
        (up.up.to_string(), up.source),
        ("+z".to_string(), c3dfix::UpSource::Markers)
    );
}
