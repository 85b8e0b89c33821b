//! The expected-error model's `accel` evidence on a real drop jump: the marker's mean
//! acceleration beside a gap over its mean over the whole recording
//! (`repair::fill::accel_ratio`) must read the landing as harder than the quiet standing
//! before it, which is why it was added (issue 45 item 7: the drop jumps' gaps were judged
//! as a walk's of the same speed).

use repair::fill::accel_ratio;

/// A ratio of the evidence: of the trajectory, which samples are recorded, the gap's first
/// frame and length.
type Ratio = fn(&[[f64; 3]], &dyn Fn(usize) -> bool, usize, usize) -> Option<f64>;

/// Every position of a 10-frame gap in marker `m` (step 5), with its `ratio`.
fn ratios(t: &repair::Trial, m: usize, ratio: Ratio) -> Vec<(usize, f64)> {
    let n = t.frames();
    (0..n.saturating_sub(10))
        .step_by(5)
        .filter_map(|a| {
            let ok = |f: usize| t.valid[m][f] && !(a..a + 10).contains(&f);
            ratio(&t.xyz[m], &ok, a, 10).map(|r| (a, r))
        })
        .collect()
}

/// The least and largest ratio.
fn range(v: &[(usize, f64)]) -> (f64, f64) {
    v.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &(_, r)| {
        (lo.min(r), hi.max(r))
    })
}

/// psbiomech's single-leg drop jump SLDJ01 (the recorded samples only) and its sacrum's row,
/// or `None` without c3d-labs.
fn drop_jumps_sacrum() -> Option<(repair::Trial, usize)> {
    let root = testkit::c3d_labs()?;
    let path = root.join("psbiomech__lasem-data-processing__FAILT01_SLDJ01.c3d");
    let c = c3d::read_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let labels = c.point_labels();
    let t = evals::corpus::load_recorded(&path).unwrap_or_else(|e| panic!("{e}"));
    let sacrum = evals::corpus::markers_of(&c)
        .iter()
        .position(|&i| labels[i].trim() == "SACR")
        .expect("a sacrum marker");
    Some((t, sacrum))
}

#[test]
fn a_drop_jumps_landing_reads_harder_than_its_standing() {
    // The sacrum: the whole body drops, lands and stands still.
    let Some((t, sacrum)) = drop_jumps_sacrum() else {
        return;
    };
    let v = ratios(&t, sacrum, |x, ok, a, n| accel_ratio(x, ok, a, n));
    let (lo, hi) = range(&v);
    println!("{} positions, ratio {lo:.3} to {hi:.3}", v.len());
    // 137 positions, 0.055 to 5.35 (the landing against standing still).
    assert!(hi > 4.5, "largest {hi}");
    assert!(lo < 0.1, "least {lo}");
    // A gap with no recorded frame beside it has nothing to read.
    let none = accel_ratio(&t.xyz[sacrum], |_| false, 100, 10);
    assert_eq!(none, None);
}

/// The `speed` evidence (`repair::fill::speed_ratio`) on the same jump: the sacrum's mean
/// step beside a 10-frame gap over its mean step reads the drop and landing as fast and
/// the standing as still; the model's choice of it (beside the method leading the fill)
/// was made on the older corpora's labs (docs/fill-evaluation.md, "Issue 45 item 7, third
/// round").
#[test]
fn a_drop_jumps_fall_reads_faster_than_its_standing() {
    let Some((t, sacrum)) = drop_jumps_sacrum() else {
        return;
    };
    let v = ratios(&t, sacrum, |x, ok, a, n| {
        repair::fill::speed_ratio(x, ok, a, n)
    });
    let (lo, hi) = range(&v);
    println!("{} positions, ratio {lo:.3} to {hi:.3}", v.len());
    assert!(hi > 4.0, "largest {hi}");
    assert!(lo < 0.2, "least {lo}");
    let none = repair::fill::speed_ratio(&t.xyz[sacrum], |_| false, 100, 10);
    assert_eq!(none, None);
}
