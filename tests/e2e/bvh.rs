//! `c3dfix keyframes` end to end, in temporary folders.

use std::path::Path;

/// The binary, for tests that build their own argument lists.
fn c3dfix() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_c3dfix"))
}

/// Root x position piecewise linear with breakpoints at frames 5 and 12 (of 21).
fn synthetic(dir: &Path) -> std::path::PathBuf {
    let mut text = String::from(
        "HIERARCHY\nROOT root\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n End Site\n {\n  OFFSET 0 5 0\n }\n}\nMOTION\nFrames: 21\nFrame Time: 0.1\n",
    );
    for f in 0..21 {
        let t = f as f64;
        let x = if f <= 5 {
            t
        } else if f <= 12 {
            5.0 - 2.0 * (t - 5.0)
        } else {
            -9.0 + 0.5 * (t - 12.0)
        };
        text.push_str(&format!("{x} 0 0 0 0 0\n"));
    }
    let path = dir.join("walk.bvh");
    std::fs::write(&path, text).expect("write synthetic file");
    path
}

#[test]
fn keyframes_finds_breakpoints_and_writes_a_parsable_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = synthetic(dir.path());
    let out = dir.path().join("out.bvh");
    for method in ["greedy", "optimal"] {
        let o = c3dfix()
            .current_dir(dir.path())
            .args(["keyframes", "walk.bvh", "--keys", "4", "--json", "--force"])
            .args(["--method", method, "-o", "out.bvh"])
            .output()
            .expect("run c3dfix");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON report");
        assert_eq!(
            report["keys"],
            serde_json::json!([0, 5, 12, 20]),
            "{method}"
        );
        assert!(report["total_error"].as_f64().expect("number") < 1e-12);
        assert_eq!(report["frame_errors"].as_array().expect("array").len(), 21);
        // Removing 0..=19 frames; flat at zero until a breakpoint has to go (17 removed).
        let curve = report["greedy_curve"].as_array().expect("curve");
        assert_eq!(curve.len(), 20);
        assert!(curve[17][1].as_f64().expect("error") < 1e-12);
        assert!(curve[18][1].as_f64().expect("error") > 1e-3);
        let written = ::bvh::read(&out).expect("output parses");
        let original = ::bvh::read(&input).expect("input parses");
        assert_eq!(written.motion.frames(), 21);
        for (a, b) in written.motion.values.iter().zip(&original.motion.values) {
            assert!((a - b).abs() < 1e-9);
        }
    }
}

#[test]
fn keyframes_does_not_overwrite_without_force() {
    let dir = tempfile::tempdir().expect("temp dir");
    synthetic(dir.path());
    let out = dir.path().join("out.bvh");
    std::fs::write(&out, "keep me").expect("write");
    let o = c3dfix()
        .current_dir(dir.path())
        .args(["keyframes", "walk.bvh", "--keys", "3", "-o", "out.bvh"])
        .output()
        .expect("run c3dfix");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--force"));
    assert_eq!(std::fs::read_to_string(&out).expect("read"), "keep me");
    let o = c3dfix()
        .current_dir(dir.path())
        .args([
            "keyframes",
            "walk.bvh",
            "--keys",
            "3",
            "-o",
            "out.bvh",
            "--force",
        ])
        .output()
        .expect("run c3dfix");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(::bvh::read(&out).expect("parses").motion.frames(), 21);
}

#[test]
fn keyframes_real_file_key_count_error_bound_and_plot() {
    let Some(samples) = testkit::bvh_samples() else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let input = samples.join("bvhtoolbox_walk01.bvh");
    let o = c3dfix()
        .current_dir(dir.path())
        .arg("keyframes")
        .arg(&input)
        .args(["--keys", "20", "--interp", "euler", "--json", "-o", "k.bvh"])
        .args(["--plot", "curve.svg"])
        .output()
        .expect("run c3dfix");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["keys"].as_array().expect("keys").len(), 20);
    let written = ::bvh::read(&dir.path().join("k.bvh")).expect("output parses");
    assert_eq!(written.motion.frames(), 101);
    let svg = std::fs::read_to_string(dir.path().join("curve.svg")).expect("svg");
    assert!(svg.starts_with("<svg") && svg.contains("euler") && svg.contains("quat"));
    // One curve per panel: Euler in red, quaternion in blue.
    for colour in ["#FF0000", "#0000FF"] {
        let curves = svg
            .split("<polyline")
            .filter(|p| p.split('>').next().is_some_and(|tag| tag.contains(colour)))
            .count();
        assert_eq!(curves, 1, "{colour}");
    }

    // An error bound: the reported RMS distance respects it.
    let o = c3dfix()
        .arg("keyframes")
        .arg(&input)
        .args(["--max-error", "2.0", "--method", "optimal", "--json"])
        .output()
        .expect("run c3dfix");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert!(report["rms_distance"].as_f64().expect("rms") <= 2.0);
    let keys = report["keys"].as_array().expect("keys").len();
    assert!(keys > 2 && keys < 101, "{keys}");
}

#[test]
fn keyframes_bad_input_names_the_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("bad.bvh"),
        "HIERARCHY\nROOT r\n{\nOFFSET 0 0\n}\n",
    )
    .expect("write");
    let o = c3dfix()
        .current_dir(dir.path())
        .args(["keyframes", "bad.bvh", "--keys", "3"])
        .output()
        .expect("run c3dfix");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("line 5"), "{err}");
}
