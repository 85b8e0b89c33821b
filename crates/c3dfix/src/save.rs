//! Saving files safely: a temporary file in the target folder, written, synced, renamed into
//! place, then the folder synced, so that a crash or a kill never leaves a partial file and a
//! completed save survives a power loss.

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Temporary names are unique per call (process id and a counter), so that parallel jobs
/// writing into one folder, even to the same target, never share a temporary file.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Longest file name most file systems accept, in bytes.
const NAME_MAX: usize = 255;

fn temp_path(dir: &Path, name: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let suffix = format!(".c3dfix-tmp-{}-{n}", std::process::id());
    // Keep the whole name within NAME_MAX bytes: shorten the target's name (on a character
    // boundary) rather than fail on a long but valid output name.
    let room = NAME_MAX - suffix.len() - 1;
    let mut stem = name;
    while stem.len() > room {
        let mut cut = room.min(stem.len() - 1);
        while !stem.is_char_boundary(cut) {
            cut -= 1;
        }
        stem = &stem[..cut];
    }
    dir.join(format!(".{stem}{suffix}"))
}

/// The folder a path is in (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Check that `path` can be written as a file: its folder exists, and it is not a folder, a
/// device or a FIFO; an existing file is refused unless `force`. Checking every destination
/// of a run first keeps a run from writing one output and then failing on the next.
pub fn check_destination(path: &Path, force: bool) -> Result<()> {
    if path.file_name().is_none() {
        return Err(Error::Destination {
            path: path.to_path_buf(),
            what: "is not a file path".into(),
        });
    }
    let dir = folder_of(path);
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(Error::Destination {
                path: path.to_path_buf(),
                what: format!("{} is not a folder", dir.display()),
            })
        }
        Err(e) => return Err(Error::io("use the folder of", path, e)),
    }
    match std::fs::symlink_metadata(path) {
        Ok(m) => {
            let t = m.file_type();
            if t.is_dir() {
                return Err(Error::Destination {
                    path: path.to_path_buf(),
                    what: "is a folder".into(),
                });
            }
            if !(t.is_file() || t.is_symlink())
                || !std::fs::metadata(path).is_ok_and(|m| m.is_file())
            {
                return Err(Error::Destination {
                    path: path.to_path_buf(),
                    what: "is not a regular file (a device, FIFO or socket); it is never replaced"
                        .into(),
                });
            }
            if !force {
                return Err(Error::Exists(path.to_path_buf()));
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io("inspect", path, e)),
    }
}

/// Write `bytes` to `path` atomically. An existing file is replaced only when `force`.
pub fn write_atomic(path: &Path, bytes: &[u8], force: bool) -> Result<()> {
    check_destination(path, force)?;
    let dir = folder_of(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = temp_path(dir, &name);
    let result = (|| -> Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| Error::io("create", &tmp, e))?;
        f.write_all(bytes)
            .map_err(|e| Error::io("write", &tmp, e))?;
        f.sync_all().map_err(|e| Error::io("sync", &tmp, e))?;
        drop(f);
        std::fs::rename(&tmp, path)
            .map_err(|e| Error::io("rename a temporary file to", path, e))?;
        sync_folder(dir);
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Make a rename in `dir` durable. Best effort: some file systems refuse to sync a folder,
/// and the data itself is already synced.
fn sync_folder(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

/// Where a backup of `original` is kept: `FILE.bak` beside it.
pub fn backup_path(original: &Path) -> PathBuf {
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
    let bytes =
        std::fs::read(original).map_err(|e| Error::io("read for its backup", original, e))?;
    write_atomic(backup, &bytes, false)?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_unique_and_short() {
        let long = "x".repeat(250);
        let a = temp_path(Path::new("/d"), &long);
        let b = temp_path(Path::new("/d"), &long);
        assert_ne!(a, b);
        assert!(a.file_name().unwrap().len() <= NAME_MAX);
        let multi = "é".repeat(200);
        assert!(
            temp_path(Path::new("/d"), &multi)
                .file_name()
                .unwrap()
                .len()
                <= NAME_MAX
        );
    }

    #[test]
    fn writes_replace_only_with_force_and_never_a_folder() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.bin");
        write_atomic(&p, b"one", false).unwrap();
        assert!(matches!(
            write_atomic(&p, b"two", false),
            Err(Error::Exists(_))
        ));
        write_atomic(&p, b"two", true).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert!(write_atomic(dir.path(), b"x", true).is_err());
        let missing = dir.path().join("no/such/folder/a.bin");
        let e = write_atomic(&missing, b"x", true).unwrap_err().to_string();
        assert!(e.contains("no/such/folder"), "{e}");
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
        assert_eq!(left.len(), 1);
    }
}
