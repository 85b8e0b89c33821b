//! `c3dfix convert`: rewrite files, optionally in another processor or number format.
//!
//! One file to one output (`-o`), or many — files and folders, `--files-from`, `--shard` —
//! in place or into `--out-dir`, in parallel. Each output is a synced temporary file renamed
//! into place, so stopping the process at any moment leaves every file either as it was or
//! fully converted. A file that fails is reported and left untouched; the others go on.

use crate::commands::parallel::run_each;
use crate::commands::targets::TargetArgs;
use crate::console::{errln, outln};
use anyhow::{bail, Result};
use c3dfix::files::{convert_to, Conversion, Converted};
use c3dfix::targets::plan;
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

pub fn run(a: Args) -> Result<i32> {
    let want = Conversion {
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
fn one(t: &TargetArgs, output: &Path, want: Conversion) -> Result<i32> {
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
    let done = convert_to(input, output, &want, false, false, t.force)?;
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
fn many(t: &TargetArgs, want: Conversion) -> Result<i32> {
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
            Ok(convert_to(
                &job.input,
                &job.output,
                &want,
                t.in_place,
                t.backup,
                overwrite,
            )?)
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
