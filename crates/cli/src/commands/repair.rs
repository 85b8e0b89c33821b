//! `c3dfix repair`: spikes → fill → filter on one file, written back as a valid C3D.

use crate::commands::info::read_c3d;
use crate::commands::repair_io::{self, method_name, RepairArgs};
use crate::console::outln;
use crate::output::{check_destination, new_backup, refuse_input, write_all, Output};
use anyhow::{Context, Result};
use repair::FillOutcome;
use serde::Serialize;
use std::collections::BTreeMap;
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

/// What one repair did, in numbers.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Summary {
    pub file: String,
    pub output: String,
    pub markers: usize,
    pub model_outputs_left: usize,
    pub gaps: usize,
    pub filled: usize,
    /// Gaps filled per method (for `auto`, the method it chose).
    pub filled_by: BTreeMap<String, usize>,
    pub left: usize,
    /// Gaps left per reason.
    pub left_because: BTreeMap<String, usize>,
    pub spikes: usize,
    pub segments_filtered: usize,
    pub segments_too_short: usize,
    pub samples_changed: usize,
    /// Repaired samples clamped to the integer range of POINT:SCALE (integer files only).
    pub samples_clamped: usize,
    pub markers_changed: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backup: Option<String>,
    /// Why the file was left as it was (batch only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

/// Repair `input` into `output`; the full report as JSON, and the summary.
pub fn repair_file(
    input: &Path,
    output: &Path,
    a: &RepairArgs,
    backup: bool,
    overwrite: bool,
) -> Result<(serde_json::Value, Summary)> {
    repair_read(read_c3d(input)?, input, output, a, backup, overwrite)
}

/// [`repair_file`] on a file already read from `input` (so callers that look at it first,
/// like `batch`, read and parse it once).
pub fn repair_read(
    mut c: c3d::C3d,
    input: &Path,
    output: &Path,
    a: &RepairArgs,
    backup: bool,
    overwrite: bool,
) -> Result<(serde_json::Value, Summary)> {
    let backup = if backup { new_backup(input) } else { None };
    let r = repair_c3d(&mut c, input, output, a, backup.as_deref())?;
    let mut outs = Vec::with_capacity(2);
    if let Some(b) = &backup {
        outs.push(Output {
            path: b,
            bytes: c.source_bytes().unwrap_or_default(),
            replace: false,
        });
    }
    outs.push(Output {
        path: output,
        bytes: &r.bytes,
        replace: overwrite,
    });
    write_all(&outs)?;
    Ok((r.report, r.summary))
}

/// A repair done in memory: the repaired file's bytes, the full report, the summary.
pub struct Repaired {
    pub bytes: Vec<u8>,
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
    if c.points().count() == 0 {
        anyhow::bail!("{}: the file has no points to repair", input.display());
    }
    let cfg = a.config(&c.point_units())?;
    let only = repair_io::select(c, &a.markers)?;
    let points = repair_io::marker_indices(c);
    let mut trial = repair_io::trial(c, &points, a.zero_invalid)?;
    let report = repair::repair_trial(&mut trial, &cfg)
        .map_err(|e| anyhow::anyhow!("{}: {e}", input.display()))?;
    let labels = c.point_labels();
    let row_label = |row: usize| labels[points[row]].clone();
    let in_scope = |row: usize| only.as_ref().is_none_or(|o| o.contains(&points[row]));

    let mut s = Summary {
        file: input.display().to_string(),
        output: output.display().to_string(),
        markers: points.len(),
        model_outputs_left: c.points().count() - points.len(),
        backup: backup.map(|b| b.display().to_string()),
        ..Summary::default()
    };
    let mut gaps_json = Vec::new();
    for g in report.gaps.iter().filter(|g| in_scope(g.gap.marker)) {
        s.gaps += 1;
        match g.outcome {
            FillOutcome::Filled { method, .. } => {
                s.filled += 1;
                *s.filled_by.entry(method_name(method)).or_default() += 1;
            }
            FillOutcome::Skipped(reason) => {
                s.left += 1;
                let why = serde_json::to_value(reason)
                    .ok()
                    .map(|v| match v {
                        serde_json::Value::String(x) => x,
                        serde_json::Value::Object(m) => {
                            m.keys().next().cloned().unwrap_or_default()
                        }
                        other => other.to_string(),
                    })
                    .unwrap_or_default();
                *s.left_because.entry(why).or_default() += 1;
            }
        }
        let mut v = serde_json::to_value(g)?;
        v["label"] = row_label(g.gap.marker).into();
        gaps_json.push(v);
    }
    let spikes: Vec<_> = report
        .spikes
        .iter()
        .filter(|sp| in_scope(sp.marker))
        .collect();
    s.spikes = spikes.len();
    let mut spikes_json = Vec::new();
    for sp in &spikes {
        let mut v = serde_json::to_value(sp)?;
        v["label"] = row_label(sp.marker).into();
        spikes_json.push(v);
    }
    for seg in report.segments.iter().filter(|x| in_scope(x.marker)) {
        if seg.filtered {
            s.segments_filtered += 1;
        } else {
            s.segments_too_short += 1;
        }
    }
    let wb = repair_io::write_back(c, &trial, &points, &report.changes, only.as_deref());
    s.samples_changed = wb.changed;
    s.samples_clamped = wb.clamped;
    s.markers_changed = (0..points.len())
        .filter(|&r| in_scope(r) && report.changes[r].iter().any(|&x| x != 0))
        .count();
    let bytes = c
        .to_bytes()
        .with_context(|| format!("writing the repaired {}", input.display()))?;
    let per_marker: Vec<_> = (0..points.len())
        .filter(|&r| in_scope(r))
        .map(|r| serde_json::json!({"label": row_label(r), "samples_changed": report.changed_per_marker[r]}))
        .collect();
    let full = serde_json::json!({
        "file": s.file,
        "output": s.output,
        "config": cfg,
        "summary": s,
        "gaps": gaps_json,
        "spikes": spikes_json,
        "spike_mode": report.spike_mode,
        "segments": report.segments.iter().filter(|x| in_scope(x.marker)).map(|x| {
            let mut v = serde_json::to_value(x).unwrap_or_default();
            v["label"] = row_label(x.marker).into();
            v
        }).collect::<Vec<_>>(),
        "markers": per_marker,
    });
    Ok(Repaired {
        bytes,
        report: full,
        summary: s,
    })
}

pub fn run(a: Args) -> Result<i32> {
    let out = repair_io::output_path(&a.input, &a.output, a.in_place)?;
    if a.backup && !a.in_place {
        anyhow::bail!("--backup goes with --in-place");
    }
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
    let mut outs = Vec::with_capacity(3);
    if let Some(b) = &backup {
        outs.push(Output {
            path: b,
            bytes: c.source_bytes().unwrap_or_default(),
            replace: false,
        });
    }
    outs.push(Output {
        path: &out,
        bytes: &r.bytes,
        replace: overwrite,
    });
    if let Some(path) = &a.report {
        outs.push(Output {
            path,
            bytes: report.as_bytes(),
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
