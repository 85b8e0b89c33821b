//! A process forked after the library ran parallel work still reads and repairs: the library's
//! pool belongs to the process that built it, and a child builds its own (see `forkpool`).
//! Without that, the child's first parallel iterator waits forever for the parent's worker
//! threads, which fork did not copy; the parent here gives up after a timeout, so a hang fails
//! the test instead of stalling the run.
#![cfg(unix)]

use std::path::Path;
use std::time::{Duration, Instant};

/// The encoded bytes of `file` repaired with the default options.
fn repaired(file: &Path) -> Vec<u8> {
    let mut c = c3dfix::open(file).unwrap();
    c3dfix::repair(&mut c, &c3dfix::RepairOptions::default(), file).unwrap();
    c.encoded().unwrap().to_vec()
}

#[test]
fn a_forked_child_repairs_after_the_parent_did() {
    let Some(dir) = testkit::c3d_samples() else {
        return;
    };
    // 2.6 MB of point data: above the size at which decoding goes parallel.
    let file = dir.join("sample_00/Codamotion/codamotion_gaitwands_20150204.c3d");
    let want = repaired(&file);
    // SAFETY: the child only runs the library and leaves with _exit, running no destructor
    // or exit handler of the parent's state.
    let pid = unsafe { libc::fork() };
    assert!(pid >= 0, "fork failed");
    if pid == 0 {
        let ok = std::panic::catch_unwind(|| repaired(&file) == want).unwrap_or(false);
        unsafe { libc::_exit(if ok { 0 } else { 3 }) };
    }
    let start = Instant::now();
    let mut status = 0;
    loop {
        let r = unsafe { libc::waitpid(pid, &mut status, libc::WNOHANG) };
        if r == pid {
            break;
        }
        assert_eq!(r, 0, "waitpid failed");
        if start.elapsed() > Duration::from_secs(120) {
            unsafe {
                libc::kill(pid, libc::SIGKILL);
                libc::waitpid(pid, &mut status, 0);
            }
            panic!("the forked child hung repairing {}", file.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "the forked child failed (status {status})"
    );
}
