//! The expected-error model's `accel` evidence on a real drop jump: the marker's mean
//! acceleration beside a gap over its mean over the whole recording
//! (`repair::fill::accel_ratio`) must read the landing as harder than the quiet standing
//! before it, which is why it was added (issue 45 item 7: the drop jumps' gaps were judged
//! as a walk's of the same speed).

use repair::fill::accel_ratio;

/// Every position of a 10-frame gap in marker `m` (step 5), with its ratio.
fn ratios(t: &repair::Trial, m: usize) -> Vec<(usize, f64)> {
    let n = t.frames();
    (0..n.saturating_sub(10))
        .step_by(5)
        .filter_map(|a| {
            let ok = |f: usize| t.valid[m][f] && !(a..a + 10).contains(&f);
            accel_ratio(&t.xyz[m], ok, a, 10).map(|r| (a, r))
        })
        .collect()
}

#[test]
fn a_drop_jumps_landing_reads_harder_than_its_standing() {
    let Some(root) = testkit::c3d_labs() else {
        return;
    };
    let path = root.join("psbiomech__lasem-data-processing__FAILT01_SLDJ01.c3d");
    let c = c3d::read_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let labels = c.point_labels();
    let t = evals::corpus::load_recorded(&path).unwrap_or_else(|e| panic!("{e}"));
    let markers = evals::corpus::markers_of(&c);
    // The sacrum: the whole body drops, lands and stands still.
    let sacrum = markers
        .iter()
        .position(|&i| labels[i].trim() == "SACR")
        .expect("a sacrum marker");
    let v = ratios(&t, sacrum);
    let (lo, hi) = v.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &(_, r)| {
        (lo.min(r), hi.max(r))
    });
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
    let Some(root) = testkit::c3d_labs() else {
        return;
    };
    let path = root.join("psbiomech__lasem-data-processing__FAILT01_SLDJ01.c3d");
    let c = c3d::read_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let labels = c.point_labels();
    let t = evals::corpus::load_recorded(&path).unwrap_or_else(|e| panic!("{e}"));
    let markers = evals::corpus::markers_of(&c);
    let sacrum = markers
        .iter()
        .position(|&i| labels[i].trim() == "SACR")
        .expect("a sacrum marker");
    let n = t.frames();
    let v: Vec<(usize, f64)> = (0..n.saturating_sub(10))
        .step_by(5)
        .filter_map(|a| {
            let ok = |f: usize| t.valid[sacrum][f] && !(a..a + 10).contains(&f);
            repair::fill::speed_ratio(&t.xyz[sacrum], ok, a, 10).map(|r| (a, r))
        })
        .collect();
    let (lo, hi) = v.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &(_, r)| {
        (lo.min(r), hi.max(r))
    });
    println!("{} positions, ratio {lo:.3} to {hi:.3}", v.len());
    assert!(hi > 4.0, "largest {hi}");
    assert!(lo < 0.2, "least {lo}");
    let none = repair::fill::speed_ratio(&t.xyz[sacrum], |_| false, 100, 10);
    assert_eq!(none, None);
}
