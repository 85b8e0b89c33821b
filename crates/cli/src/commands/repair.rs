//! `c3dfix repair`: spikes → fill → filter on one file, written back as a valid C3D, through
//! the library ([`c3dfix::repair`]).

use crate::commands::info::read_c3d;
use crate::commands::repair_io::{self, RepairArgs};
use crate::console::outln;
use crate::output::{
    check_destination, new_backup, refuse_input, replacing, write_all, Content, Output,
};
use anyhow::{Context, Result};
use c3dfix::Summary;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    pub input: PathBuf,
    /// Where to write the repaired file.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Replace the input file (atomically).
    #[arg(long)]
    pub in_place: bool,
    /// With --in-place: keep the original as FILE.bak (an existing backup is kept as is).
    #[arg(long)]
    pub backup: bool,
    /// Replace an existing output (and report) file.
    #[arg(long)]
    pub force: bool,
    /// Write the full report (every gap and what filled it, spikes, filter segments) here;
    /// an existing file is replaced only with --force, and never the input or the output.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub repair: RepairArgs,
}

/// A repair done in memory: the full report and the summary (the repaired samples are in
/// the trial, whose bytes [`c3d::C3d::encoded`] gives).
pub struct Repaired {
    pub report: serde_json::Value,
    pub summary: Summary,
}

/// Repair `c` (read from `input`, to be written to `output`, with its original kept at
/// `backup` when given) in memory; nothing is written, so every destination can be checked
/// and written together afterwards.
pub fn repair_c3d(
    c: &mut c3d::C3d,
    input: &Path,
    output: &Path,
    a: &RepairArgs,
    backup: Option<&Path>,
) -> Result<Repaired> {
    let mut done = c3dfix::repair(c, &a.options(), input)?;
    done.summary.output = output.display().to_string();
    done.summary.backup = backup.map(|b| b.display().to_string());
    Ok(Repaired {
        report: done.report(),
        summary: done.summary,
    })
}

pub fn run(a: Args) -> Result<i32> {
    let out = repair_io::output_path(&a.input, &a.output, a.in_place)?;
    if a.backup && !a.in_place {
        anyhow::bail!("--backup goes with --in-place");
    }
    a.repair.check()?;
    let overwrite = a.force || a.in_place;
    // Every destination is checked before the work, and written together after it.
    check_destination(&out, overwrite)?;
    if let Some(r) = &a.report {
        refuse_input(r, &[&a.input, &out], "--report")?;
        check_destination(r, a.force)?;
    }
    let backup = if a.backup { new_backup(&a.input) } else { None };
    let mut c = read_c3d(&a.input)?;
    let r = repair_c3d(&mut c, &a.input, &out, &a.repair, backup.as_deref())?;
    let report = match &a.report {
        Some(_) => serde_json::to_string_pretty(&r.report)?,
        None => String::new(),
    };
    let bytes = c
        .encoded()
        .with_context(|| format!("writing the repaired {}", a.input.display()))?;
    // With --backup (in place), the input as it is on disk: the trial in memory holds the
    // repaired samples.
    let mut outs = replacing(&out, &bytes, overwrite, backup.as_deref());
    if let Some(path) = &a.report {
        outs.push(Output {
            path,
            bytes: Content::Bytes(report.as_bytes()),
            replace: a.force,
        });
    }
    write_all(&outs)?;
    let s = r.summary;
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&s)?)?;
    } else {
        print_summary(&s)?;
    }
    Ok(0)
}

/// The few lines a person reads after a repair.
pub fn print_summary(s: &Summary) -> Result<()> {
    outln!("repaired {} -> {}", s.file, s.output)?;
    let by: Vec<String> = s
        .filled_by
        .iter()
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    let left: Vec<String> = s
        .left_because
        .iter()
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    outln!(
        "  gaps     {} found in {} markers: {} filled ({}), {} left{}",
        s.gaps,
        s.markers,
        s.filled,
        if by.is_empty() {
            "-".into()
        } else {
            by.join(", ")
        },
        s.left,
        if left.is_empty() {
            String::new()
        } else {
            format!(" ({})", left.join(", "))
        }
    )?;
    if let (Some(mean), Some(max)) = (s.expected_error_mm_mean, s.expected_error_mm_max) {
        outln!("  expected fill error {mean:.2} mm on average, {max:.2} mm at most")?;
    }
    for g in s
        .gap_list
        .iter()
        .filter(|g| g.reason.as_deref() == Some("uncertain"))
    {
        outln!(
            "  uncertain {} frames {}..{}: expected error {:.1} mm (left unfilled)",
            g.label,
            g.first,
            g.last,
            g.expected_error_mm.unwrap_or(f64::NAN)
        )?;
    }
    if s.spikes > 0 {
        outln!("  spikes   {} found", s.spikes)?;
    }
    if s.segments_filtered + s.segments_too_short > 0 {
        outln!(
            "  filter   {} segments filtered, {} too short (left unfiltered)",
            s.segments_filtered,
            s.segments_too_short
        )?;
    }
    outln!(
        "  changed  {} samples in {} markers",
        s.samples_changed,
        s.markers_changed
    )?;
    if s.model_outputs_left > 0 {
        outln!(
            "  kept     {} model outputs (angles, forces, …) untouched",
            s.model_outputs_left
        )?;
    }
    if let Some(b) = &s.backup {
        outln!("  backup   {b}")?;
    }
    Ok(())
}
