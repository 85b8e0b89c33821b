//! Where the shared test corpora live.
//!
//! Every crate's tests find the real files through the same rules, so they live here once:
//! `C3D_SAMPLES` (default `../shared/c3d-samples`, relative to the workspace root), and the
//! sibling folders `c3d-extra`, `c3d-fullbody`, `c3d-more`, `c3d-labs` and `bvh-samples` beside it
//! (overridable with `C3D_EXTRA`, `C3D_FULLBODY`, `C3D_MORE`, `C3D_LABS` and `BVH_SAMPLES`). When a corpus is missing, tests skip with a message — unless `CI` is set,
//! in which case a missing corpus is a failure.

use std::path::{Path, PathBuf};

/// The workspace root (two levels above this crate's manifest).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap_or_else(|_| Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
}

fn resolve(var: &str, default: &str) -> PathBuf {
    let raw = std::env::var_os(var)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(default));
    if raw.is_absolute() {
        raw
    } else {
        workspace_root().join(raw)
    }
}

fn required() -> bool {
    std::env::var_os("CI").is_some_and(|v| !v.is_empty() && v != "false" && v != "0")
}

fn corpus(var: &str, default: &str) -> Option<PathBuf> {
    let dir = resolve(var, default);
    if dir.is_dir() {
        Some(dir)
    } else if required() {
        panic!(
            "corpus {} (from {var}) is missing and CI requires it",
            dir.display()
        );
    } else {
        eprintln!(
            "skipping: corpus {} not found (set {var} to run this test)",
            dir.display()
        );
        skipped(&format!("{var}={}", dir.display()));
        None
    }
}

/// Record that the running test skips (some or all of its work) for `reason`.
///
/// The test harness hides what a passing test prints, so a skip would go unseen: with
/// `C3DFIX_SKIP_LOG` set (as `tests/all.sh` sets it), each skip is also appended to that file
/// as `TEST<tab>REASON`, and the script counts the tests that skipped. The harness names
/// each test's thread after the test, which is how the line names it.
pub fn skipped(reason: &str) {
    use std::io::Write as _;
    let Some(log) = std::env::var_os("C3DFIX_SKIP_LOG") else {
        return;
    };
    let test = std::thread::current()
        .name()
        .unwrap_or("(unnamed test)")
        .to_string();
    let line = format!("{test}\t{reason}\n");
    // One write of one short line with O_APPEND: lines from parallel tests do not interleave.
    if let Ok(mut f) = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
    {
        let _ = f.write_all(line.as_bytes());
    }
}

/// The c3d.org sample corpus, or `None` (after saying so) when it is absent outside CI.
pub fn c3d_samples() -> Option<PathBuf> {
    corpus("C3D_SAMPLES", "../shared/c3d-samples")
}

/// The extra C3D files (BTK test data), beside the sample corpus by default.
pub fn c3d_extra() -> Option<PathBuf> {
    let default = resolve("C3D_SAMPLES", "../shared/c3d-samples").join("../c3d-extra");
    corpus("C3D_EXTRA", &default.to_string_lossy())
}

/// The full-body sequences (CMU, numediart), beside the sample corpus by default.
pub fn c3d_fullbody() -> Option<PathBuf> {
    let default = resolve("C3D_SAMPLES", "../shared/c3d-samples").join("../c3d-fullbody");
    corpus("C3D_FULLBODY", &default.to_string_lossy())
}

/// More real trials from ten other sources (walking, running, landing, sports; plates of
/// types 1-4), beside the sample corpus by default: labs nothing was tuned on.
pub fn c3d_more() -> Option<PathBuf> {
    let default = resolve("C3D_SAMPLES", "../shared/c3d-samples").join("../c3d-more");
    corpus("C3D_MORE", &default.to_string_lossy())
}

/// Trials from about a dozen more labs (other marker sets, treadmills, drop jumps, running,
/// lifting, unlabelled points), beside the sample corpus by default: the next lab's trials,
/// on which no constant was chosen before they arrived.
pub fn c3d_labs() -> Option<PathBuf> {
    let default = resolve("C3D_SAMPLES", "../shared/c3d-samples").join("../c3d-labs");
    corpus("C3D_LABS", &default.to_string_lossy())
}

/// One `c3d-labs` trial by its name without `.c3d` (`RehabEngGroup__MOtoNMS__Walking1`), or
/// `None` (said once) when the corpus is absent.
pub fn c3d_labs_trial(name: &str) -> Option<PathBuf> {
    Some(c3d_labs()?.join(format!("{name}.c3d")))
}

/// The BVH corpus, beside the sample corpus by default.
pub fn bvh_samples() -> Option<PathBuf> {
    let default = resolve("C3D_SAMPLES", "../shared/c3d-samples").join("../bvh-samples");
    corpus("BVH_SAMPLES", &default.to_string_lossy())
}

/// Every file below `dir` whose extension matches `ext` (case-insensitive), sorted.
pub fn files_with_ext(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|x| x.to_string_lossy().eq_ignore_ascii_case(ext))
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// All C3D files of the three corpora (empty when the corpora are absent outside CI).
pub fn all_c3d_files() -> Vec<PathBuf> {
    let mut v = Vec::new();
    for d in [c3d_samples(), c3d_extra(), c3d_fullbody()]
        .into_iter()
        .flatten()
    {
        v.extend(files_with_ext(&d, "c3d"));
    }
    v
}

/// Every C3D file of the four C3D corpora, `c3d-more` included (the labs nothing was tuned
/// on): what the whole-corpus checks (reruns, round trips) run over.
pub fn every_c3d_file() -> Vec<PathBuf> {
    let mut v = all_c3d_files();
    if let Some(d) = c3d_more() {
        v.extend(files_with_ext(&d, "c3d"));
    }
    v
}

/// A path relative to the corpus, for readable test output.
pub fn short(p: &Path) -> String {
    let s = p.to_string_lossy();
    match s
        .find("c3d-samples/")
        .or_else(|| s.find("c3d-extra/"))
        .or_else(|| s.find("c3d-fullbody/"))
    {
        Some(i) => s[i..].to_string(),
        None => s.into_owned(),
    }
}

/// Run `check` on every input kept in a fuzz-regression folder (the workspace-relative
/// `dir`; its README is skipped); the number of inputs replayed.
pub fn replay_regressions(dir: &str, mut check: impl FnMut(&[u8])) -> usize {
    let dir = workspace_root().join(dir);
    let mut n = 0;
    for e in std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("regression folder {}: {e}", dir.display()))
        .flatten()
    {
        if e.path().extension().is_some_and(|x| x == "md") {
            continue;
        }
        let data = std::fs::read(e.path()).expect("read regression file");
        check(&data);
        n += 1;
    }
    eprintln!("{n} regression inputs replayed from {}", dir.display());
    n
}
