//! The options of the commands that work on many files (`batch`, `convert`), and the lists
//! of `--files-from`; the plan they make (which files, where each goes, `--shard`) is the
//! library's ([`c3dfix::targets`]).

use anyhow::{Context, Result};
use c3dfix::targets::{Destination, Shard};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The options of the commands that work on many files (`batch`, `convert`).
#[derive(clap::Args, Clone, Debug)]
pub struct TargetArgs {
    /// Files and folders (folders are searched recursively for *.c3d).
    #[arg(required_unless_present = "files_from")]
    pub paths: Vec<PathBuf>,
    /// Also process the paths listed in LIST, one a line (`-`: standard input). Relative
    /// paths are taken from the current folder.
    #[arg(long, value_name = "LIST")]
    pub files_from: Option<PathBuf>,
    /// Process only the K-th of N disjoint parts of the sorted file list (1 ≤ K ≤ N), e.g.
    /// `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Write the outputs here, keeping the folder structure below each given folder.
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// Replace each file (atomically).
    #[arg(long)]
    pub in_place: bool,
    /// With --in-place: keep each original as FILE.bak (existing backups are kept as they are).
    #[arg(long)]
    pub backup: bool,
    /// Replace existing output files (in place, files are always replaced).
    #[arg(long)]
    pub force: bool,
    /// Files worked on at once, 1 to 256 (default: one per core; never more than the files).
    #[arg(long, value_parser = crate::ranges::choice::<c3dfix::Jobs>)]
    pub jobs: Option<c3dfix::Jobs>,
    /// One JSON line per file, then a JSON summary line.
    #[arg(long)]
    pub json: bool,
}

impl TargetArgs {
    /// Check the combination of options (before any file is looked at).
    pub fn destination(&self) -> Result<Destination<'_>> {
        Ok(Destination::choose(
            self.out_dir.as_deref(),
            self.in_place,
            self.backup,
        )?)
    }

    /// Every path named on the command line, then those of `--files-from`.
    pub fn named_paths(&self) -> Result<Vec<PathBuf>> {
        let mut out = self.paths.clone();
        if let Some(list) = &self.files_from {
            out.extend(read_list(list)?);
        }
        Ok(out)
    }
}

/// The paths listed in `list` (`-`: standard input), one a line; blank lines are skipped and
/// a trailing carriage return (a list written on Windows) is dropped.
pub fn read_list(list: &Path) -> Result<Vec<PathBuf>> {
    let mut bytes = Vec::new();
    if list == Path::new("-") {
        std::io::stdin()
            .lock()
            .read_to_end(&mut bytes)
            .context("cannot read the file list from standard input")?;
    } else {
        bytes = std::fs::read(list)
            .with_context(|| format!("cannot read the file list {}", list.display()))?;
    }
    let mut out = Vec::new();
    for line in bytes.split(|&b| b == b'\n') {
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.is_empty() {
            continue;
        }
        out.push(path_from_bytes(line));
    }
    Ok(out)
}

#[cfg(unix)]
fn path_from_bytes(b: &[u8]) -> PathBuf {
    use std::os::unix::ffi::OsStrExt;
    PathBuf::from(std::ffi::OsStr::from_bytes(b))
}

#[cfg(not(unix))]
fn path_from_bytes(b: &[u8]) -> PathBuf {
    PathBuf::from(String::from_utf8_lossy(b).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_skip_blank_lines_and_carriage_returns() {
        let dir = tempfile::tempdir().unwrap();
        let l = dir.path().join("list");
        std::fs::write(&l, b"a.c3d\r\n\nsub dir/b.c3d\n").unwrap();
        assert_eq!(
            read_list(&l).unwrap(),
            [PathBuf::from("a.c3d"), PathBuf::from("sub dir/b.c3d")]
        );
    }
}
