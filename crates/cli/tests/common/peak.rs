//! The peak memory of a command, for the memory test and the commands bench.

use std::process::{Command, Stdio};

/// Peak resident memory (bytes) of `cmd` run to its end with its output discarded; `None`
/// when it fails or where it cannot be measured (outside Linux).
// The child is reaped by wait4 (which also gives its peak memory), not by `Child::wait`.
#[allow(clippy::zombie_processes)]
#[cfg(target_os = "linux")]
pub fn peak_memory(cmd: &mut Command) -> Option<u64> {
    use std::os::unix::process::CommandExt;
    // A hook before exec makes the standard library fork a copy of this process instead of
    // starting the child in this process's memory: the kernel would count that memory's peak
    // as the child's.
    // SAFETY: the hook does nothing, so it cannot break the forked child.
    unsafe {
        cmd.pre_exec(|| Ok(()));
    }
    let child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .ok()?;
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value to be filled in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is our own child, not yet waited for; both pointers are to live locals.
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    (r == pid && libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0)
        .then_some(usage.ru_maxrss as u64 * 1024)
}

#[cfg(not(target_os = "linux"))]
pub fn peak_memory(_: &mut Command) -> Option<u64> {
    None
}
