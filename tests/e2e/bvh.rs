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

/// The shared walk with its first motion value (the root's Xposition in frame 0) replaced.
fn walk_with_first_value(dir: &Path, value: &str) -> Option<std::path::PathBuf> {
    let samples = testkit::bvh_samples()?;
    let text = std::fs::read_to_string(samples.join("bvhtoolbox_walk01.bvh")).expect("read");
    let motion = text.find("Frame Time:").expect("MOTION header");
    let line_end = motion + text[motion..].find('\n').expect("line end") + 1;
    let rest = &text[line_end..];
    let first = rest.find(|c: char| !c.is_whitespace()).expect("a value");
    let len = rest[first..].find(char::is_whitespace).expect("value end");
    let edited = format!(
        "{}{}{}{}",
        &text[..line_end],
        &rest[..first],
        value,
        &rest[first + len..]
    );
    let path = dir.join("walk.bvh");
    std::fs::write(&path, edited).expect("write");
    Some(path)
}

/// Run the binary, failing the test (not hanging it) if it takes more than a minute.
fn run_with_deadline(cmd: &mut std::process::Command) -> std::process::Output {
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run c3dfix");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while child.try_wait().expect("wait").is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("c3dfix did not finish within a minute");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

/// A motion value no capture has (1e200, whose square overflows) used to make the error curve
/// NaN and the plot never finish: now every keyframes run stops at once with an error naming
/// the frame, joint and channel, and writes nothing.
#[test]
fn keyframes_absurd_motion_value_is_a_clear_error_and_never_hangs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let Some(input) = walk_with_first_value(dir.path(), "1e200") else {
        return;
    };
    for extra in [
        &["--plot", "c.svg"][..],
        &["--json"],
        &["--method", "optimal", "-o", "out.bvh"],
    ] {
        let o = run_with_deadline(
            c3dfix()
                .current_dir(dir.path())
                .arg("keyframes")
                .arg(&input)
                .args(["--keys", "10"])
                .args(extra),
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert!(o.stdout.is_empty(), "{extra:?}");
        for part in ["walk.bvh", "MOTION frame 0", "`Hips`", "Xposition", "1e200"] {
            assert!(err.contains(part), "{extra:?}: {part} missing from {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!dir.path().join("c.svg").exists());
    assert!(!dir.path().join("out.bvh").exists());
    // Non-finite values are refused by the reader already, with their line.
    let input = walk_with_first_value(dir.path(), "nan").expect("corpus");
    let o = run_with_deadline(c3dfix().arg("keyframes").arg(&input).args(["--keys", "10"]));
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a finite number"));
}

/// Every numeric option has a documented range, and values outside it (however large) are
/// refused with a message naming the range, never an overflow.
#[test]
fn keyframes_numeric_options_out_of_range_are_clear_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    synthetic(dir.path());
    let cases: [(&[&str], &str); 7] = [
        (
            &[
                "--keys",
                "3",
                "--method",
                "optimal",
                "--max-segment",
                "18446744073709551615",
            ],
            "from 0 to 4294967295",
        ),
        (&["--max-error", "1e300"], "from 0 to 1e9"),
        (&["--max-error=-1"], "from 0 to 1e9"),
        (&["--max-error", "nan"], "from 0 to 1e9"),
        (
            &["--keys", "18446744073709551615"],
            "between 2 and the 21 frames",
        ),
        (&["--keys", "1"], "between 2 and the 21 frames"),
        (&["--keys", "99999999999999999999999"], "--keys"),
    ];
    for (args, message) in cases {
        let o = c3dfix()
            .current_dir(dir.path())
            .args(["keyframes", "walk.bvh"])
            .args(args)
            .output()
            .expect("run c3dfix");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // The largest accepted cap is no cap at all.
    let o = c3dfix()
        .current_dir(dir.path())
        .args([
            "keyframes",
            "walk.bvh",
            "--keys",
            "4",
            "--method",
            "optimal",
        ])
        .args(["--max-segment", "4294967295", "--json"])
        .output()
        .expect("run c3dfix");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["keys"], serde_json::json!([0, 5, 12, 20]));
}

/// The report says whether the keys are proven optimal: short motions are searched
/// exhaustively; `--exact` forces it; greedy never claims it.
#[test]
fn keyframes_report_says_whether_the_keys_are_proven_optimal() {
    let dir = tempfile::tempdir().expect("temp dir");
    synthetic(dir.path());
    for (args, proven, step) in [
        (&["--method", "optimal"][..], true, serde_json::json!(1)),
        (
            &["--method", "optimal", "--exact"],
            true,
            serde_json::json!(1),
        ),
        (&["--method", "greedy"], false, serde_json::Value::Null),
    ] {
        let o = c3dfix()
            .current_dir(dir.path())
            .args(["keyframes", "walk.bvh", "--keys", "4", "--json"])
            .args(args)
            .output()
            .expect("run c3dfix");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        assert_eq!(report["proven_optimal"], proven, "{args:?}");
        assert_eq!(report["search_step"], step, "{args:?}");
        let o = c3dfix()
            .current_dir(dir.path())
            .args(["keyframes", "walk.bvh", "--keys", "4"])
            .args(args)
            .output()
            .expect("run c3dfix");
        let text = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            text.contains("proven optimal (exhaustive search)"),
            proven,
            "{text}"
        );
    }
}
