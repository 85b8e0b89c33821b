//! Reruns change nothing (docs/reruns.md): every corpus file repaired with the defaults, and
//! the repaired file repaired again, gives the same bytes; a second run fills no gap the first
//! left, and the record in the file names what the first run did.

use rayon::prelude::*;
use std::path::{Path, PathBuf};

fn corpus() -> Vec<PathBuf> {
    testkit::every_c3d_file()
}

/// Repair `bytes` (read from `path`) as `opts` says; the bytes written and the summary, or
/// `None` when the file cannot be repaired (unreadable, no points).
fn repaired(
    bytes: Vec<u8>,
    path: &Path,
    opts: &c3dfix::RepairOptions,
) -> Option<(Vec<u8>, c3dfix::Summary)> {
    let mut c = c3d::read(bytes).ok()?;
    let done = c3dfix::repair(&mut c, opts, path).ok()?;
    Some((c.encoded().ok()?.into_owned(), done.summary))
}

struct Outcome {
    file: String,
    first_filled: usize,
    /// Swaps exchanged back and jumps made gaps by the first run.
    first_undone: usize,
    /// Samples moved from unlabelled points by the first run.
    first_reclaimed: usize,
    second_filled: usize,
    second_changed: usize,
    same: bool,
}

fn twice(path: &Path, opts: &c3dfix::RepairOptions) -> Option<Outcome> {
    let raw = std::fs::read(path).ok()?;
    let (once, s1) = repaired(raw, path, opts)?;
    let (again, s2) = repaired(once.clone(), path, opts).expect("a repaired file repairs again");
    Some(Outcome {
        file: testkit::short(path),
        first_filled: s1.filled,
        first_undone: s1.swaps_undone + s1.jumps_to_gaps,
        first_reclaimed: s1.reclaimed,
        second_filled: s2.filled,
        second_changed: s2.samples_changed,
        same: once == again,
    })
}

/// Files repaired, gaps filled, swaps and jumps undone and samples reclaimed by the first runs.
fn check_all(opts: &c3dfix::RepairOptions) -> (usize, usize, usize, usize) {
    let files = corpus();
    if files.is_empty() {
        eprintln!("corpora absent (C3D_SAMPLES, C3D_EXTRA, C3D_MORE, C3D_FULLBODY): skipped");
        return (0, 0, 0, 0);
    }
    let done: Vec<Outcome> = files.par_iter().filter_map(|f| twice(f, opts)).collect();
    let bad: Vec<String> = done
        .iter()
        .filter(|o| !o.same || o.second_filled > 0 || o.second_changed > 0)
        .map(|o| {
            format!(
                "{}: identical {}, second run filled {} changed {}",
                o.file, o.same, o.second_filled, o.second_changed
            )
        })
        .collect();
    assert!(
        bad.is_empty(),
        "{} files change on a rerun:\n{}",
        bad.len(),
        bad.join("\n")
    );
    (
        done.len(),
        done.iter().map(|o| o.first_filled).sum(),
        done.iter().map(|o| o.first_undone).sum(),
        done.iter().map(|o| o.first_reclaimed).sum(),
    )
}

#[test]
fn every_corpus_file_repaired_twice_is_the_same_file() {
    let (files, filled, _, _) = check_all(&c3dfix::RepairOptions::default());
    if files > 0 {
        // Every corpus file but the few without points (or unreadable) is repaired.
        assert!(files >= 100, "{files} files repaired");
        assert!(filled > 1000, "{filled} gaps filled by the first runs");
    }
}

/// With label swaps fixed, the first stage: a second run finds no swap the first undid (the
/// file records the stage as done, docs/reruns.md) and writes the same bytes.
#[test]
fn every_corpus_file_repaired_twice_with_swaps_fixed_is_the_same_file() {
    let opts = c3dfix::RepairOptions {
        swaps: c3dfix::SwapsMode::Fix,
        ..c3dfix::RepairOptions::default()
    };
    let (files, _, undone, _) = check_all(&opts);
    if files > 0 {
        assert!(files >= 100, "{files} files repaired");
        // The corpus has label errors of its own (docs/swaps.md lists them).
        assert!(undone > 0, "no swap or jump undone in {files} files");
    }
}

/// With unlabelled samples reclaimed (`--reclaim on`): the file records the stage, a second
/// run moves nothing more and writes the same bytes.
#[test]
fn every_corpus_file_repaired_twice_with_reclaim_on_is_the_same_file() {
    let opts = c3dfix::RepairOptions {
        reclaim: c3dfix::ReclaimMode::On,
        ..c3dfix::RepairOptions::default()
    };
    let (files, _, _, reclaimed) = check_all(&opts);
    if files > 0 {
        assert!(files >= 100, "{files} files repaired");
        // c3d-samples' analogfpscale03 has two unlabelled samples in a marker's gap.
        assert!(reclaimed > 0, "no sample reclaimed in {files} files");
    }
}
