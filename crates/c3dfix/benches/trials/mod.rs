//! The walking trials the gait benches (`events`, `gait_params`) time, read once: the
//! repository's synthetic walk (400 frames, no plates), so a bench runs where no corpus is
//! around, then the named corpus trials that are present and readable. Kept in one place so
//! both benches load their trials the same way and a trial missing from a corpus is skipped
//! alike.

use std::path::PathBuf;

/// A trial read once, with the name its bench rows carry.
pub struct Trial {
    /// The file name.
    pub name: String,
    pub path: PathBuf,
    pub c3d: c3d::C3d,
}

/// The synthetic walk, then `samples` (paths under c3d-samples) and `more` (file names in
/// c3d-more), each where its corpus is present and it reads.
pub fn load(samples: &[&str], more: &[&str]) -> Vec<Trial> {
    let mut paths = vec![testkit::workspace_root().join("sample_c3d/walk_truth.c3d")];
    for (root, names) in [
        (testkit::c3d_samples(), samples),
        (testkit::c3d_more(), more),
    ] {
        if let Some(root) = root {
            paths.extend(names.iter().map(|n| root.join(n)));
        }
    }
    paths
        .into_iter()
        .filter_map(|path| {
            let c3d = c3dfix::open(&path).ok()?;
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().to_string())
                .unwrap_or_default();
            Some(Trial { name, path, c3d })
        })
        .collect()
}
