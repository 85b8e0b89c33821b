//! Writing output files safely: a temporary file in the target folder, synced, then renamed
//! into place, so that an interrupted run never leaves a partial file behind.

use anyhow::{bail, Context, Result};
use std::io::Write;
use std::path::Path;

/// Write `bytes` to `path` atomically. Refuses to replace an existing file unless `force`.
pub fn write_atomic(path: &Path, bytes: &[u8], force: bool) -> Result<()> {
    if !force && path.exists() {
        bail!("{} exists (use --force to overwrite)", path.display());
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "cannot write {}: the folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file path", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.c3dfix-tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> Result<()> {
        let mut f = std::fs::File::create(&tmp)
            .with_context(|| format!("cannot create {}", tmp.display()))?;
        f.write_all(bytes)
            .with_context(|| format!("cannot write {}", tmp.display()))?;
        f.sync_all()
            .with_context(|| format!("cannot sync {}", tmp.display()))?;
        std::fs::rename(&tmp, path)
            .with_context(|| format!("cannot rename {} to {}", tmp.display(), path.display()))?;
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Where `--backup` keeps the original: `FILE.bak` beside it.
pub fn backup_path(original: &Path) -> std::path::PathBuf {
    let mut name = original.file_name().unwrap_or_default().to_os_string();
    name.push(".bak");
    original.with_file_name(name)
}

/// Copy `original` to `backup` atomically, unless a backup already exists: the first backup
/// is the true original, and a second in-place repair must not replace it with a repaired
/// file. Returns whether a backup was written.
pub fn write_backup(original: &Path, backup: &Path) -> Result<bool> {
    if backup.exists() {
        return Ok(false);
    }
    let bytes = std::fs::read(original)
        .with_context(|| format!("cannot read {} for its backup", original.display()))?;
    write_atomic(backup, &bytes, false)?;
    Ok(true)
}

/// A path's file name for titles and messages (the whole path when it has none).
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}
