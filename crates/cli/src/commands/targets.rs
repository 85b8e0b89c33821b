//! Which files a run over many trials processes, and where each one goes.
//!
//! Paths come from the command line and from a list (`--files-from`); folders are walked for
//! `*.c3d`. A file reached twice — a folder and a file inside it, a symbolic link, `./a` and
//! `a` — is processed once (the first naming wins), since two jobs writing one file would race.
//! The list is sorted by the path as named, so every process given the same arguments sees
//! the same order, and `--shard K/N` takes a deterministic, disjoint part of it: the shards of
//! a Slurm array or an indexed Kubernetes job together cover every file exactly once.

use anyhow::{bail, Context, Result};
use std::collections::{HashMap, HashSet};
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
    #[arg(long, value_parser = crate::ranges::jobs)]
    pub jobs: Option<usize>,
    /// One JSON line per file, then a JSON summary line.
    #[arg(long)]
    pub json: bool,
}

/// `K/N`: the K-th (1-based) of N parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("{s:?}: expected K/N with 1 ≤ K ≤ N, e.g. 2/8");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// Whether the `i`-th (0-based) file of the sorted list belongs to this shard. Files are
    /// dealt round-robin, so each shard gets a mix of every folder rather than one stretch.
    pub fn holds(&self, i: usize) -> bool {
        i % self.n == self.k - 1
    }
}

/// Where the outputs go.
#[derive(Clone, Copy, Debug)]
pub enum Destination<'a> {
    /// Each file replaces itself.
    InPlace,
    /// Below this folder, mirroring the structure below each given folder.
    OutDir(&'a Path),
}

/// One file to process.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Target {
    /// The file as it was named (given, listed or found in a given folder).
    pub input: PathBuf,
    /// Where its output goes. In place, the file's canonical path, so that a symbolic link
    /// is written through rather than replaced by a copy.
    pub output: PathBuf,
}

impl Target {
    /// Make the output's folder, and refuse an existing output unless `overwrite`.
    pub fn prepare_output(&self, overwrite: bool) -> anyhow::Result<()> {
        if let Some(parent) = self.output.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("cannot create the folder {}", parent.display()))?;
        }
        if !overwrite && self.output.exists() {
            anyhow::bail!(
                "{} exists (use --force to overwrite)",
                self.output.display()
            );
        }
        Ok(())
    }
}

/// The files of one run.
#[derive(Debug)]
pub struct Plan {
    /// This shard's files (all of them without `--shard`), sorted by input path.
    pub targets: Vec<Target>,
    /// Distinct files named before sharding.
    pub listed: usize,
    /// Namings dropped because they reached a file named before.
    pub duplicates: usize,
}

impl TargetArgs {
    /// Check the combination of options (before any file is looked at).
    pub fn destination(&self) -> Result<Destination<'_>> {
        let d = match (&self.out_dir, self.in_place) {
            (Some(_), true) => bail!("give either --out-dir DIR or --in-place, not both"),
            (None, false) => bail!("give --out-dir DIR or --in-place"),
            (Some(d), false) => Destination::OutDir(d),
            (None, true) => Destination::InPlace,
        };
        if self.backup && !self.in_place {
            bail!("--backup goes with --in-place");
        }
        if self.jobs == Some(0) {
            bail!("--jobs must be at least 1");
        }
        Ok(d)
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

/// The files below `named` (files as they are, folders walked), each once, sorted, with
/// their outputs; then this shard's part.
pub fn plan(named: &[PathBuf], dest: Destination<'_>, shard: Option<Shard>) -> Result<Plan> {
    let mut seen = HashSet::new();
    let mut duplicates = 0;
    let mut targets = Vec::new();
    for p in named {
        // (file, its path below the output folder)
        let found: Vec<(PathBuf, PathBuf)> = if p.is_file() {
            vec![(p.clone(), PathBuf::from(p.file_name().unwrap_or_default()))]
        } else if p.is_dir() {
            let mut files = Vec::new();
            walk(p, &mut files)?;
            files
                .into_iter()
                .map(|f| {
                    let rel = f.strip_prefix(p).unwrap_or(&f).to_path_buf();
                    (f, rel)
                })
                .collect()
        } else {
            bail!("{}: no such file or folder", p.display());
        };
        for (input, rel) in found {
            let canonical = input
                .canonicalize()
                .with_context(|| format!("{}: cannot resolve the path", input.display()))?;
            if !seen.insert(canonical.clone()) {
                duplicates += 1;
                continue;
            }
            let output = match dest {
                Destination::InPlace => canonical,
                Destination::OutDir(d) => d.join(rel),
            };
            targets.push(Target { input, output });
        }
    }
    targets.sort_by(|a, b| a.input.cmp(&b.input));
    // Two files written to one output would have one silently replace the other.
    let mut by_output: HashMap<&Path, &Path> = HashMap::new();
    for t in &targets {
        if let Some(first) = by_output.insert(&t.output, &t.input) {
            bail!(
                "{} and {} would both be written to {}; give their folder instead, or run them separately",
                first.display(),
                t.input.display(),
                t.output.display()
            );
        }
    }
    let listed = targets.len();
    if let Some(s) = shard {
        targets = targets
            .into_iter()
            .enumerate()
            .filter(|(i, _)| s.holds(*i))
            .map(|(_, t)| t)
            .collect();
    }
    Ok(Plan {
        targets,
        listed,
        duplicates,
    })
}

/// The `*.c3d` files below `dir` (any case of the extension), symbolic links not followed.
fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    let entries = std::fs::read_dir(dir).map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?;
    for e in entries.flatten() {
        let p = e.path();
        let Ok(ft) = e.file_type() else { continue };
        if ft.is_dir() {
            walk(&p, out)?;
        } else if ft.is_file() && p.extension().is_some_and(|x| x.eq_ignore_ascii_case("c3d")) {
            out.push(p);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_parses_and_deals_round_robin() {
        let s: Shard = "2/3".parse().unwrap();
        assert_eq!(s, Shard { k: 2, n: 3 });
        assert_eq!(s.to_string(), "2/3");
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        // Every index lands in exactly one of the N shards.
        for i in 0..20 {
            let owners = (1..=3).filter(|&k| Shard { k, n: 3 }.holds(i)).count();
            assert_eq!(owners, 1);
        }
    }

    #[test]
    fn a_file_named_twice_is_planned_once() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir_all(d.join("in/sub")).unwrap();
        for f in ["in/a.c3d", "in/sub/b.C3D", "in/notes.txt"] {
            std::fs::write(d.join(f), b"x").unwrap();
        }
        let named = vec![
            d.join("in"),
            d.join("in/a.c3d"),
            d.join("in/sub/../a.c3d"),
            d.join("in/sub/b.C3D"),
        ];
        let p = plan(&named, Destination::OutDir(&d.join("out")), None).unwrap();
        assert_eq!(p.listed, 2);
        assert_eq!(p.duplicates, 3);
        let outs: Vec<_> = p.targets.iter().map(|t| t.output.clone()).collect();
        assert_eq!(outs, [d.join("out/a.c3d"), d.join("out/sub/b.C3D")]);
        let p = plan(&named, Destination::InPlace, None).unwrap();
        let canon = d.canonicalize().unwrap();
        assert_eq!(p.targets[0].output, canon.join("in/a.c3d"));
    }

    #[test]
    fn two_files_with_one_output_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in ["x/a.c3d", "y/a.c3d"] {
            std::fs::create_dir_all(d.join(f).parent().unwrap()).unwrap();
            std::fs::write(d.join(f), b"x").unwrap();
        }
        let named = vec![d.join("x/a.c3d"), d.join("y/a.c3d")];
        let e = plan(&named, Destination::OutDir(d), None).unwrap_err();
        assert!(e.to_string().contains("would both be written"), "{e}");
        assert!(plan(&named, Destination::InPlace, None).is_ok());
    }

    #[test]
    fn shards_cover_the_list_once() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for i in 0..10 {
            std::fs::write(d.join(format!("t{i}.c3d")), b"x").unwrap();
        }
        let named = vec![d.to_path_buf()];
        let all = plan(&named, Destination::InPlace, None).unwrap().targets;
        let mut union = Vec::new();
        for k in 1..=3 {
            let p = plan(&named, Destination::InPlace, Some(Shard { k, n: 3 })).unwrap();
            assert_eq!(p.listed, 10);
            union.extend(p.targets);
        }
        union.sort_by(|a, b| a.input.cmp(&b.input));
        assert_eq!(union, all);
    }

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
