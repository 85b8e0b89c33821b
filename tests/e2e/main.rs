//! End-to-end tests of the `c3dfix` binary, run in temporary folders.

mod bvh;

use std::process::Command;

fn c3dfix() -> Command {
    Command::new(env!("CARGO_BIN_EXE_c3dfix"))
}

#[test]
fn help_lists_commands() {
    let out = c3dfix().arg("--help").output().expect("run c3dfix");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("info"), "{text}");
}
