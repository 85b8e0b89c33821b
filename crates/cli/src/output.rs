//! Writing output files: every command writes through the library's atomic writer
//! ([`c3dfix::save`]): every destination of a run checked before the first byte is written,
//! temporary files synced and renamed together, folders synced.

pub use c3dfix::save::{
    backup_path, check_destination, new_backup, refuse_input, replacing, same_file, write_all,
    Content, Output, NAME_MAX,
};
use std::path::Path;

/// Write `bytes` to `path` atomically. Refuses to replace an existing file unless `force`,
/// and never replaces a folder, device or FIFO.
pub fn write_atomic(path: &Path, bytes: &[u8], force: bool) -> anyhow::Result<()> {
    Ok(c3dfix::save::write_atomic(path, bytes, force)?)
}

/// A path's file name for titles and messages (the whole path when it has none).
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}
