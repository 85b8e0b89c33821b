//! Saving files safely, for the library, the command and the Python package alike. Every destination of a run is checked before the first byte
//! is written; each file goes to a temporary file in its target folder, is synced, and is
//! renamed into place only once every temporary file of the run exists; the folder is then
//! synced so the rename itself survives a crash. An interrupted or failed run leaves each
//! destination as it was or fully written, and never leaves one output of a run without the
//! others.

use crate::error::{Error, Result};
use std::ffi::OsStr;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Return an [`Error::Output`] with a formatted message (every message names its path).
macro_rules! bail {
    ($($t:tt)*) => {
        return Err(Error::Output(format!($($t)*)))
    };
}

/// Attach a message naming the path to an I/O error.
trait Context<T> {
    fn with_context(self, what: impl FnOnce() -> String) -> Result<T>;
}

impl<T> Context<T> for std::io::Result<T> {
    fn with_context(self, what: impl FnOnce() -> String) -> Result<T> {
        self.map_err(|e| Error::Output(format!("{}: {e}", what())))
    }
}

impl<T> Context<T> for Option<T> {
    fn with_context(self, what: impl FnOnce() -> String) -> Result<T> {
        self.ok_or_else(|| Error::Output(what()))
    }
}

/// The longest file name (in bytes) written: the limit of ext4, XFS, Btrfs, APFS and NTFS.
pub const NAME_MAX: usize = 255;

/// Bytes of the destination's name kept in a temporary name (so a stray temporary file says
/// what it was for, while the whole name stays far below [`NAME_MAX`]).
const TMP_STEM_MAX: usize = 64;

/// Temporary files made by this process so far: with the process id, a name no other call
/// (another thread of `batch`, or another c3dfix) uses at the same time.
static TMP_COUNT: AtomicU64 = AtomicU64::new(0);

/// What an [`Output`] holds.
#[derive(Debug, Clone, Copy)]
pub enum Content<'a> {
    /// These bytes.
    Bytes(&'a [u8]),
    /// A copy of this file as it is on disk when the run writes, streamed (a backup of a
    /// long trial costs no memory).
    CopyOf(&'a Path),
}

impl<'a> From<&'a [u8]> for Content<'a> {
    fn from(b: &'a [u8]) -> Self {
        Content::Bytes(b)
    }
}

impl<'a> From<&'a Vec<u8>> for Content<'a> {
    fn from(b: &'a Vec<u8>) -> Self {
        Content::Bytes(b)
    }
}

/// One file a command writes.
pub struct Output<'a> {
    pub path: &'a Path,
    pub bytes: Content<'a>,
    /// Whether an existing file there may be replaced (`--force`, `--in-place`).
    pub replace: bool,
}

/// The outputs of a run that writes `bytes` to `path`, keeping the file there first as
/// `backup` when given: the backup (a copy of the file on disk, streamed as the run writes)
/// and the new file. Add the run's other outputs and give them all to [`write_all`], so that
/// they land together or not at all.
pub fn replacing<'a>(
    path: &'a Path,
    bytes: &'a [u8],
    replace: bool,
    backup: Option<&'a Path>,
) -> Vec<Output<'a>> {
    let mut outs = Vec::with_capacity(3);
    if let Some(b) = backup {
        outs.push(Output {
            path: b,
            bytes: Content::CopyOf(path),
            replace: false,
        });
    }
    outs.push(Output {
        path,
        bytes: Content::Bytes(bytes),
        replace,
    });
    outs
}

/// Write `bytes` to `path` atomically. Refuses to replace an existing file unless `force`.
pub fn write_atomic(path: &Path, bytes: &[u8], force: bool) -> Result<()> {
    write_all(&[Output {
        path,
        bytes: bytes.into(),
        replace: force,
    }])
}

/// Write the outputs of one run: all of them, or (on any failure before the renames) none.
pub fn write_all(outputs: &[Output]) -> Result<()> {
    for (i, o) in outputs.iter().enumerate() {
        check_destination(o.path, o.replace)?;
        if let Some(other) = outputs[..i].iter().find(|p| same_file(p.path, o.path)) {
            bail!(
                "{} and {} are the same file: each output needs its own path",
                other.path.display(),
                o.path.display()
            );
        }
    }
    let mut temps: Vec<PathBuf> = Vec::with_capacity(outputs.len());
    let written = outputs.iter().try_for_each(|o| {
        let tmp = temp_path(o.path)?;
        let r = write_synced(&tmp, o.bytes)
            .map_err(|e| Error::Output(format!("cannot write {}: {e}", o.path.display())));
        // Recorded even on failure: a partly written temporary file is removed below.
        temps.push(tmp);
        r
    });
    if let Err(e) = written {
        temps.iter().for_each(|t| drop(std::fs::remove_file(t)));
        return Err(e);
    }
    for (k, (o, tmp)) in outputs.iter().zip(&temps).enumerate() {
        if let Err(e) = std::fs::rename(tmp, o.path) {
            temps[k..]
                .iter()
                .for_each(|t| drop(std::fs::remove_file(t)));
            return Err(Error::Output(format!(
                "cannot rename {} to {}: {e}",
                tmp.display(),
                o.path.display()
            )));
        }
    }
    let mut synced: Vec<&Path> = Vec::new();
    for o in outputs {
        let dir = folder_of(o.path);
        if !synced.contains(&dir) {
            sync_folder(dir)?;
            synced.push(dir);
        }
    }
    Ok(())
}

/// Everything about a destination that can be known before writing: its folder exists, its
/// name fits the file system, and what is there now is a regular file that may be replaced.
/// A device, a FIFO or a folder is never replaced by a file, even with `--force`.
pub fn check_destination(path: &Path, replace: bool) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file path", path.display()))?;
    if name.len() > NAME_MAX {
        bail!(
            "{}: the file name is {} bytes, longer than file systems allow ({NAME_MAX})",
            path.display(),
            name.len()
        );
    }
    let dir = folder_of(path);
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => bail!(
            "cannot write {}: {} is not a folder",
            path.display(),
            dir.display()
        ),
        Err(e) => bail!(
            "cannot write {}: folder {}: {e}",
            path.display(),
            dir.display()
        ),
    }
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => bail!(
            "{} is {}, not a regular file: c3dfix writes only regular files",
            path.display(),
            kind_of(&m)
        ),
        Ok(_) if !replace => Err(Error::Exists {
            path: path.to_path_buf(),
        }),
        Ok(_) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => bail!("cannot write {}: {e}", path.display()),
    }
}

/// Refuse `dest` when it is one of the files the run reads: an output of another kind (a
/// report, a CSV, a picture) written there would destroy the input, `--force` or not.
pub fn refuse_input(dest: &Path, inputs: &[&Path], what: &str) -> Result<()> {
    if let Some(i) = inputs.iter().find(|i| same_file(i, dest)) {
        bail!(
            "{what} {} is the input file {}: refusing to overwrite it",
            dest.display(),
            i.display()
        );
    }
    Ok(())
}

/// Refuse writing a command's result over its own input through `-o` (or an output folder
/// that is the input's): the raw trial would be gone. Replacing the input is asked for by
/// name, with in-place (and a backup if wanted), never by `--force`.
pub fn refuse_own_input(input: &Path, output: &Path) -> Result<()> {
    if same_file(input, output) {
        return Err(Error::OwnInput {
            output: output.to_path_buf(),
            input: input.to_path_buf(),
        });
    }
    Ok(())
}

/// Whether two paths name the same file: the same inode when both exist, else the same
/// absolute path once their folders are resolved.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    let resolved = |p: &Path| -> Option<PathBuf> {
        let dir = std::fs::canonicalize(folder_of(p)).ok()?;
        Some(dir.join(p.file_name()?))
    };
    match (resolved(a), resolved(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// The folder a path's file is in (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

fn kind_of(m: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = m.file_type();
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_block_device() || t.is_char_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if m.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// A fresh temporary name beside `path`: a short prefix of its name, the process id and a
/// per-process counter — unique per call, and well within [`NAME_MAX`].
fn temp_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .map(OsStr::to_string_lossy)
        .with_context(|| format!("{}: not a file path", path.display()))?;
    let mut end = name.len().min(TMP_STEM_MAX);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    let n = TMP_COUNT.fetch_add(1, Ordering::Relaxed);
    Ok(folder_of(path).join(format!(
        ".{}.{}-{n}.c3dfix-tmp",
        &name[..end],
        std::process::id()
    )))
}

/// Create `tmp` (it must not exist), write the content and sync it to disk.
fn write_synced(tmp: &Path, content: Content) -> Result<()> {
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(tmp)
        .with_context(|| format!("cannot create {}", tmp.display()))?;
    match content {
        Content::Bytes(bytes) => f
            .write_all(bytes)
            .with_context(|| format!("cannot write {}", tmp.display()))?,
        Content::CopyOf(src) => {
            let mut from = std::fs::File::open(src)
                .with_context(|| format!("cannot read {}", src.display()))?;
            std::io::copy(&mut from, &mut f)
                .with_context(|| format!("cannot copy {} to {}", src.display(), tmp.display()))?;
        }
    }
    f.sync_all()
        .with_context(|| format!("cannot sync {}", tmp.display()))
}

/// Sync a folder, so that a rename into it is on disk. File systems that cannot sync a
/// folder say so with "invalid input"; their renames are as durable as they get.
fn sync_folder(dir: &Path) -> Result<()> {
    #[cfg(unix)]
    {
        let r = std::fs::File::open(dir).and_then(|d| d.sync_all());
        match r {
            Err(e)
                if !matches!(
                    e.kind(),
                    std::io::ErrorKind::InvalidInput | std::io::ErrorKind::Unsupported
                ) =>
            {
                return Err(Error::Output(format!(
                    "cannot sync folder {}: {e}",
                    dir.display()
                )));
            }
            _ => {}
        }
    }
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

/// Where `--backup` keeps the original: `FILE.bak` beside it.
pub fn backup_path(original: &Path) -> PathBuf {
    let mut name = original.file_name().unwrap_or_default().to_os_string();
    name.push(".bak");
    original.with_file_name(name)
}

/// The backup to write for `original` with `--backup`: none when one already exists, since
/// the first backup is the true original and a second in-place repair must not replace it
/// with a repaired file.
pub fn new_backup(original: &Path) -> Option<PathBuf> {
    let b = backup_path(original);
    (!b.exists()).then_some(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_unique_and_short() {
        let long = "x".repeat(NAME_MAX);
        let p = Path::new("/some/folder").join(&long);
        let a = temp_path(&p).unwrap();
        let b = temp_path(&p).unwrap();
        assert_ne!(a, b);
        let n = a.file_name().unwrap().len();
        assert!(n < 120, "temporary name of {n} bytes");
        assert_eq!(a.parent(), Some(Path::new("/some/folder")));
        // A name cut inside a multi-byte character is cut before it.
        let name = "é".repeat(100);
        assert!(temp_path(Path::new(&name)).is_ok());
    }

    #[test]
    fn all_or_nothing() {
        let d = tempfile::tempdir().unwrap();
        let a = d.path().join("a.txt");
        let b = d.path().join("missing").join("b.txt");
        let outs = [
            Output {
                path: &a,
                bytes: Content::Bytes(b"a"),
                replace: false,
            },
            Output {
                path: &b,
                bytes: Content::Bytes(b"b"),
                replace: false,
            },
        ];
        let e = write_all(&outs).unwrap_err().to_string();
        assert!(e.contains("missing"), "{e}");
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 0);
        let same = [
            Output {
                path: &a,
                bytes: Content::Bytes(b"a"),
                replace: true,
            },
            Output {
                path: &d.path().join(".").join("a.txt"),
                bytes: Content::Bytes(b"b"),
                replace: true,
            },
        ];
        assert!(write_all(&same)
            .unwrap_err()
            .to_string()
            .contains("same file"));
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 0);
    }
}
