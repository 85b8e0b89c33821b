//! Writing output files: every command writes through the library's atomic writer
//! ([`c3dfix::save::write_atomic`]: a temporary file in the target folder, synced, renamed into place, the
//! folder synced), so that an interrupted run never leaves a partial file behind.

use anyhow::Result;
use std::path::Path;

/// Write `bytes` to `path` atomically. Refuses to replace an existing file unless `force`,
/// and never replaces a folder, device or FIFO.
pub fn write_atomic(path: &Path, bytes: &[u8], force: bool) -> Result<()> {
    Ok(c3dfix::save::write_atomic(path, bytes, force)?)
}

/// A path's file name for titles and messages (the whole path when it has none).
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}
