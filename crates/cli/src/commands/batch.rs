//! `c3dfix batch`: repair every C3D file under the given paths, in parallel. A file that fails
//! is reported and left untouched; the others go on. Each output is a synced temporary file
//! renamed into place, so stopping the process at any moment leaves every file either as it
//! was or fully repaired.

use crate::commands::info::read_c3d;
use crate::commands::repair::{print_summary, repair_read, Summary};
use crate::commands::repair_io::RepairArgs;
use crate::console::{errln, outln};
use crate::output::write_atomic;
use anyhow::{bail, Result};
use rayon::prelude::*;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

#[derive(clap::Args)]
pub struct Args {
    /// Files and folders (searched recursively for *.c3d).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Write repaired files here, keeping the folder structure below each given folder.
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// Replace each file (atomically).
    #[arg(long)]
    pub in_place: bool,
    /// With --in-place: keep each original as FILE.bak (existing backups are kept as they are).
    #[arg(long)]
    pub backup: bool,
    /// Replace existing files in --out-dir.
    #[arg(long)]
    pub force: bool,
    /// Files repaired at once, 1 to 256 (default: one per core).
    #[arg(long, value_parser = crate::ranges::jobs)]
    pub jobs: Option<usize>,
    /// One JSON line per file, then a JSON summary line.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub repair: RepairArgs,
}

/// (input, output) for every C3D file below the given paths, in a stable order.
fn plan(paths: &[PathBuf], out_dir: Option<&Path>) -> Result<Vec<(PathBuf, PathBuf)>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_file() {
            let target = match out_dir {
                Some(d) => d.join(p.file_name().unwrap_or_default()),
                None => p.clone(),
            };
            out.push((p.clone(), target));
        } else if p.is_dir() {
            let mut files = Vec::new();
            walk(p, &mut files)?;
            files.sort();
            for f in files {
                let target = match out_dir {
                    Some(d) => d.join(f.strip_prefix(p).unwrap_or(&f)),
                    None => f.clone(),
                };
                out.push((f, target));
            }
        } else {
            bail!("{}: no such file or folder", p.display());
        }
    }
    Ok(out)
}

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

pub fn run(a: Args) -> Result<i32> {
    match (&a.out_dir, a.in_place) {
        (Some(_), true) => bail!("give either --out-dir DIR or --in-place, not both"),
        (None, false) => bail!("give --out-dir DIR or --in-place"),
        _ => {}
    }
    if a.backup && !a.in_place {
        bail!("--backup goes with --in-place");
    }
    if a.jobs == Some(0) {
        bail!("--jobs must be at least 1");
    }
    // Options are checked once, before any file is touched.
    a.repair.config("mm")?;
    let jobs = plan(&a.paths, a.out_dir.as_deref())?;
    if jobs.is_empty() {
        bail!("no C3D files found");
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.jobs.unwrap_or(0))
        .build()
        .map_err(|e| anyhow::anyhow!("cannot start worker threads: {e}"))?;
    let bar = (!a.json && std::io::stderr().is_terminal()).then(|| {
        let b = indicatif::ProgressBar::new(jobs.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let out_lock = Mutex::new(());
    let results: Vec<Result<Summary, String>> = pool.install(|| {
        jobs.par_iter()
            .map(|(input, output)| {
                let r = (|| -> Result<Summary> {
                    if let Some(parent) = output.parent() {
                        std::fs::create_dir_all(parent).map_err(|e| {
                            anyhow::anyhow!("cannot create folder {}: {e}", parent.display())
                        })?;
                    }
                    let overwrite = a.force || a.in_place;
                    if !overwrite && output.exists() {
                        bail!("{} exists (use --force to overwrite)", output.display());
                    }
                    // Read once: a trial without points (EMG only) has nothing to repair; it
                    // is skipped, and copied unchanged so the output folder holds every trial.
                    let c = read_c3d(input)?;
                    if c.points().count() == 0 {
                        if !a.in_place {
                            write_atomic(output, c.source_bytes().unwrap_or_default(), overwrite)?;
                        }
                        return Ok(Summary {
                            file: input.display().to_string(),
                            output: output.display().to_string(),
                            skipped: Some("no points".into()),
                            ..Summary::default()
                        });
                    }
                    repair_read(c, input, output, &a.repair, a.backup, overwrite).map(|(_, s)| s)
                })()
                .map_err(|e| format!("{e:#}"));
                let _guard = out_lock.lock();
                if a.json {
                    let line = match &r {
                        Ok(s) => serde_json::json!({"file": input.display().to_string(), "ok": true, "summary": s}),
                        Err(e) => serde_json::json!({"file": input.display().to_string(), "ok": false, "error": e}),
                    };
                    let mut so = std::io::stdout().lock();
                    let _ = writeln!(so, "{line}");
                } else if let Err(e) = &r {
                    match &bar {
                        Some(b) => b.println(format!("failed: {e}")),
                        None => errln!("failed: {e}"),
                    }
                }
                if let Some(b) = &bar {
                    b.set_message(input.file_name().unwrap_or_default().to_string_lossy().into_owned());
                    b.inc(1);
                }
                r
            })
            .collect()
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let ok: Vec<&Summary> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
    let failed = results.len() - ok.len();
    let skipped = ok.iter().filter(|s| s.skipped.is_some()).count();
    let filled: usize = ok.iter().map(|s| s.filled).sum();
    let gaps: usize = ok.iter().map(|s| s.gaps).sum();
    let spikes: usize = ok.iter().map(|s| s.spikes).sum();
    let changed: usize = ok.iter().map(|s| s.samples_changed).sum();
    if a.json {
        outln!(
            "{}",
            serde_json::json!({"summary": {"files": results.len(), "repaired": ok.len() - skipped, "skipped": skipped, "failed": failed,
                "gaps": gaps, "filled": filled, "spikes": spikes, "samples_changed": changed}})
        )?;
    } else {
        if ok.len() <= 3 {
            for s in &ok {
                print_summary(s)?;
            }
        }
        outln!(
            "{} files: {} repaired, {skipped} skipped (no points), {} failed; {gaps} gaps, {filled} filled, {spikes} spikes, {changed} samples changed",
            results.len(),
            ok.len() - skipped,
            failed
        )?;
    }
    Ok(if failed > 0 { 1 } else { 0 })
}
