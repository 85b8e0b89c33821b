//! Hostile inputs, arguments and surroundings: nothing lost, nothing partial, no panic.
//! Each test is named after what went wrong before.

use super::{c3dfix, s, sample, stderr, stdout};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// `sample_02/pc_real.c3d` of the shared corpus (`None` after saying so when it is absent).
fn pc_real() -> Option<PathBuf> {
    testkit::c3d_samples().map(|d| d.join("sample_02").join("pc_real.c3d"))
}

/// A copy of `src` in `dir` with the bytes at `edits` (offset, value) replaced.
fn damaged(src: &Path, dir: &Path, name: &str, edits: &[(usize, u8)]) -> PathBuf {
    let mut b = std::fs::read(src).unwrap();
    for &(at, v) in edits {
        b[at] = v;
    }
    let p = dir.join(name);
    std::fs::write(&p, b).unwrap();
    p
}

/// The run failed cleanly: exit 2, a message, no panic.
fn refused(out: &Output, expect: &str) {
    let e = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{e}");
    assert!(e.contains(expect), "expected {expect:?} in: {e}");
    assert!(!e.contains("panicked"), "{e}");
}

/// Names in `dir`, sorted (to see that nothing was left behind).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Run c3dfix with its standard output on `/dev/full`.
fn to_dev_full(args: &[&str]) -> Output {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    Command::new(super::bin())
        .args(args)
        .stdout(full)
        .stderr(Stdio::piped())
        .output()
        .unwrap()
}

#[test]
fn report_onto_the_input_or_an_existing_file_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let input = d.path().join("in.c3d");
    std::fs::copy(sample("walk_int.c3d"), &input).unwrap();
    let original = std::fs::read(&input).unwrap();
    let out = d.path().join("out.c3d");
    refused(
        &c3dfix(&["repair", s(&input), "-o", s(&out), "--report", s(&input)]),
        "is the input file",
    );
    // Not even with --force, nor in place.
    refused(
        &c3dfix(&[
            "repair",
            s(&input),
            "-o",
            s(&out),
            "--report",
            s(&input),
            "--force",
        ]),
        "is the input file",
    );
    refused(
        &c3dfix(&["repair", s(&input), "--in-place", "--report", s(&input)]),
        "is the input file",
    );
    refused(
        &c3dfix(&["repair", s(&input), "-o", s(&out), "--report", s(&out)]),
        "",
    );
    assert!(std::fs::read(&input).unwrap() == original);
    assert_eq!(names(d.path()), ["in.c3d"]);
    // An existing report is replaced only with --force.
    let report = d.path().join("r.json");
    std::fs::write(&report, "keep").unwrap();
    refused(
        &c3dfix(&["repair", s(&input), "-o", s(&out), "--report", s(&report)]),
        "use --force",
    );
    assert_eq!(std::fs::read_to_string(&report).unwrap(), "keep");
    assert!(!out.exists());
    let o = c3dfix(&[
        "repair",
        s(&input),
        "-o",
        s(&out),
        "--report",
        s(&report),
        "--force",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(v["file"], s(&input));
}

#[test]
fn force_never_replaces_a_fifo_or_a_device() {
    let d = tempfile::tempdir().unwrap();
    let fifo = d.path().join("fifo");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    // A link to /dev/null: were it replaced, only the link would go, not the device.
    let dev = d.path().join("null");
    std::os::unix::fs::symlink("/dev/null", &dev).unwrap();
    let input = sample("walk_int.c3d");
    for target in [&fifo, &dev] {
        for args in [
            vec!["repair", s(&input), "-o", s(target), "--force"],
            vec!["convert", s(&input), "-o", s(target), "--force"],
            vec![
                "export",
                s(&input),
                "--format",
                "json",
                "-o",
                s(target),
                "--force",
            ],
        ] {
            let out = c3dfix(&args);
            refused(&out, "not a regular file");
        }
    }
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert!(std::fs::symlink_metadata(&dev).unwrap().is_symlink());
    assert_eq!(names(d.path()), ["fifo", "null"]);
}

#[test]
fn repair_of_a_header_with_a_data_start_inside_it_keeps_the_file_readable() {
    let Some(src) = pc_real() else { return };
    let d = tempfile::tempdir().unwrap();
    // Byte 16 is the header's data-start block: 0x0d (13) becomes 1, the header itself.
    let bad = damaged(&src, d.path(), "bad.c3d", &[(16, 0x01)]);
    let fixed = d.path().join("fixed.c3d");
    let out = c3dfix(&["repair", s(&bad), "-o", s(&fixed)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let info = c3dfix(&["info", "--json", s(&fixed)]);
    assert!(info.status.success(), "{}", stderr(&info));
    let v: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(
        (v["frames"].as_u64(), v["points"].as_u64()),
        (Some(89), Some(36))
    );
    // The same repair as of the undamaged file: only the damaged header word differs.
    let reference = d.path().join("reference.c3d");
    let out = c3dfix(&["repair", s(&src), "-o", s(&reference)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let diff = c3dfix(&["diff", "--json", s(&reference), s(&fixed)]);
    let v: serde_json::Value = serde_json::from_slice(&diff.stdout).unwrap();
    assert_eq!(v["diff"]["points"]["markers"], serde_json::json!([]), "{v}");
    assert_eq!(v["diff"]["parameters"], serde_json::json!([]), "{v}");
    // In place, the user's own file stays readable.
    let out = c3dfix(&["repair", s(&bad), "--in-place"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let info = c3dfix(&["info", s(&bad)]);
    assert!(info.status.success(), "{}", stderr(&info));
}

#[test]
fn convert_refuses_a_scale_that_would_store_every_coordinate_as_zero() {
    let Some(src) = pc_real() else { return };
    let d = tempfile::tempdir().unwrap();
    let o = d.path().join("o.c3d");
    for scale in ["1e30", "1e-9"] {
        let out = c3dfix(&[
            "convert",
            s(&src),
            "-o",
            s(&o),
            "--format",
            "int",
            "--scale",
            scale,
        ]);
        refused(&out, "the scale must be from");
        assert!(!o.exists());
    }
    for scale in ["0", "-2", "nan", "inf", "1e39"] {
        let out = c3dfix(&[
            "convert",
            s(&src),
            "-o",
            s(&o),
            "--format",
            "int",
            &format!("--scale={scale}"),
        ]);
        refused(&out, "--scale");
    }
    let out = c3dfix(&[
        "convert",
        s(&src),
        "-o",
        s(&o),
        "--format",
        "int",
        "--scale",
        "0.5",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    // Rounding to 0.5 moves a point by at most √3 × 0.25 ≈ 0.433, and keeps every gap.
    let out = c3dfix(&["diff", s(&src), s(&o), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let markers = v["diff"]["points"]["markers"].as_array().unwrap();
    assert_eq!(markers.len(), 36);
    for m in markers {
        assert!(m["max_displacement"].as_f64().unwrap() <= 0.433, "{m}");
        assert_eq!(
            (m["became_valid"].as_u64(), m["became_invalid"].as_u64()),
            (Some(0), Some(0))
        );
    }
}

#[test]
fn a_full_standard_output_is_a_clean_error_not_a_panic() {
    let d = tempfile::tempdir().unwrap();
    let input = sample("walk_int.c3d");
    let out_c3d = d.path().join("r.c3d");
    let out_dir = d.path().join("batch");
    let bvh = testkit::bvh_samples().map(|d| d.join("bvhtoolbox_walk01.bvh"));
    let mut runs: Vec<Vec<&str>> = vec![
        vec!["info", s(&input)],
        vec!["info", "--json", s(&input)],
        vec!["gaps", s(&input)],
        vec!["diff", s(&input), s(&input)],
        vec!["export", s(&input), "--format", "csv"],
        vec!["export", s(&input), "--format", "trc"],
        vec!["repair", s(&input), "-o", s(&out_c3d)],
        vec!["batch", s(&input), "--out-dir", s(&out_dir)],
        vec![
            "evaluate",
            s(&input),
            "--gap-lengths",
            "5",
            "--gaps-per-length",
            "2",
            "--methods",
            "linear",
        ],
        vec!["--help"],
    ];
    if let Some(f) = &bvh {
        runs.push(vec!["keyframes", s(f), "--keys", "10"]);
        runs.push(vec!["keyframes", s(f), "--keys", "10", "--json"]);
    }
    for args in runs {
        let out = to_dev_full(&args);
        let e = stderr(&out);
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        assert_ne!(out.status.code(), Some(0), "{args:?}");
        if args[0] != "--help" {
            assert_eq!(out.status.code(), Some(2), "{args:?}: {e}");
            assert!(e.contains("standard output"), "{args:?}: {e}");
        }
    }
    // The files were written before the summary was lost.
    assert!(out_c3d.exists());
    assert!(out_dir.join("walk_int.c3d").exists());
}

#[test]
fn huge_numbers_in_arguments_are_refused_with_their_range() {
    let d = tempfile::tempdir().unwrap();
    let input = sample("walk_int.c3d");
    let o = d.path().join("o.c3d");
    let huge = "18446744073709551615";
    let (spikes, order) = (format!("hampel:{huge}"), format!("butterworth:{huge}:6"));
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["repair", s(&input), "-o", s(&o), "--spikes", &spikes],
            "from 1 to 1000",
        ),
        (
            vec![
                "repair",
                s(&input),
                "-o",
                s(&o),
                "--spikes",
                "hampel:1000000000",
            ],
            "from 1 to 1000",
        ),
        (
            vec!["repair", s(&input), "-o", s(&o), "--spikes", "hampel:5:nan"],
            "nsigma",
        ),
        (
            vec!["repair", s(&input), "-o", s(&o), "--max-gap", "0"],
            "--max-gap",
        ),
        (
            vec!["repair", s(&input), "-o", s(&o), "--spike-min-mm", "nan"],
            "--spike-min-mm",
        ),
        (
            vec!["repair", s(&input), "-o", s(&o), "--lowpass", &order],
            "from 1 to 10",
        ),
        (
            vec![
                "repair",
                s(&input),
                "-o",
                s(&o),
                "--lowpass",
                "cheby2:4:6:1e300",
            ],
            "at most 200",
        ),
        (
            vec!["batch", s(&input), "--out-dir", s(d.path()), "--jobs", huge],
            "--jobs",
        ),
        (
            vec!["evaluate", s(&input), "--gap-lengths", huge],
            "--gap-lengths",
        ),
        (
            vec!["evaluate", s(&input), "--gaps-per-length", huge],
            "--gaps-per-length",
        ),
        (
            vec!["diff", s(&input), s(&input), "--tolerance", "inf"],
            "--tolerance",
        ),
    ];
    for (args, expect) in cases {
        let out = c3dfix(&args);
        refused(&out, expect);
    }
    assert!(!o.exists());
}

#[test]
fn info_refuses_an_endless_stream_that_is_not_c3d() {
    let out = c3dfix(&["info", "/dev/zero"]);
    refused(&out, "not a C3D file");
}

#[test]
fn a_c3d_stream_is_read_only_as_far_as_its_header_announces() {
    // The sample through a pipe, followed by zeros that never end: the reader stops at the
    // end of the announced data.
    let bytes = std::fs::read(sample("walk_int.c3d")).unwrap();
    let mut child = Command::new(super::bin())
        .args(["info", "--json", "/dev/stdin"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        if stdin.write_all(&bytes).is_err() {
            return;
        }
        let zeros = vec![0u8; 1 << 16];
        // Bounded, so a reader that never stops fails the test instead of hanging it.
        for _ in 0..16 * 1024 {
            if stdin.write_all(&zeros).is_err() {
                return;
            }
        }
    });
    let out = child.wait_with_output().unwrap();
    feeder.join().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["frames"], 400);
    assert_eq!(v["analog_channels"], 4);
}

#[test]
fn a_report_that_cannot_be_written_leaves_no_output() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("out.c3d");
    let report = d.path().join("missing").join("dir").join("r.json");
    let o = c3dfix(&[
        "repair",
        s(&sample("walk_int.c3d")),
        "-o",
        s(&out),
        "--report",
        s(&report),
    ]);
    refused(&o, "missing");
    assert!(names(d.path()).is_empty(), "{:?}", names(d.path()));
}

#[test]
fn export_with_a_long_name_writes_both_files_or_neither() {
    let d = tempfile::tempdir().unwrap();
    let input = sample("walk_int.c3d");
    // 230 characters: the analog file's name (237) fits; the temporary names must too.
    let main = d.path().join(format!("{}.csv", "m".repeat(226)));
    let out = c3dfix(&["export", s(&input), "--format", "csv", "-o", s(&main)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let analog = main.with_extension("analog.csv");
    assert!(main.exists() && analog.exists());
    assert_eq!(names(d.path()).len(), 2, "{:?}", names(d.path()));
    // 250 characters: the analog file's name (257) cannot exist, so nothing is written.
    let d = tempfile::tempdir().unwrap();
    let main = d.path().join(format!("{}.csv", "m".repeat(246)));
    let out = c3dfix(&["export", s(&input), "--format", "csv", "-o", s(&main)]);
    refused(&out, "longer than file systems allow");
    assert!(names(d.path()).is_empty(), "{:?}", names(d.path()));
}

/// Fields of RFC 4180 CSV text, row by row.
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut rows = vec![];
    let mut row = vec![];
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => field.push(c),
        }
    }
    rows
}

#[test]
fn csv_and_trc_hold_labels_with_quotes_line_breaks_and_tabs() {
    let Some(src) = pc_real() else { return };
    let d = tempfile::tempdir().unwrap();
    // Bytes 5260 and 5261 lie in a point label of pc_real.c3d.
    for (name, at, byte, ch) in [
        ("quote.c3d", 5260, 0x22u8, '"'),
        ("newline.c3d", 5261, 0x0a, '\n'),
        ("tab.c3d", 5261, 0x09, '\t'),
    ] {
        let f = damaged(&src, d.path(), name, &[(at, byte)]);
        let info = c3dfix(&["info", "--json", s(&f)]);
        let v: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
        let label = v["markers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["label"].as_str().unwrap().to_string())
            .find(|l| l.contains(ch))
            .unwrap_or_else(|| panic!("{name}: no label holds {ch:?}"));

        let csv = d.path().join(format!("{name}.csv"));
        let out = c3dfix(&["export", s(&f), "--format", "csv", "-o", s(&csv)]);
        assert!(out.status.success(), "{}", stderr(&out));
        let rows = parse_csv(&std::fs::read_to_string(&csv).unwrap());
        assert_eq!(rows.len(), 1 + 89, "{name}: a header and one row per frame");
        assert!(
            rows.iter().all(|r| r.len() == rows[0].len()),
            "{name}: ragged CSV"
        );
        assert!(
            rows[0].contains(&format!("{label}_X")),
            "{name}: {:?}",
            rows[0]
        );

        let out = c3dfix(&["export", s(&f), "--format", "trc"]);
        assert!(out.status.success(), "{}", stderr(&out));
        // A quote is an ordinary character in TRC; tabs and line breaks are not.
        let warned = stderr(&out).contains("warning");
        assert_eq!(warned, ch != '"', "{name}: {}", stderr(&out));
        let text = stdout(&out);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines.len(),
            5 + 1 + 89,
            "{name}: 5 header lines, a blank, the frames"
        );
        // Frame# Time, then three columns per marker on the label line.
        assert_eq!(
            lines[3].split('\t').count(),
            2 + 3 * 36,
            "{name}: {:?}",
            lines[3]
        );
        assert!(lines[3].contains(&label.replace(['\t', '\n'], " ")));
    }
}

#[test]
fn io_errors_name_their_path() {
    let d = tempfile::tempdir().unwrap();
    let input = sample("walk_int.c3d");
    let plain = d.path().join("plainfile");
    std::fs::write(&plain, "x").unwrap();
    let sub = plain.join("sub");
    let out = c3dfix(&["batch", s(&input), "--out-dir", s(&sub), "--json"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stdout(&out).contains(s(&sub)), "{}", stdout(&out));
    let out = c3dfix(&["convert", s(&input), "-o", s(&sub.join("x.c3d"))]);
    refused(&out, s(&sub));
    // A folder without write permission (root writes anyway: then there is nothing to test).
    let ro = d.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    if std::fs::write(ro.join("probe"), "x").is_err() {
        let out = c3dfix(&["batch", s(&input), "--out-dir", s(&ro), "--json"]);
        assert_eq!(out.status.code(), Some(1));
        assert!(stdout(&out).contains(s(&ro)), "{}", stdout(&out));
    }
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    let out = c3dfix(&["info", s(&d.path().join("nope.c3d"))]);
    refused(&out, "nope.c3d");
}
