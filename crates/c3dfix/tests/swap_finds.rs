//! Label errors of the corpus files themselves (issue 34: "a real swap in a corpus trial is
//! a find: show it"): each asserted on the published file, with what the samples show.

use c3dfix::repair_lib::swaps::{FindKind, SwapOptions};

/// `hockey_wristshot009.c3d` (c3d-more, PhilD001): from frame 575 to the trial's end the
/// label Reed:LFHD holds one sample repeated, its x and y frozen at the last measured ones
/// and its z at 0 — on the floor, 1.87 m under the head, whose four other markers go on
/// moving. Not a measurement of the marker: the finding calls it a settled jump over exactly
/// those frames, and `repair --swaps fix` makes them a gap.
#[test]
fn hockey_forehead_marker_dropped_to_the_floor_is_a_settled_jump() {
    let Some(dir) = testkit::c3d_more() else {
        testkit::skipped("C3D_MORE absent");
        return;
    };
    let path = dir.join("PhilD001__biomechZoo__hockey_wristshot009.c3d");
    let c = c3dfix::c3d::read_file(&path).unwrap();
    let found = c3dfix::swaps(&c, &path, &SwapOptions::default()).unwrap();
    let lfhd: Vec<_> = found
        .swaps
        .iter()
        .filter(|x| x.markers.iter().any(|m| m == "Reed:LFHD"))
        .collect();
    assert_eq!(lfhd.len(), 1, "{lfhd:?}");
    let x = lfhd[0];
    assert_eq!(x.kind, FindKind::Jump);
    assert_eq!((x.first_frame, x.last_frame), (575, 727));
    assert!(x.settled && x.confidence > 0.95, "{x:?}");
    assert_eq!(x.last_frame, c.frame_number(c.points().frames() - 1));

    // The samples: measured and moving up to frame 574, then one point on the floor.
    let i = c
        .point_labels()
        .iter()
        .position(|l| l == "Reed:LFHD")
        .unwrap();
    let t = c.points().trajectory(i);
    let at = |frame: usize| t[frame - c.frame_number(0)];
    assert!(at(574)[2] > 1800.0, "{:?}", at(574));
    assert_ne!(at(573), at(574));
    for frame in 575..=727 {
        assert_eq!(at(frame)[2], 0.0, "frame {frame}");
        assert_eq!(at(frame), at(575), "frame {frame}");
    }
    assert!((at(575)[0] - at(574)[0]).abs() < 1e-3 && (at(575)[1] - at(574)[1]).abs() < 1e-3);
}

/// `JA1Gait35.c3d` (c3d-more, keenon): LARM, an arm marker with one link, leaps by 10–30 mm
/// in nearly every frame of 941–949 (file numbering) as the arm swings fast, and the leaps
/// at the two ends happen to take each other back. A label on another point would follow
/// that point as smoothly as any marker: leaps amid leaps are noise, and not reported.
#[test]
fn fast_arm_marker_that_leaps_in_every_frame_is_not_a_jump() {
    let Some(dir) = testkit::c3d_more() else {
        testkit::skipped("C3D_MORE absent");
        return;
    };
    let path = dir.join("keenon__nimblephysics__JA1Gait35.c3d");
    let c = c3dfix::c3d::read_file(&path).unwrap();
    let found = c3dfix::swaps(&c, &path, &SwapOptions::default()).unwrap();
    assert!(
        found
            .swaps
            .iter()
            .all(|x| !x.markers.iter().any(|m| m == "LARM")),
        "{:?}",
        found.swaps
    );
    // The leaps are there: LARM's third difference in 941–949 is above 8 mm in most frames.
    let i = c.point_labels().iter().position(|l| l == "LARM").unwrap();
    let t = c.points().trajectory(i);
    let at = |frame: usize| t[frame - c.frame_number(0)];
    let leap = |frame: usize| -> f32 {
        let (p0, p1, p2, p3) = (at(frame - 2), at(frame - 1), at(frame), at(frame + 1));
        let v: Vec<f32> = (0..3)
            .map(|k| (p2[k] - p1[k]) - 0.5 * ((p1[k] - p0[k]) + (p3[k] - p2[k])))
            .collect();
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
    };
    let big = (941..=949).filter(|&f| leap(f) > 8.0).count();
    assert!(big >= 6, "{big} of 9 frames leap above 8 mm");
}
