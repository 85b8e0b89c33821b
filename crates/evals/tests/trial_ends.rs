//! Where the fill evaluation puts its gaps on a real trial: at a trial's ends with
//! `--trial-ends`, inside it otherwise.

use evals::corpus;
use repair::{evaluate, EvalConfig, FillMethod};

/// Gaps at a trial's start or end (`at_trial_ends`), on a real walking trial: each touches
/// the first or last frame of the trial as cut for it, so the polynomial methods, which
/// need samples on both sides, refuse every one and `auto` fills every one from donors; the
/// same gaps inside the trial are filled by both.
#[test]
fn trial_end_gaps_touch_the_trials_ends() {
    let Some(root) = testkit::c3d_samples() else {
        eprintln!("skipping: c3d-samples not found (set C3D_SAMPLES)");
        testkit::skipped("c3d-samples not found");
        return;
    };
    let trial = corpus::load(&root.join("sample_06/newwalk.c3d")).expect("newwalk reads");
    let n = trial.frames();
    for ends in [true, false] {
        let cfg = EvalConfig {
            gap_lengths: vec![10],
            gaps_per_length: 8,
            methods: vec![FillMethod::Spline, FillMethod::Auto],
            seed: 5,
            at_trial_ends: ends,
            ..EvalConfig::default()
        };
        let e = evaluate(&trial, &cfg).expect("evaluation runs");
        let spline = e.score(FillMethod::Spline, 10).unwrap();
        let auto = e.score(FillMethod::Auto, 10).unwrap();
        assert_eq!(spline.gaps, 8, "ends {ends}: every gap placed");
        if ends {
            assert_eq!(spline.failed, 8, "a polynomial filled a gap at an end");
        } else {
            assert_eq!(spline.failed, 0);
        }
        assert_eq!(auto.failed, 0, "ends {ends}");
        assert!(auto.mean > 0.0 && auto.mean < 50.0, "ends {ends}: {auto:?}");
        // Records give the gaps' frames in the whole trial.
        for g in e.gaps.iter().filter(|g| g.method == FillMethod::Auto) {
            assert!(g.first + 10 <= n, "{g:?}");
        }
    }
}
