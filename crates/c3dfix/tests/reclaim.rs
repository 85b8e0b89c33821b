//! Reclaiming in a repair (issue 47): `--reclaim on` moves the settled unlabelled samples
//! into their markers as recorded, the file records it, and a rerun changes nothing; a trial
//! without unlabelled points is left byte for byte as the stage off leaves it.

use c3dfix::ReclaimAction;
use c3dfix::{ReclaimMode, RepairOptions};

fn on() -> RepairOptions {
    RepairOptions {
        reclaim: ReclaimMode::On,
        ..RepairOptions::default()
    }
}

/// c3d-labs' fast walk: the settled pieces are moved sample for sample (coordinates,
/// residual, camera mask as recorded), the unlabelled point is missing there, C3DFIX
/// records every move, and repairing the result writes the same bytes.
#[test]
fn fast_walk_reclaimed_keeps_recorded_samples_and_reruns_to_the_same_bytes() {
    let Some(labs) = testkit::c3d_labs() else {
        testkit::skipped("C3D_LABS absent");
        return;
    };
    let path = labs.join("RehabEngGroup__MOtoNMS__Fast_Walking.c3d");
    let original = c3dfix::open(&path).unwrap();
    let mut c = original.clone();
    let done = c3dfix::repair(&mut c, &on(), &path).unwrap();
    let s = &done.summary;
    let moved: Vec<_> = done
        .reclaim
        .settled
        .iter()
        .filter(|b| b.action == ReclaimAction::Moved)
        .collect();
    assert!(!moved.is_empty(), "{:?}", done.reclaim.settled);
    assert_eq!(s.reclaimed, moved.iter().map(|b| b.samples).sum::<usize>());
    let (a, b) = (original.points(), c.points());
    let filled = c3dfix::RepairRecord::read(&c).filled;
    for m in &moved {
        // A later fill never covers a moved sample: they are data.
        assert!(!filled
            .iter()
            .any(|&(p, x, y)| p == m.point && x <= m.last_index && m.first_index <= y));
        let (src, dst) = (a.trajectory(m.source_point), b.trajectory(m.point));
        let (rs, rd) = (a.residuals(m.source_point), b.residuals(m.point));
        for f in m.first_index..=m.last_index {
            assert!(!a.is_valid(f, m.point) && a.is_valid(f, m.source_point));
            assert_eq!(src[f].map(f32::to_bits), dst[f].map(f32::to_bits));
            assert_eq!(rs[f].to_bits(), rd[f].to_bits());
            assert!(!b.is_valid(f, m.source_point), "{} frame {f}", m.source);
        }
    }
    let record = c3dfix::RepairRecord::read(&c);
    assert_eq!(record.reclaim.as_deref(), Some("--reclaim on"));
    assert_eq!(record.reclaimed.len(), moved.len());
    // The rerun: the stage is not applied twice, nothing changes.
    let first = c.to_bytes().unwrap();
    let mut again = c3d::read(first.clone()).unwrap();
    let rerun = c3dfix::repair(&mut again, &on(), &path).unwrap();
    assert_eq!(rerun.summary.reclaimed, 0);
    assert!(rerun
        .summary
        .already_applied
        .iter()
        .any(|x| x.starts_with("reclaim")));
    assert_eq!(again.to_bytes().unwrap(), first);
}

/// Trials with no unlabelled point: the stage on changes no byte against the stage off.
#[test]
fn no_unlabelled_points_no_change() {
    let Some(more) = testkit::c3d_more() else {
        testkit::skipped("C3D_MORE absent");
        return;
    };
    for name in [
        "keenon__nimblephysics__nick_freeform_001.c3d",
        "qualisys__cgm2-web-report-uploader__ClinicalGait_Gait1.c3d",
    ] {
        let path = more.join(name);
        let original = c3dfix::open(&path).unwrap();
        let (mut x, mut y) = (original.clone(), original.clone());
        let off = RepairOptions {
            reclaim: ReclaimMode::Off,
            ..RepairOptions::default()
        };
        let dx = c3dfix::repair(&mut x, &on(), &path).unwrap();
        c3dfix::repair(&mut y, &off, &path).unwrap();
        assert!(dx.summary.unlabelled.is_none() && dx.reclaim.settled.is_empty());
        assert_eq!(x.to_bytes().unwrap(), y.to_bytes().unwrap(), "{name}");
    }
}

/// `c3dfix reclaim` lists what `repair --reclaim on` moves, and changes nothing.
#[test]
fn the_listing_is_what_the_repair_moves() {
    let Some(labs) = testkit::c3d_labs() else {
        testkit::skipped("C3D_LABS absent");
        return;
    };
    let path = labs.join("RehabEngGroup__MOtoNMS__Running_1.c3d");
    let original = c3dfix::open(&path).unwrap();
    let listed = c3dfix::reclaim(&original, &path, &repair::Unlabelled::common(), false).unwrap();
    assert_eq!((listed.markers, listed.unlabelled), (33, 36));
    let mut c = original.clone();
    let done = c3dfix::repair(&mut c, &on(), &path).unwrap();
    let key = |b: &c3dfix::ReclaimBrief| (b.point, b.source_point, b.first_index, b.last_index);
    let a: Vec<_> = listed.settled.iter().map(key).collect();
    let b: Vec<_> = done.reclaim.settled.iter().map(key).collect();
    assert_eq!(a, b);
    assert!(listed
        .settled
        .iter()
        .all(|b| b.action == ReclaimAction::Reported));
    assert_eq!(listed.unsettled, done.reclaim.unsettled);
}

/// A small trial written in memory: `labels` points over `frames` frames at 100 Hz, in mm,
/// each sample from `at` (`None`: missing).
fn made(frames: usize, labels: &[&str], at: impl Fn(usize, usize) -> Option<[f32; 3]>) -> c3d::C3d {
    use c3d::{Analog, C3d, Parameters, Points, Processor};
    let mut pts = Points::new(frames, labels.len());
    for f in 0..frames {
        for m in 0..labels.len() {
            if let Some(p) = at(f, m) {
                let k = pts.index(f, m);
                pts.xyz[k] = p;
                pts.residual[k] = 0.5;
            }
        }
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 100.0).unwrap();
    let labels: Vec<String> = labels.iter().map(|l| l.to_string()).collect();
    ps.set_strings("POINT", "LABELS", &labels).unwrap();
    ps.set_strings("POINT", "UNITS", &["mm".to_string()])
        .unwrap();
    let bytes = C3d::new(pts, Analog::new(frames, 0, 1), ps, Processor::Intel, -1.0)
        .to_bytes()
        .unwrap();
    c3d::read(bytes).unwrap()
}

/// Four markers of one rigid body walking along x; marker 0 (`A`) is lost over frames
/// 80–119, where `*1` holds its samples.
fn walker(f: usize, m: usize) -> [f32; 3] {
    let o = [
        [0.0, 0.0, 0.0],
        [120.0, 0.0, 10.0],
        [0.0, 90.0, -20.0],
        [60.0, 40.0, 80.0],
    ];
    let t = f as f32 / 100.0;
    [
        1000.0 * t + o[m][0],
        200.0 + o[m][1],
        900.0 + o[m][2] + 20.0 * (3.0 * t).sin(),
    ]
}

fn lost(f: usize) -> bool {
    (80..120).contains(&f)
}

/// Bad input gets clear answers and no panic: a mode misspelt, a trial of one frame, NaN
/// coordinates in the unlabelled point, and a label given twice.
#[test]
fn bad_input_one_frame_nan_and_duplicate_labels() {
    let e = "maybe".parse::<ReclaimMode>().unwrap_err().to_string();
    assert!(e.contains("expected on, report or off"), "{e}");
    let name = std::path::Path::new("made.c3d");
    // One frame.
    let mut c = made(1, &["A", "B", "*1"], |_, m| (m < 2).then(|| walker(0, m)));
    let done = c3dfix::repair(&mut c, &on(), name).unwrap();
    assert_eq!((done.summary.reclaimed, done.summary.markers), (0, 2));
    // The walker, moved back: the recorded samples, the unlabelled point missing there.
    let labels = ["A", "B", "C", "D", "*1"];
    let at = |f: usize, m: usize| match m {
        0 => (!lost(f)).then(|| walker(f, 0)),
        4 => lost(f).then(|| walker(f, 0)),
        _ => Some(walker(f, m)),
    };
    let mut c = made(300, &labels, at);
    let done = c3dfix::repair(&mut c, &on(), name).unwrap();
    assert_eq!(done.summary.reclaimed, 40, "{:?}", done.reclaim.settled);
    assert!((80..120).all(|f| c.points().is_valid(f, 0) && !c.points().is_valid(f, 4)));
    // NaN in the unlabelled samples: missing by the one rule, never moved.
    let nan = |f: usize, m: usize| {
        if m == 4 && lost(f) {
            Some([f32::NAN; 3])
        } else {
            at(f, m)
        }
    };
    let mut c = made(300, &labels, nan);
    let done = c3dfix::repair(&mut c, &on(), name).unwrap();
    assert_eq!(done.summary.reclaimed, 0);
    // `*1` twice, holding the same samples: neither is settled, both are reported.
    let twice = ["A", "B", "C", "D", "*1", "*1"];
    let both = |f: usize, m: usize| at(f, m.min(4));
    let mut c = made(300, &twice, both);
    let done = c3dfix::repair(&mut c, &on(), name).unwrap();
    assert_eq!(done.summary.reclaimed, 0);
    assert_eq!(done.reclaim.unsettled.len(), 2);
    assert!(done
        .reclaim
        .unsettled
        .iter()
        .all(|u| matches!(u.why, c3dfix::UnsettledWhy::Ambiguous { .. })));
}
