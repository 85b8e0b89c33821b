//! The library gives what the command gives: the `repair_file` example (crates/c3dfix),
//! compiled into this test, writes byte for byte what `c3dfix repair` writes with the same
//! options.

use super::{c3dfix, s, sample, stderr};

mod example {
    include!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../c3dfix/examples/repair_file.rs"
    ));
}

#[test]
fn the_library_example_writes_what_the_command_writes() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = vec![sample("walk_int.c3d"), sample("walk_float.c3d")];
    if let Some(full) = testkit::c3d_fullbody() {
        files.push(full.join("03_rolling.c3d"));
    }
    if let Some(samples) = testkit::c3d_samples() {
        files.push(samples.join("sample_09/PlugInC3D.c3d"));
    }
    for f in &files {
        let (a, b) = (dir.path().join("lib.c3d"), dir.path().join("cli.c3d"));
        let summary = example::repair_and_save(f, &a).unwrap();
        let o = c3dfix(&[
            "repair",
            s(f),
            "-o",
            s(&b),
            "--spikes",
            "hampel",
            "--lowpass",
            "butterworth:4:6",
            "--force",
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
            "{}: library and command outputs differ",
            f.display()
        );
        let cli: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(cli["filled"], summary.filled);
        assert_eq!(cli["samples_changed"], summary.samples_changed);
        assert!(summary.samples_changed > 0, "{}", f.display());
    }
}
