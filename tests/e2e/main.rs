//! End-to-end tests of the `c3dfix` binary, run in temporary folders.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod auto_eval;
mod bvh;
mod convert;
mod cycles;
mod events;
mod forces;
mod frames;
mod gait;
mod hostile;
mod library;
mod reclaim;
mod repair;
mod report;
mod reruns;
mod seen;
mod swaps;
mod upright;
mod validity;
mod view;

/// The binary under test: this build's, or `C3DFIX_E2E_BIN` (to run the tests against
/// another build, e.g. to see a regression test fail on the code before its fix).
fn bin() -> PathBuf {
    std::env::var_os("C3DFIX_E2E_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_c3dfix")))
}

fn c3dfix(args: &[&str]) -> Output {
    Command::new(bin()).args(args).output().expect("run c3dfix")
}

/// Start the binary with `args` (output discarded), kill it after `delay_ms` and wait for it:
/// how the interruption tests stop a run at a random moment.
fn killed_after<S: AsRef<std::ffi::OsStr>>(args: impl IntoIterator<Item = S>, delay_ms: u64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_c3dfix"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(delay_ms));
    let _ = child.kill();
    let _ = child.wait();
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn sample(name: &str) -> PathBuf {
    testkit::workspace_root().join("sample_c3d").join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

#[test]
fn help_lists_commands() {
    let out = c3dfix(&["--help"]);
    assert!(out.status.success());
    let text = stdout(&out);
    for cmd in ["info", "convert", "diff", "export"] {
        assert!(text.contains(cmd), "{text}");
    }
}

#[test]
fn info_describes_the_sample() {
    let out = c3dfix(&["info", s(&sample("walk_int.c3d"))]);
    assert!(out.status.success(), "{}", stderr(&out));
    let t = stdout(&out);
    assert!(t.contains("Intel processor, integer data"), "{t}");
    assert!(t.contains("400 (first 1), 100 Hz"), "{t}");
    assert!(t.contains("8 with gaps out of 35"), "{t}");
    let out = c3dfix(&["info", "--json", s(&sample("walk_int.c3d"))]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["frames"], 400);
    assert_eq!(v["analog_channels"], 4);
    let rkne = v["markers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["label"] == "RKNE")
        .unwrap();
    assert_eq!(rkne["longest_gap"], 60);
    assert_eq!(rkne["valid_frames"], 340);
    assert_eq!(v["events"].as_array().unwrap().len(), 7);
}

/// `info` counts markers as `gaps` does (model outputs apart) and lists events in time order,
/// on a Plug-in Gait trial with 238 model outputs (84 listed by type, 154 bones, virtual
/// points and muscle lengths stored after them) and a Nexus trial whose events the file
/// stores side by side.
#[test]
fn info_counts_markers_as_gaps_does_and_orders_events_in_time() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let f = more.join("HansUniVie__MuscleLength__test.c3d");
    let t = stdout(&c3dfix(&["info", s(&f)]));
    assert!(
        t.contains("7 with gaps out of 26 (238 model outputs apart)"),
        "{t}"
    );
    let g = stdout(&c3dfix(&["gaps", s(&f)]));
    assert!(g.contains("7 gaps in 26 markers"), "{g}");
    let v: serde_json::Value =
        serde_json::from_slice(&c3dfix(&["info", "--json", s(&f)]).stdout).unwrap();
    let outputs = v["markers"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["model_output"] == true)
        .count();
    assert_eq!(outputs, 238);

    let Some(samples) = testkit::c3d_samples() else {
        return;
    };
    let f = samples.join("sample_11/2198928.c3d");
    let v: serde_json::Value =
        serde_json::from_slice(&c3dfix(&["info", "--json", s(&f)]).stdout).unwrap();
    let times: Vec<f64> = v["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["time"].as_f64().unwrap())
        .collect();
    assert_eq!(times.len(), 8);
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    assert!((times[0] - 0.288).abs() < 0.001, "{times:?}");
}

#[test]
fn bad_files_get_a_clear_error_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(sample("walk_int.c3d")).unwrap();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty.c3d", Vec::new(), "512-byte header"),
        (
            "truncated.c3d",
            good[..good.len() / 2].to_vec(),
            "truncated",
        ),
        ("header_only.c3d", good[..700].to_vec(), "truncated"),
        (
            "random.c3d",
            (0..4096u32)
                .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
                .collect(),
            "not a C3D file",
        ),
    ];
    for (name, bytes, expect) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, &bytes).unwrap();
        let out = c3dfix(&["info", s(&p)]);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", stderr(&out));
        let e = stderr(&out);
        assert!(e.contains(name) && e.contains(expect), "{name}: {e}");
        // Each part of the message is said once (the file's name, then what is wrong).
        let parts: Vec<&str> = e.trim().split(": ").collect();
        let mut unique = parts.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), parts.len(), "said once: {e}");
        assert!(!e.contains("panicked"), "{e}");
        // Nothing is written on error.
        let o = dir.path().join(format!("{name}.out.c3d"));
        let out = c3dfix(&["convert", s(&p), "-o", s(&o)]);
        assert_eq!(out.status.code(), Some(2));
        assert!(!o.exists());
    }
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains("c3dfix-tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn convert_without_options_is_byte_identical_and_diff_agrees_for_every_corpus_file() {
    let files = testkit::all_c3d_files();
    let dir = tempfile::tempdir().unwrap();
    let mut done = 0;
    for f in files.iter().chain([sample("walk_int.c3d")].iter()) {
        let bytes = std::fs::read(f).unwrap();
        if bytes.is_empty() {
            continue; // the empty file: refused, tested above
        }
        let o = dir.path().join(format!("out{done}.c3d"));
        let out = c3dfix(&["convert", s(f), "-o", s(&o)]);
        assert!(out.status.success(), "{}: {}", f.display(), stderr(&out));
        assert!(
            std::fs::read(&o).unwrap() == bytes,
            "{}: rewrite differs",
            f.display()
        );
        let out = c3dfix(&["diff", s(f), s(&o)]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {}",
            f.display(),
            stdout(&out)
        );
        assert_eq!(stdout(&out).trim(), "no differences");
        done += 1;
    }
    assert!(done >= 1);
}

#[test]
fn convert_refuses_to_overwrite_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o.c3d");
    std::fs::write(&o, b"keep me").unwrap();
    let out = c3dfix(&["convert", s(&sample("walk_int.c3d")), "-o", s(&o)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--force"));
    assert_eq!(std::fs::read(&o).unwrap(), b"keep me");
    let out = c3dfix(&[
        "convert",
        s(&sample("walk_int.c3d")),
        "-o",
        s(&o),
        "--force",
    ]);
    assert!(out.status.success());
    assert_eq!(
        std::fs::read(&o).unwrap(),
        std::fs::read(sample("walk_int.c3d")).unwrap()
    );
}

#[test]
fn convert_to_dec_float_and_back_keeps_values() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("dec.c3d");
    let b = dir.path().join("back.c3d");
    let src = sample("walk_int.c3d");
    let out = c3dfix(&[
        "convert",
        s(&src),
        "-o",
        s(&a),
        "--processor",
        "dec",
        "--format",
        "float",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = c3dfix(&[
        "convert",
        s(&a),
        "-o",
        s(&b),
        "--processor",
        "intel",
        "--format",
        "int",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = c3dfix(&["diff", "--json", s(&src), s(&a)]);
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        v["diff"]["points"]["markers"].as_array().unwrap().len(),
        0,
        "{v}"
    );
    assert_eq!(v["diff"]["format"].as_array().unwrap().len(), 2);
    let out = c3dfix(&["diff", s(&src), s(&b)]);
    let t = stdout(&out);
    // Back in the original format: only the data start may move (the section was rebuilt).
    assert!(!t.contains("points") && !t.contains("analog"), "{t}");
}

#[test]
fn diff_reports_changed_markers() {
    let out = c3dfix(&[
        "diff",
        "--json",
        "--tolerance",
        "0.5",
        s(&sample("walk_truth.c3d")),
        s(&sample("walk_float.c3d")),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let markers = v["diff"]["points"]["markers"].as_array().unwrap();
    let rkne = markers.iter().find(|m| m["label"] == "RKNE").unwrap();
    assert_eq!(rkne["became_invalid"], 60);
    let strn = markers.iter().find(|m| m["label"] == "STRN").unwrap();
    let d = strn["max_displacement"].as_f64().unwrap();
    assert!((48.0..52.0).contains(&d), "{d}");
}

#[test]
fn export_csv_trc_json() {
    let dir = tempfile::tempdir().unwrap();
    let src = sample("walk_int.c3d");
    let csv = dir.path().join("w.csv");
    let out = c3dfix(&["export", s(&src), "--format", "csv", "-o", s(&csv)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("Frame,Time,LASI_X,LASI_Y,LASI_Z,RASI_X"));
    assert_eq!(text.lines().count(), 401);
    let analog = std::fs::read_to_string(dir.path().join("w.analog.csv")).unwrap();
    assert!(analog.starts_with("Sample,Time,EMG_LTA (V)"));
    assert_eq!(analog.lines().count(), 4001);
    // RKNE is missing in frames 331–390: empty cells there.
    let rkne_col = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == "RKNE_X")
        .unwrap();
    let row = text.lines().nth(331).unwrap();
    assert_eq!(row.split(',').nth(rkne_col), Some(""));

    let out = c3dfix(&["export", s(&src), "--format", "trc"]);
    let t = stdout(&out);
    assert!(t.starts_with("PathFileType\t4\t(X/Y/Z)\twalk_int.c3d"));
    assert!(t
        .lines()
        .nth(2)
        .unwrap()
        .starts_with("100\t100\t400\t35\tmm"));

    let out = c3dfix(&["export", s(&src), "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["markers"].as_array().unwrap().len(), 35);
    assert_eq!(v["analog"]["channels"].as_array().unwrap().len(), 4);
    assert_eq!(v["markers"][11]["label"], "RKNE");
    assert!(v["markers"][11]["xyz"][335].is_null()); // in its gap
    assert!(v["markers"][11]["xyz"][329].is_array());
}
