//! Unlabelled points are not markers (issue 47): a repair fills, searches for swaps and
//! counts the labelled markers only; the points a lab did not label are counted apart and
//! come out as they went in.

use c3dfix::RepairOptions;

/// c3d-labs' fast walk: 80 points, 29 of them `*51`…`*79`. Before, the repair spoke of
/// "1500 gaps in 80 markers … 1166 left (implausible 988 …)" and a swap `*53 ↔ *55`.
#[test]
fn fast_walk_speaks_of_its_51_labelled_markers_and_leaves_29_unlabelled_as_recorded() {
    let Some(labs) = testkit::c3d_labs() else {
        testkit::skipped("C3D_LABS absent");
        return;
    };
    let path = labs.join("RehabEngGroup__MOtoNMS__Fast_Walking.c3d");
    let original = c3dfix::open(&path).unwrap();
    let mut c = original.clone();
    let done = c3dfix::repair(&mut c, &RepairOptions::default(), &path).unwrap();
    let s = &done.summary;
    assert_eq!((s.markers, s.gaps, s.filled, s.left), (51, 98, 6, 92));
    let u = s.unlabelled.as_ref().unwrap();
    assert_eq!((u.points, u.samples), (29, 12590));
    assert_eq!(s.left_because.get(c3dfix::SkipKind::Implausible), 0);
    assert!(done.gap_list.iter().all(|g| !g.label.starts_with('*')));
    assert!(done
        .swaps
        .iter()
        .all(|b| b.find.markers.iter().all(|m| !m.starts_with('*'))));
    // Every unlabelled point's samples are the recorded ones, bit for bit.
    let labels = original.point_labels();
    let (a, b) = (original.points(), c.points());
    let mut seen = 0;
    for p in (0..labels.len()).filter(|&p| labels[p].starts_with('*')) {
        seen += 1;
        for f in 0..original.frames() {
            assert_eq!(
                a.is_valid(f, p),
                b.is_valid(f, p),
                "{} frame {f}",
                labels[p]
            );
        }
        assert_eq!(a.trajectory(p), b.trajectory(p), "{}", labels[p]);
        assert_eq!(a.residuals(p), b.residuals(p), "{}", labels[p]);
    }
    assert_eq!(seen, 29);
    // Asked for by name, an unlabelled point is refused with why.
    let opts = RepairOptions {
        markers: Some(vec!["*53".into()]),
        ..RepairOptions::default()
    };
    let e = c3dfix::repair(&mut original.clone(), &opts, &path).unwrap_err();
    assert!(
        e.to_string().contains("\"*53\" is an unlabelled point"),
        "{e}"
    );
}

/// A lab's own placeholder, by pattern (here `lth3`, any case): the fast walk's `LTH3` named unlabelled
/// leaves 50 markers, its gap with them, and the pattern in the record's fill settings.
#[test]
fn a_pattern_adds_the_labs_own_placeholder() {
    let Some(labs) = testkit::c3d_labs() else {
        testkit::skipped("C3D_LABS absent");
        return;
    };
    let path = labs.join("RehabEngGroup__MOtoNMS__Fast_Walking.c3d");
    let mut c = c3dfix::open(&path).unwrap();
    let opts = RepairOptions {
        unlabelled: Some("lth3".parse().unwrap()),
        ..RepairOptions::default()
    };
    let done = c3dfix::repair(&mut c, &opts, &path).unwrap();
    let s = &done.summary;
    assert_eq!(s.markers, 50);
    assert_eq!(s.unlabelled.as_ref().map(|u| u.points), Some(30));
    assert!(done.gap_list.iter().all(|g| g.label != "LTH3"));
    let record = c3dfix::RepairRecord::read(&c);
    assert!(
        record
            .fill
            .as_deref()
            .unwrap()
            .ends_with("--unlabelled lth3"),
        "{:?}",
        record.fill
    );
}

/// A trial with no labelled marker (c3d-samples' 128analogchannels names its ten points
/// `*1`…`*10`) is repaired to nothing: no gap, no change, the points counted apart.
#[test]
fn a_trial_of_unlabelled_points_only_changes_nothing() {
    let Some(samples) = testkit::c3d_samples() else {
        testkit::skipped("C3D_SAMPLES absent");
        return;
    };
    let path = samples.join("sample_17/128analogchannels.c3d");
    let original = c3dfix::open(&path).unwrap();
    let mut c = original.clone();
    let done = c3dfix::repair(&mut c, &RepairOptions::default(), &path).unwrap();
    let s = &done.summary;
    assert_eq!((s.markers, s.gaps, s.samples_changed), (0, 0, 0));
    assert_eq!(s.unlabelled.as_ref().map(|u| u.points), Some(10));
    assert_eq!(original.points().trajectory(0), c.points().trajectory(0));
}
