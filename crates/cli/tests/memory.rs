//! Peak memory of the commands on a long trial (100 000 frames × 100 markers, about 162 MB):
//! a trial is held once. `info`, `gaps` and a byte-identical `convert` need at most 1.2× the
//! file, `repair --fill auto` at most 3× (the trial's trajectories in double precision are
//! 1.5× the file by themselves).
//!
//! Its own test binary, so that no other test runs beside it: the peak of a child includes
//! whatever this process held when it forked.

#[cfg(target_os = "linux")]
#[path = "../../c3d/examples/common/big_trial.rs"]
mod big_trial;

#[cfg(target_os = "linux")]
#[path = "common/peak.rs"]
mod peak;

/// Peak resident memory (bytes) of `c3dfix ARGS`, run to its end.
#[cfg(target_os = "linux")]
fn peak(args: &[&str]) -> u64 {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_c3dfix"));
    cmd.args(args);
    peak::peak_memory(&mut cmd).unwrap_or_else(|| panic!("c3dfix {args:?} failed"))
}

#[cfg(target_os = "linux")]
#[test]
fn a_long_trial_is_held_once() {
    let d = tempfile::tempdir().expect("temporary folder");
    let file = d.path().join("long.c3d");
    let out = d.path().join("out.c3d");
    let bytes = big_trial::big_trial().expect("generate the long trial");
    std::fs::write(&file, &bytes).expect("write the long trial");
    let size = bytes.len() as f64;
    drop(bytes);
    let (f, o) = (
        file.to_str().expect("utf-8 path"),
        out.to_str().expect("utf-8 path"),
    );
    let runs: [(&str, &[&str], f64); 5] = [
        ("info", &["info", "--json", f], 1.2),
        ("gaps", &["gaps", f], 1.2),
        ("convert", &["convert", "--force", "-o", o, f], 1.2),
        (
            "convert to DEC",
            &["convert", "--processor", "dec", "--force", "-o", o, f],
            2.2,
        ),
        (
            "repair",
            &["repair", "--fill", "auto", "--force", "-o", o, f],
            3.0,
        ),
    ];
    let mut report = Vec::new();
    for (name, args, limit) in runs {
        let ratio = peak(args) as f64 / size;
        report.push(format!("{name} {ratio:.2}× (limit {limit}×)"));
        assert!(ratio <= limit, "{report:?}");
        if name == "convert" {
            let same = std::fs::read(&out).ok() == std::fs::read(&file).ok();
            assert!(same, "convert without changes is byte-identical");
        }
    }
    println!("peak memory / file size: {report:?}");
}

#[cfg(not(target_os = "linux"))]
#[test]
fn a_long_trial_is_held_once() {
    eprintln!("skipped: peak memory is measured on Linux only");
}
