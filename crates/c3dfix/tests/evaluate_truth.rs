//! What `evaluate` takes as the truth of an artificial gap: ART-Human's sample trial stores
//! the one frame where the body was lost as every point at exactly (0, 0, 0) with a valid
//! fourth word. Scored against that frame, a fill was off by the marker's distance from the
//! origin; the evaluation now knocks no gap there.

use c3dfix::{evaluate, EvaluateOptions, FillMethod};

/// The lost frame of `arthuman-sample.c3d` (0-based), and the valid samples an artificial
/// gap keeps on each side of it (`repair`'s placement margin).
const LOST: usize = 2463;
const MARGIN: usize = 4;

#[test]
fn no_artificial_gap_touches_samples_at_the_origin() {
    let Some(dir) = testkit::c3d_samples() else {
        return;
    };
    let path = dir.join("sample_00/Advanced Realtime Tracking GmbH/arthuman-sample.c3d");
    let c = c3dfix::open(&path).expect("arthuman-sample.c3d");
    // The frame as stored: every point at the origin, none flagged missing.
    let p = c.points();
    assert_eq!(p.count(), 63);
    for i in 0..p.count() {
        assert!(p.is_valid(LOST, i), "point {i}");
        assert_eq!(p.trajectory(i)[LOST], [0.0; 3], "point {i}");
        assert_ne!(p.trajectory(i)[LOST - 1], [0.0; 3], "point {i}");
    }
    let opts = EvaluateOptions {
        gap_lengths: vec![5, 20, 80],
        methods: Some(vec![FillMethod::Linear]),
        gaps_per_length: 200,
        ..EvaluateOptions::default()
    };
    let ev = evaluate(&[path], &opts, |_| {}).expect("evaluate");
    let gaps = &ev.files[0].evaluation.gaps;
    // Most stretches of this trial are points computed from three others and get no gap;
    // the rest still do.
    assert!(gaps.len() > 20, "{} gaps", gaps.len());
    for g in gaps {
        let (lo, hi) = (g.first - MARGIN, g.first + g.gap_len + MARGIN);
        assert!(
            !(lo..hi).contains(&LOST),
            "marker {} frames {}..{}",
            g.marker,
            g.first,
            g.first + g.gap_len
        );
    }
}
