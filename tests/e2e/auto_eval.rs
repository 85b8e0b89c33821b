//! Issue 3's acceptance criterion on real gait trials: `evaluate` shows `auto` at or below
//! the best single method at every gap length (pooled over the trials), and the donor
//! methods (PCA, rigid) well below the polynomials from 20 frames up.

use super::{c3dfix, stderr};

#[test]
fn auto_beats_every_single_method_on_real_gait_trials() {
    let Some(dir) = testkit::c3d_samples() else {
        return;
    };
    let files: Vec<_> = [
        "sample_06/newwalk.c3d",
        "sample_09/PlugInC3D.c3d",
        "sample_00/Motion Analysis Corporation/Walk1.c3d",
        "sample_30/marche281.c3d",
        "sample_03/gait-pig.c3d",
        "sample_03/gait-raw.c3d",
    ]
    .iter()
    .map(|f| dir.join(f))
    .collect();
    if let Some(f) = files.iter().find(|f| !f.exists()) {
        eprintln!("skipping: {} not found", f.display());
        testkit::skipped(&format!("{} not found", f.display()));
        return;
    }
    let mut args = vec![
        "evaluate",
        "--json",
        "--seed",
        "1",
        "--gaps-per-length",
        "40",
    ];
    args.extend(files.iter().map(|f| f.to_str().expect("utf-8 path")));
    let out = c3dfix(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mean = |len: u64, method: &str| -> f64 {
        v["pooled"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["gap_len"] == len && r["method"] == method)
            .and_then(|r| r["mean"].as_f64())
            .unwrap_or_else(|| panic!("no pooled {method} at {len}"))
    };
    let min = |len: u64, ms: &[&str]| ms.iter().map(|m| mean(len, m)).fold(f64::MAX, f64::min);
    let singles = [
        "linear",
        "lagrange2",
        "lagrange5",
        "spline",
        "rigid",
        "pattern",
        "pca",
    ];
    let polynomials = ["linear", "lagrange2", "lagrange5", "spline"];
    for len in [5, 10, 20, 40, 80] {
        let (auto, best) = (mean(len, "auto"), min(len, &singles));
        // No tolerance: auto must not lose to any single method.
        assert!(
            auto <= best,
            "gap {len}: auto {auto:.2} > best single {best:.2}"
        );
        if len >= 20 {
            let (donor, poly) = (min(len, &["pca", "rigid"]), min(len, &polynomials));
            assert!(
                donor < 0.5 * poly,
                "gap {len}: pca/rigid {donor:.2} not well below polynomials {poly:.2}"
            );
        }
    }
}
