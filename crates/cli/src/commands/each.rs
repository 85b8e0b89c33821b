//! One job per trial for the commands that annotate trials (`events`, `gait`): folders are
//! walked as `batch` walks them, the trials are done in parallel on `--jobs` threads, and
//! the results come back in the order the trials were named, so what is printed does not
//! depend on which thread finished first. Each file is written atomically (the library's
//! `save`), so a run that is killed leaves every trial either as it was or complete.

use anyhow::Result;
use c3dfix::targets::{plan, Destination};
use std::path::{Path, PathBuf};

/// The trials named: files as given, each folder replaced by the C3D files below it
/// (sorted, each once, symbolic links not followed).
pub fn trials(named: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in named {
        if p.is_dir() {
            let found = plan(std::slice::from_ref(p), Destination::InPlace, None)?;
            if found.targets.is_empty() {
                anyhow::bail!("{}: no C3D files in this folder", p.display());
            }
            out.extend(found.targets.into_iter().map(|t| t.input));
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// `work` on every trial, on `jobs` threads (None: one per core), results in the trials'
/// order.
pub fn each<T, W>(files: &[PathBuf], jobs: Option<c3dfix::Jobs>, work: W) -> Result<Vec<Result<T>>>
where
    T: Send,
    W: Fn(&Path) -> Result<T> + Sync,
{
    Ok(jobs.unwrap_or_default().each(files, |f| work(f))?)
}
