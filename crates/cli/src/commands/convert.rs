//! `c3dfix convert`: rewrite files, optionally in another processor or number format.
//!
//! One file to one output (`-o`), or many — files and folders, `--files-from`, `--shard` —
//! in place or into `--out-dir`, in parallel. Each output is a synced temporary file renamed
//! into place, so stopping the process at any moment leaves every file either as it was or
//! fully converted. A file that fails is reported and left untouched; the others go on.

use crate::commands::info::read_c3d;
use crate::commands::parallel::run_each;
use crate::commands::targets::{plan, TargetArgs};
use crate::console::{errln, outln};
use anyhow::{bail, Context, Result};
use c3dfix::save::{check_destination, new_backup, replacing, write_all};
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum ProcessorArg {
    Intel,
    Dec,
    Sgi,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum FormatArg {
    Int,
    Float,
}

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub targets: TargetArgs,
    /// Where to write, when converting one file.
    #[arg(short, long, conflicts_with_all = ["out_dir", "in_place", "files_from", "shard"])]
    pub output: Option<PathBuf>,
    /// Target processor format (default: each input's).
    #[arg(long, value_enum)]
    pub processor: Option<ProcessorArg>,
    /// Target number format (default: each input's).
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// POINT:SCALE for integer output (default: keep it if exact, else the finest that fits).
    /// Above 0, from the largest coordinate / 32767 (finer does not fit in 16 bits) to the
    /// largest coordinate (coarser would store every coordinate as 0).
    #[arg(long, value_parser = crate::ranges::scale)]
    pub scale: Option<f32>,
}

/// The formats asked for; `None` keeps each file's own.
#[derive(Clone, Copy)]
struct Wanted {
    processor: Option<c3d::Processor>,
    format: Option<c3d::NumberFormat>,
    scale: Option<f32>,
}

/// What converting one file did.
#[derive(Debug, Clone, Serialize)]
pub struct Converted {
    pub output: String,
    pub processor: &'static str,
    pub format: &'static str,
    pub bytes: usize,
    /// In place: the file already was what was asked for, byte for byte, and was not rewritten.
    pub unchanged: bool,
    /// What the reader noticed about the input (format rule breaks it read around).
    pub warnings: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backup: Option<String>,
}

/// Convert `input` into `output`. With `in_place`, a file that would not change is left alone
/// (not even its time stamp moves); with `backup`, the original is kept first as FILE.bak.
fn convert_one(
    input: &Path,
    output: &Path,
    want: Wanted,
    in_place: bool,
    backup: bool,
    overwrite: bool,
) -> Result<Converted> {
    let c = read_c3d(input)?;
    let processor = want.processor.unwrap_or(c.processor());
    let format = want.format.unwrap_or(c.format());
    let bytes = c
        .converted(processor, format, want.scale)
        .with_context(|| format!("converting {}", input.display()))?;
    let mut done = Converted {
        output: output.display().to_string(),
        processor: processor.name(),
        format: format.name(),
        bytes: bytes.len(),
        unchanged: false,
        warnings: c.warnings().iter().map(|w| w.to_string()).collect(),
        backup: None,
    };
    if in_place && c.source_bytes() == Some(&bytes[..]) {
        done.unchanged = true;
        return Ok(done);
    }
    check_destination(output, overwrite)?;
    // In place the output is the file itself (by its canonical path, so a backup of a file
    // reached through a link sits beside the file, as `c3dfix::save` puts it).
    let backup_to = if backup && output.exists() {
        new_backup(output)
    } else {
        None
    };
    done.backup = backup_to.as_ref().map(|b| b.display().to_string());
    let outs = replacing(output, &bytes, overwrite, backup_to.as_deref());
    // The backup and the converted file land together, or neither does.
    write_all(&outs)?;
    Ok(done)
}

pub fn run(a: Args) -> Result<i32> {
    let want = Wanted {
        processor: a.processor.map(|p| match p {
            ProcessorArg::Intel => c3d::Processor::Intel,
            ProcessorArg::Dec => c3d::Processor::Dec,
            ProcessorArg::Sgi => c3d::Processor::Sgi,
        }),
        format: a.format.map(|f| match f {
            FormatArg::Int => c3d::NumberFormat::Integer,
            FormatArg::Float => c3d::NumberFormat::Float,
        }),
        scale: a.scale,
    };
    match &a.output {
        Some(o) => one(&a.targets, o, want),
        None => many(&a.targets, want),
    }
}

/// `convert IN -o OUT`: one file; any error is the command's error (exit 2).
fn one(t: &TargetArgs, output: &Path, want: Wanted) -> Result<i32> {
    let [input] = t.paths.as_slice() else {
        bail!("-o OUT takes one input file; for several, give --out-dir DIR or --in-place");
    };
    if input.is_dir() {
        bail!(
            "{} is a folder: give --out-dir DIR or --in-place",
            input.display()
        );
    }
    if t.backup {
        bail!("--backup goes with --in-place");
    }
    let done = convert_one(input, output, want, false, false, t.force)?;
    if t.json {
        let line =
            serde_json::json!({"file": input.display().to_string(), "ok": true, "result": done});
        outln!("{line}")?;
    } else {
        for w in &done.warnings {
            errln!("c3dfix: warning: {}: {w}", input.display());
        }
        errln!(
            "wrote {} ({} processor, {} data, {} bytes)",
            done.output,
            done.processor,
            done.format,
            done.bytes
        );
    }
    Ok(0)
}

/// Many files, in place or into a folder; exit 1 if any failed.
fn many(t: &TargetArgs, want: Wanted) -> Result<i32> {
    let dest = t.destination()?;
    let plan = plan(&t.named_paths()?, dest, t.shard)?;
    if plan.listed == 0 {
        bail!("no C3D files found");
    }
    let overwrite = t.force || t.in_place;
    let results = run_each(
        &plan.targets,
        t.jobs,
        t.json,
        |job| {
            job.prepare_output(overwrite)?;
            convert_one(
                &job.input,
                &job.output,
                want,
                t.in_place,
                t.backup,
                overwrite,
            )
        },
        "result",
    )?;
    let ok: Vec<&Converted> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
    let failed = results.len() - ok.len();
    let unchanged = ok.iter().filter(|d| d.unchanged).count();
    let with_warnings = ok.iter().filter(|d| !d.warnings.is_empty()).count();
    if t.json {
        outln!(
            "{}",
            serde_json::json!({"summary": {"files": results.len(), "converted": ok.len() - unchanged,
                "unchanged": unchanged, "failed": failed, "with_warnings": with_warnings,
                "listed": plan.listed, "duplicates": plan.duplicates,
                "shard": t.shard.map(|s| s.to_string())}})
        )?;
    } else {
        outln!(
            "{} files: {} converted, {unchanged} already so, {failed} failed; {with_warnings} with warnings (see c3dfix info FILE)",
            results.len(),
            ok.len() - unchanged,
        )?;
    }
    Ok(if failed > 0 { 1 } else { 0 })
}
