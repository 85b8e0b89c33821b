//! Which files a run over many trials processes, and where each one goes: the plan of
//! `c3dfix batch` and `convert` (and the folders `events` and `gait` walk), here so that a
//! Python script sharding a folder over workers plans it as the command does.
//!
//! Folders are walked for `*.c3d`. A file reached twice — a folder and a file inside it, a
//! symbolic link, `./a` and `a` — is processed once (the first naming wins), since two jobs
//! writing one file would race. The list is sorted by the path as named, so every process
//! given the same arguments sees the same order, and a [`Shard`] `K/N` takes a
//! deterministic, disjoint part of it: the shards of a Slurm array or an indexed Kubernetes
//! job together cover every file exactly once.

use crate::error::{Conflict, Error, Result};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// `K/N`: the K-th (1-based) of N parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = Error;

    fn from_str(s: &str) -> Result<Shard> {
        let bad = || Error::Options(format!("{s:?}: expected K/N with 1 ≤ K ≤ N, e.g. 2/8"));
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

impl<'a> Destination<'a> {
    /// Where a run over many files writes, from what was asked: an output folder or in place
    /// (exactly one), and a backup of each original only in place.
    pub fn choose(out_dir: Option<&'a Path>, in_place: bool, backup: bool) -> Result<Self> {
        let d = match (out_dir, in_place) {
            (Some(_), true) => return Err(Error::Conflict(Conflict::FolderAndInPlace)),
            (None, false) => return Err(Error::Conflict(Conflict::NoFolderOrInPlace)),
            (Some(d), false) => Destination::OutDir(d),
            (None, true) => Destination::InPlace,
        };
        if backup && !in_place {
            return Err(Error::Conflict(Conflict::BackupWithoutInPlace));
        }
        Ok(d)
    }
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
    pub fn prepare_output(&self, overwrite: bool) -> Result<()> {
        if let Some(parent) = self.output.parent() {
            std::fs::create_dir_all(parent).map_err(|e| {
                Error::Output(format!(
                    "cannot create the folder {}: {e}",
                    parent.display()
                ))
            })?;
        }
        if !overwrite && self.output.exists() {
            return Err(Error::Exists {
                path: self.output.clone(),
            });
        }
        Ok(())
    }
}

/// The files of one run.
#[derive(Debug)]
pub struct Plan {
    /// This shard's files (all of them without a shard), sorted by input path.
    pub targets: Vec<Target>,
    /// Distinct files named before sharding.
    pub listed: usize,
    /// Namings dropped because they reached a file named before.
    pub duplicates: usize,
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
            return Err(Error::Trial {
                path: p.clone(),
                what: "no such file or folder".into(),
            });
        };
        for (input, rel) in found {
            let canonical = input.canonicalize().map_err(|e| Error::Trial {
                path: input.clone(),
                what: format!("cannot resolve the path: {e}"),
            })?;
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
            return Err(Error::Output(format!(
                "{} and {} would both be written to {}; give their folder instead, or run them separately",
                first.display(),
                t.input.display(),
                t.output.display()
            )));
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
    let entries = std::fs::read_dir(dir).map_err(|e| Error::Trial {
        path: dir.to_path_buf(),
        what: e.to_string(),
    })?;
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
}
