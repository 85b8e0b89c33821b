//! The events glue on the repository's synthetic walk (no corpus needed): `auto`'s merge,
//! and the EVENT group as written (minutes and seconds, kept and replaced events).

use c3dfix::events::{merge_auto, to_trial_event, TrialEvent};
use c3dfix::gait::{Event, Kind, Side, Source};

fn walk() -> c3d::C3d {
    c3dfix::open(testkit::workspace_root().join("sample_c3d/walk_truth.c3d")).unwrap()
}

fn ev(side: Side, kind: Kind, index: f64, source: Source) -> Event {
    Event {
        side,
        kind,
        index,
        source,
        plate: (source == Source::Plate).then_some(1),
    }
}

#[test]
fn auto_replaces_a_kinematic_event_near_a_plate_event_of_the_same_foot_and_kind() {
    let kin = [
        ev(Side::Left, Kind::FootStrike, 100.0, Source::Kinematics),
        ev(Side::Right, Kind::FootStrike, 150.0, Source::Kinematics),
        ev(Side::Left, Kind::FootStrike, 210.0, Source::Kinematics),
    ];
    let plates = [
        ev(Side::Left, Kind::FootStrike, 103.5, Source::Plate),
        // The other foot's strike near a kinematic one: both kept.
        ev(Side::Left, Kind::FootStrike, 148.0, Source::Plate),
    ];
    let m = merge_auto(&plates, &kin, 100.0);
    let got: Vec<(f64, Source)> = m.iter().map(|e| (e.index, e.source)).collect();
    assert_eq!(
        got,
        vec![
            (103.5, Source::Plate),
            (148.0, Source::Plate),
            (150.0, Source::Kinematics),
            (210.0, Source::Kinematics)
        ]
    );
}

#[test]
fn the_event_group_holds_minutes_and_seconds_and_keeps_or_replaces_the_files_events() {
    let mut c = walk();
    assert_eq!(c.events().len(), 7);
    // walk_truth: 100 Hz, first frame 1, so index 7549.5 is at 75.495 s, frame 7551.
    let e = to_trial_event(
        &c,
        &ev(Side::Right, Kind::FootOff, 7549.5, Source::Kinematics),
    );
    assert_eq!((e.frame, e.context, e.label), (7551, "Right", "Foot Off"));
    assert!((e.time - 75.495).abs() < 1e-9);
    let new: Vec<TrialEvent> = vec![e];
    let w = c3dfix::event_group::write_events(&mut c, &new, false).unwrap();
    assert_eq!((w.added, w.removed, w.total), (1, 0, 8));
    let times = c.parameters.get("EVENT", "TIMES").unwrap().as_f32s();
    assert_eq!(times.len(), 16);
    assert_eq!(times[14], 1.0);
    assert!((times[15] - 15.495).abs() < 1e-4, "{}", times[15]);
    let back = c.events();
    assert_eq!(back.len(), 8);
    assert!((back[7].time - 75.495).abs() < 1e-4);
    assert_eq!(
        back[7].description,
        "The moment the foot ceases all contact with the floor during a gait cycle."
    );
    let ctx = c.parameters.get_strings("EVENT_CONTEXT", "LABELS").unwrap();
    assert_eq!(
        ctx.iter().map(|s| s.trim()).collect::<Vec<_>>(),
        ["Left", "Right", "General"]
    );
    // --replace: the file's seven Foot Strike events and the one added go.
    let w = c3dfix::event_group::write_events(&mut c, &new, true).unwrap();
    assert_eq!((w.removed, w.total), (8, 1));
    // Written and read back.
    let bytes = c.to_bytes().unwrap();
    let r = c3d::read(bytes).unwrap();
    assert_eq!(r.events().len(), 1);
    assert_eq!(r.parameters.get_i32("EVENT", "USED"), Some(1));
    let icons = r.parameters.get("EVENT", "ICON_IDS").unwrap().as_f32s();
    assert_eq!(icons, vec![2.0]);
}
